#!/usr/bin/env bash
# Packs gdp, the bench tools a device run needs, their shared libraries and the photo into one folder that runs on another x86-64 Linux.
# Usage: bench/device/pack.sh [BUILD=build] [PACK=.device-pack]
# PACK/bin: gdp, make_composite (input generator) and image_diff (output comparison); the
# scripts stay in the working tree, which travels anyway. PACK/lib: every shared library they load
# (ldd) except the C library's family (libc, libm, libpthread, libdl, librt, libresolv, ld-linux),
# which the other machine has and which must match its loader; PACK/data: the blue-marble photo
# the composites are cut from (../shared/data; the script names it and exits 2 when missing) and
# its licence. Run the binaries with LD_LIBRARY_PATH=PACK/lib. The newest glibc symbol version
# they need goes to PACK/GLIBC; for a machine with an older glibc, PACK/glibc holds this one's
# (loader included), used only as `PACK/glibc/ld-linux-x86-64.so.2 --library-path
# PACK/lib:PACK/glibc PROGRAM` (bench/device/scaling.sh does so when the machine's is older).
# Fails when the pack exceeds 50 MiB (the device copies at most 64 MiB with the working tree).
set -euo pipefail
here=$(cd "$(dirname "$0")/../.." && pwd)
build=$(cd "${1:-$here/build}" && pwd)
pack=${2:-$here/.device-pack}
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
bins=("$build/tools/gdp/gdp" "$build/bench/make_composite" "$build/bench/image_diff")
for b in "${bins[@]}"; do
  [[ -x $b ]] || { echo "pack.sh: missing $b (build it: cmake --build $build --target gdp_cli make_composite image_diff)" >&2; exit 2; }
done
if [[ -e $pack && ! -f $pack/GLIBC ]]; then
  echo "pack.sh: $pack exists and is not a pack (no $pack/GLIBC); give a new folder" >&2
  exit 2
fi
rm -rf "$pack"
mkdir -p "$pack/bin" "$pack/lib" "$pack/glibc" "$pack/data"
cp "${bins[@]}" "$pack/bin/"
cp "$photo" "$(dirname "$photo")/LICENSE" "$pack/data/"
glibc='^(libc|libm|libmvec|libpthread|libdl|librt|libresolv|libutil|ld-linux[-a-z0-9_]*)\.so'
for b in "${bins[@]}"; do
  if ldd "$b" | grep -q 'not found'; then
    echo "pack.sh: $b has unresolved libraries:" >&2; ldd "$b" | grep 'not found' >&2; exit 2
  fi
  ldd "$b" | awk '$2 == "=>" && $3 ~ /^\// {print $1, $3} $1 ~ /^\/.*ld-linux/ {print "ld-linux-x86-64.so.2", $1}' |
    while read -r name path; do
      if [[ $name =~ $glibc ]]; then cp -L "$path" "$pack/glibc/$name"; else cp -L "$path" "$pack/lib/$name"; fi
    done
done
objdump -T "$pack"/bin/{gdp,make_composite,image_diff} "$pack"/lib/* 2>/dev/null \
  | grep -o 'GLIBC_[0-9.]*' | sort -uV | tail -1 > "$pack/GLIBC"
size=$(du -sb "$pack" | cut -f1)
echo "pack.sh: $pack: $(ls "$pack/bin" | wc -l) programs, $(ls "$pack/lib" | wc -l) libraries, $((size / 1048576)) MiB, needs glibc >= $(sed 's/GLIBC_//' "$pack/GLIBC")"
if ((size > 50 * 1048576)); then
  echo "pack.sh: $pack is $((size / 1048576)) MiB, over the 50 MiB a device run can carry" >&2
  exit 1
fi
