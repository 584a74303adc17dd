#!/usr/bin/env bash
# Installs gdp into a prefix inside the build tree, moves it, and checks the result: the layout,
# SONAME and RPATH, every installed program running, the installed gdp and a consumer loading the
# installed OpenImageIO module, and examples/consumer built with find_package(gdp) and pkg-config.
# Usage: install_test.sh BUILD_DIR SOURCE_DIR CXX_COMPILER GENERATOR [COMPILER_LAUNCHER]
set -euo pipefail
build=$1 source=$2 cxx=$3 generator=$4 launcher=${5:-}
work=$build/install-test
prefix=$work/prefix
unset LD_LIBRARY_PATH GDP_OIIO_MODULE
fail() { echo "install test: $*" >&2; exit 1; }

rm -rf "$work" && mkdir -p "$work"
cmake --install "$build" --prefix "$work/staged" > /dev/null
mv "$work/staged" "$prefix"  # nothing may depend on where it was installed

# Layout: the program, the library, every public header, the module, the CMake package, gdp.pc.
for f in bin/gdp lib/gdp/libgdp_oiio.so lib/cmake/gdp/gdpConfig.cmake lib/cmake/gdp/gdpConfigVersion.cmake \
         lib/cmake/gdp/gdpTargets.cmake lib/pkgconfig/gdp.pc; do
  [ -f "$prefix/$f" ] || fail "$f was not installed"
done
for h in "$source"/include/gdp/*.h; do
  [ -f "$prefix/include/gdp/$(basename "$h")" ] || fail "header $(basename "$h") was not installed"
done
pc_static=() consumer_env=()
if [ -f "$prefix/lib/libgdp.so" ]; then
  soname=$(readelf -d "$prefix/lib/libgdp.so" | sed -n 's/.*Library soname: \[\(.*\)\]/\1/p')
  [[ "$soname" == libgdp.so.* ]] || fail "libgdp.so has no versioned SONAME ('$soname')"
  [ -f "$prefix/lib/$soname" ] || fail "lib/$soname (the SONAME) was not installed"
  readelf -d "$prefix/bin/gdp" | grep -q 'R.*PATH.*\[\$ORIGIN/\.\./lib\]' || fail "bin/gdp lacks RPATH \$ORIGIN/../lib"
  loaded=$(ldd "$prefix/bin/gdp" | sed -n "s/.*$soname => \(.*\) (0x.*/\1/p")
  [ -n "$loaded" ] && [ "$(realpath "$loaded")" = "$(realpath "$prefix/lib/$soname")" ] ||
    fail "the installed gdp does not load the installed $soname (ldd: '$loaded')"
else
  [ -f "$prefix/lib/libgdp.a" ] || fail "neither lib/libgdp.so nor lib/libgdp.a was installed"
  pc_static=(--static)
  consumer_env=(GDP_OIIO_MODULE="$prefix/lib/gdp/libgdp_oiio.so")  # a static libgdp looks beside the program
fi
# What the package's target brings to a consumer's link: nothing for a shared libgdp (its dependencies
# are private, Threads included: no public header starts a thread), never Eigen (header-only, private).
links=$(sed -n 's/.*INTERFACE_LINK_LIBRARIES "\(.*\)"/\1/p' "$prefix"/lib/cmake/gdp/gdpTargets.cmake)
if [ ${#pc_static[@]} -eq 0 ]; then
  [ -z "$links" ] || fail "the CMake package of a shared libgdp brings link dependencies: $links"
fi
[[ "$links" != *Eigen3* ]] || fail "the CMake package brings Eigen3 (a private, header-only dependency)"
for program in "$prefix"/bin/*; do
  "$program" --help > /dev/null || fail "$(basename "$program") --help failed"
done

# The installed gdp loads the installed module (LD_DEBUG names every file dlopen()ed): a
# round trip through Targa, which only the module reads and writes, is lossless.
module=$prefix/lib/gdp/libgdp_oiio.so
labels=$source/examples/data/weir_labels.png
LD_DEBUG=files LD_DEBUG_OUTPUT="$work/gdp.ld" "$prefix/bin/gdp" convert "$labels" -o "$work/labels.tga"
grep -q "file=$module .*dynamically loaded" "$work"/gdp.ld.* || fail "the installed gdp did not load $module"
"$prefix/bin/gdp" convert "$work/labels.tga" -o "$work/labels_back.png"
"$prefix/bin/gdp" convert "$labels" -o "$work/labels_ref.png"
cmp -s "$work/labels_ref.png" "$work/labels_back.png" || fail "PNG -> Targa -> PNG changed the image"

# The example consumer, configured against the package with CMake, writes Radiance HDR (the module
# found beside the installed libgdp.so, not beside the program), which the installed gdp reads.
cmake -S "$source/examples/consumer" -B "$work/consumer" -G "$generator" -DCMAKE_BUILD_TYPE=Release \
  -DCMAKE_CXX_COMPILER="$cxx" -DCMAKE_CXX_COMPILER_LAUNCHER="$launcher" -DCMAKE_PREFIX_PATH="$prefix" > /dev/null
cmake --build "$work/consumer" > /dev/null
env "${consumer_env[@]}" LD_DEBUG=files LD_DEBUG_OUTPUT="$work/consumer.ld" "$work/consumer/gdp_consumer" "$work/stitched.hdr"
grep -q "file=$module .*dynamically loaded" "$work"/consumer.ld.* || fail "the consumer did not load $module"
"$prefix/bin/gdp" convert "$work/stitched.hdr" -o "$work/stitched.tif"

# The same consumer compiled with pkg-config's flags alone.
flags=$(PKG_CONFIG_PATH=$prefix/lib/pkgconfig pkg-config "${pc_static[@]}" --cflags --libs gdp)
# shellcheck disable=SC2086
$launcher "$cxx" -std=c++20 "$source/examples/consumer/main.cc" -o "$work/consumer_pc" $flags -Wl,-rpath,"$prefix/lib"
"$work/consumer_pc"
echo "install test: ok ($prefix)"
