#!/usr/bin/env bash
# gdp stitch side by side with DMG (Kazhdan's Distributed Multigrid, the paper's own code) on the
# same held-out composite: wall, CPU, peak memory, scratch bytes and error. docs/vs-dmg.md.
#
#   bench/vs_dmg.sh [--dmg DIR] [--runs N (2)] [--build DIR (build)] [SIZE ...] (2048)
#
# DIR (or $DMG_SRC) is DMG's public source, a checkout or a bare git repository of
# https://github.com/mkazhdan/DMG; nothing of it enters this repository. It is built once, with
# its own Makefile and release flags (-O3 -ffast-math -msse2), into ${DMG_BUILD:-/tmp/gdp-vs-dmg/dmg}.
# Its build needs: g++ make libboost-thread-dev libboost-system-dev libboost-chrono-dev
# libpng-dev libtiff-dev libjpeg-dev zlib1g-dev (Debian 12). One local change, on the make command
# line only: LFLAGS adds -lboost_chrono (Boost 1.74's condition_variable::wait_for needs it; DMG's
# Makefile links only boost_thread and boost_system). No source file is patched.
#
# Per SIZE, bench/make_composite cuts a SIZE x SIZE composite and label map (PNG, 8-bit) from a real
# photo (../shared/data, named in one line when missing) and the photo without the exposure offsets
# (the held-out truth). Runs alternate gdp, DMG, DMG, gdp, gdp, DMG ... N times each (pair r is
# the two tools' run r, side by side; the order swaps every pair, so that a machine growing slower
# or faster during the runs does not always favour one tool):
#   gdp: gdp stitch --threads 2 (streaming, its defaults: 3 sweeps, 1 V-cycle, narrow scratch;
#        the tables in docs/vs-dmg.md before it became the default: GDP_ARGS="--scratch float")
#   DMG: ServerSocket --count 1 --verbose + ClientSocket --threads 2 on 127.0.0.1 (streaming, no --inCore;
#        its defaults: 5 Gauss-Seidel iterations, 1 V-cycle, half-float scratch, inCoreRes 1024)
# both writing a 16-bit uncompressed TIFF, scratch in the same directory. Costs come from
# bench/measure_run.py (/usr/bin/time -v; bytes written from /proc/PID/io): CPU = user+sys,
# DMG's wall from the server's start to the later exit, its CPU and peak RSS summed over both
# processes. scratch = bytes written by write() less the output file; disk = bytes the kernel sent
# towards the disk. Error: RMS in 8-bit levels against the truth, each channel's mean difference
# removed (the two solvers may differ in the constant). Extra flags: $GDP_ARGS, $DMG_SERVER_ARGS,
# $DMG_CLIENT_ARGS. VS_DMG_NICE=N runs both under `nice -n N` (negative, as root: a shared machine's
# other load then disturbs the wall figures less). GDP_BENCH_PAUSE=S sleeps S seconds before each
# tool's run (this VM takes freed pages back after ~3 s; docs/reproduce.md). Work files: ${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/SIZE (inputs kept, outputs removed
# once scored; the last pair is also compared with each other).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
me=$(basename "$0")
dmg_src=${DMG_SRC:-}
runs=2
build=build
sizes=()
while (($#)); do
  case $1 in
    --dmg) dmg_src=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --build) build=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) sizes+=("$1"); shift ;;
  esac
done
((${#sizes[@]})) || sizes=(2048)
if [[ -z $dmg_src || ! -e $dmg_src ]]; then
  echo "$me: DMG's source is needed: --dmg DIR or DMG_SRC=DIR (a checkout or bare clone of https://github.com/mkazhdan/DMG)${dmg_src:+; $dmg_src does not exist}" >&2
  exit 2
fi
for h in boost/thread.hpp boost/chrono.hpp png.h tiffio.h jpeglib.h zlib.h; do
  [[ -f /usr/include/$h || -f /usr/include/x86_64-linux-gnu/$h ]] || {
    echo "$me: building DMG needs /usr/include/$h: apt-get install libboost-thread-dev libboost-system-dev libboost-chrono-dev libpng-dev libtiff-dev libjpeg-dev zlib1g-dev" >&2
    exit 2
  }
done
for l in boost_thread boost_system boost_chrono; do  # the headers come with other Boost packages, the libraries not
  [[ -e /usr/lib/x86_64-linux-gnu/lib$l.so || -e /usr/lib/lib$l.so ]] || {
    echo "$me: building DMG needs lib$l.so: apt-get install libboost-thread-dev libboost-system-dev libboost-chrono-dev" >&2
    exit 2
  }
done
gdp="$here/$build/tools/gdp/gdp"
for exe in "$gdp" "$here/$build/bench/make_composite" "$here/$build/bench/blend_layers"; do
  [[ -x $exe ]] || { echo "$me: missing $exe (scripts/build.sh)" >&2; exit 2; }
done
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
measure=("$here/bench/measure_run.py")
[[ -z ${VS_DMG_NICE:-} ]] || measure=(nice -n "$VS_DMG_NICE" "${measure[@]}")

# DMG, built once outside the repository from the given source.
dmg=${DMG_BUILD:-/tmp/gdp-vs-dmg/dmg}
if [[ ! -x $dmg/Bin/Server || ! -x $dmg/Bin/Client ]]; then
  echo "building DMG from $dmg_src into $dmg (minutes)" >&2
  rm -rf "$dmg" && mkdir -p "$dmg"
  parts=(Makefile Util ServerSocket ClientSocket LaplacianMatrix LinearAlgebra FunctionBasis)
  if [[ -f $dmg_src/Makefile ]]; then
    (cd "$dmg_src" && cp -r "${parts[@]}" "$dmg/")
  else
    git --git-dir="$dmg_src" archive HEAD -- "${parts[@]}" 2> "$dmg/archive.log" | tar -x -C "$dmg"
  fi
  make -C "$dmg" -j"$(nproc)" Bin/Server Bin/Client \
    CFLAGS="-fpermissive -fopenmp -Wno-deprecated -msse2 --std=c++11 -Wno-unused-result -Wno-dangling-else -Wno-pointer-bool-conversion -O3 -DRELEASE -funroll-loops -ffast-math" \
    LFLAGS="-lgomp -lz -lpng -ltiff -ljpeg -lboost_thread -lboost_system -lboost_chrono -lpthread -O3" \
    > "$dmg/build.log" 2>&1 || { echo "$me: DMG did not build; see $dmg/build.log" >&2; exit 2; }
fi

wrappers=() scratch=""
stop_tree() {  # a measure_run started here, its `time` and the program under it, by id
  local t p
  for t in $(pgrep -P "$1" || true); do
    for p in $(pgrep -P "$t" || true); do kill "$p" 2> /dev/null || true; done
  done
  kill "$1" 2> /dev/null || true
}
cleanup() {  # should a run stop halfway (an error, Ctrl-C, TERM): the programs still running, scratch
  local w
  for w in "${wrappers[@]}"; do stop_tree "$w"; done
  [[ -z $scratch ]] || rm -rf "$scratch"
}
trap cleanup EXIT
trap 'exit 130' INT TERM

measured() {  # JSON, LOG, COMMAND...: in the background, so that a signal reaches the traps at once
  local json=$1 log=$2
  shift 2
  # (GDP_BENCH_PAUSE is slept once before each tool's run, below: DMG's server would count its
  # client's pause as its own wall.)
  GDP_BENCH_PAUSE= "${measure[@]}" "$json" -- "$@" > "$log" 2>&1 &
  wrappers+=($!)
}

finish() {  # LOG, WHAT: waits for the latest measured command
  local pid=${wrappers[-1]}
  wait "$pid" || { echo "$me: $2 failed; see $1" >&2; exit 1; }
  unset 'wrappers[-1]'
}

run_gdp() {  # dir, run
  local d=$1 r=$2
  sleep "${GDP_BENCH_PAUSE:-0}"
  measured "$d/gdp_$r.json" "$d/gdp_$r.log" "$gdp" stitch -c "$d/composite.png" -l "$d/labels.png" \
    -o "$d/out_gdp.tif" --depth 16 --compression none --threads 2 --temp "$d/scratch" \
    --stats "$d/gdp_stats_$r.json" -q ${GDP_ARGS:-}
  finish "$d/gdp_$r.log" gdp
}

run_dmg() {  # dir, run
  local d=$1 r=$2 port="" i
  sleep "${GDP_BENCH_PAUSE:-0}"
  measured "$d/dmg_server_$r.json" "$d/dmg_server_$r.log" "$dmg/Bin/Server" --count 1 --quality 0 --hdr --verbose \
    ${DMG_SERVER_ARGS:-}
  for ((i = 0; i < 300; ++i)); do
    port=$(sed -n 's/^Server Address: .*:\([0-9][0-9]*\)$/\1/p' "$d/dmg_server_$r.log" 2> /dev/null || true)
    [[ -n $port ]] && break
    kill -0 "${wrappers[-1]}" 2> /dev/null || break
    sleep 0.1
  done
  [[ -n $port ]] || { echo "$me: DMG's server gave no port; see $d/dmg_server_$r.log" >&2; exit 1; }
  measured "$d/dmg_client_$r.json" "$d/dmg_client_$r.log" "$dmg/Bin/Client" --pixels "$d/composite.png" \
    --labels "$d/labels.png" --out "$d/out_dmg.tif" --address 127.0.0.1 --port "$port" --threads 2 \
    --temp "$d/scratch" ${DMG_CLIENT_ARGS:-}
  finish "$d/dmg_client_$r.log" "DMG's client"
  finish "$d/dmg_server_$r.log" "DMG's server"
}

score() {  # dir, tool, run: output size and error against the truth
  local d=$1 tool=$2 r=$3
  stat -c %s "$d/out_$tool.tif" > "$d/${tool}_outbytes_$r"
  "$here/$build/bench/blend_layers" error "$d/out_$tool.tif" "$d/truth.tif" > "$d/${tool}_error_$r"
}

for size in "${sizes[@]}"; do
  d=${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/$size
  scratch=$d/scratch
  mkdir -p "$scratch"
  if [[ ! -f $d/truth.tif ]]; then
    echo "making the ${size}x$size composite, labels and truth in $d" >&2
    "$here/$build/bench/make_composite" "$photo" "$size" "$size" "$d/composite.png" "$d/labels.png" 1024 \
      "$d/truth.part.tif"
    mv "$d/truth.part.tif" "$d/truth.tif"
  fi
  rm -f "$d"/{gdp,dmg}_*
  for ((r = 1; r <= runs; ++r)); do  # gdp first in odd runs, DMG first in even ones
    if ((r % 2)); then
      run_gdp "$d" "$r" && score "$d" gdp "$r"
      run_dmg "$d" "$r" && score "$d" dmg "$r"
    else
      run_dmg "$d" "$r" && score "$d" dmg "$r"
      run_gdp "$d" "$r" && score "$d" gdp "$r"
    fi
  done
  "$here/$build/bench/blend_layers" error "$d/out_gdp.tif" "$d/out_dmg.tif" > "$d/gdp_vs_dmg_error"
  rm -f "$d/out_gdp.tif" "$d/out_dmg.tif"
  python3 "$here/bench/vs_dmg_table.py" "$d" "$size" "$runs"
done
