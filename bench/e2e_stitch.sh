#!/usr/bin/env bash
# End-to-end stitch time and memory against the I/O floor (gdp convert of the same files).
# Usage: bench/e2e_stitch.sh [SIZE=2048] [BUILD=build] [EXT=png]
# Makes a SIZE x SIZE composite + label map from a real photo (bench/make_composite: mirrored
# tiles, Voronoi regions with exposure offsets), then times `gdp convert` of each input to the
# output format and `gdp stitch` with 1 and 2 threads and with 2 bands (all in one run: compare
# the ratios). The floor is the two converts' walls added: decoding both inputs, encoding the
# composite (as large as the output, and as costly to deflate) and the labels (cheap: a few
# colours); the same binary runs both. CPU seconds (user + sys, from --stats) beside each wall.
# BUILD: a build folder (tools/gdp/gdp), or a folder holding copies of gdp and libgdp.so* (run
# with that folder as LD_LIBRARY_PATH; bench/make_composite then comes from ./build).
# E2E_INPUTS=DIR keeps the inputs in DIR (made there once, reused by later runs);
# E2E_STITCHES="2" runs only the `--threads 2` stitch (default "1 2 bands2"); E2E_PAUSE=S sleeps S
# seconds before each timed run (this VM takes freed pages back after ~3 s, which favours a run
# that follows another closely: docs/how-streaming-works.md); E2E_OUT=FILE keeps the last stitch's
# output there (to compare two builds' bytes).
set -euo pipefail
size=${1:-2048}
build=${2:-build}
ext=${3:-png}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup e2e "$build"
make_composite="$here/$build/bench/make_composite"
if [[ -x $build/gdp ]]; then  # a folder of copies
  gdp=$(realpath "$build/gdp")
  export LD_LIBRARY_PATH=$(dirname "$gdp")${LD_LIBRARY_PATH:+:$LD_LIBRARY_PATH}
  make_composite="$here/build/bench/make_composite"
fi
inputs=${E2E_INPUTS:-$work}
mkdir -p "$inputs"
if [[ ! -f $inputs/composite.$ext || ! -f $inputs/labels.$ext ]]; then
  "$make_composite" "$photo" "$size" "$size" "$inputs/composite.$ext" "$inputs/labels.$ext"
fi
pause=${E2E_PAUSE:-0}
sleep "$pause"
"$gdp" convert "$inputs/composite.$ext" -o "$work/copy.tif" --stats "$work/convert.json" -q
sleep "$pause"
"$gdp" convert "$inputs/labels.$ext" -o "$work/copy_labels.tif" --stats "$work/convert_labels.json" -q
stitches=${E2E_STITCHES:-1 2 bands2}
for t in $stitches; do
  case $t in
    bands2) flags=(--bands 2) ;;
    *) flags=(--threads "$t") ;;
  esac
  sleep "$pause"
  "$gdp" stitch -c "$inputs/composite.$ext" -l "$inputs/labels.$ext" -o "$work/out.tif" "${flags[@]}" \
    --stats "$work/stitch$t.json" -q
done
if [[ -n ${E2E_OUT:-} ]]; then cp "$work/out.tif" "$E2E_OUT"; fi
python3 - "$work" $stitches <<'PY'
import json, sys
w = sys.argv[1]
conv = json.load(open(f"{w}/convert.json"))
lab = json.load(open(f"{w}/convert_labels.json"))
floor = conv['seconds_total']
both = floor + lab['seconds_total']
print(f"convert composite: {floor:.2f} s ({conv['cpu_seconds']:.2f} CPU-s), peak {conv['peak_rss_mb']} MB;"
      f" convert labels: {lab['seconds_total']:.2f} s ({lab['cpu_seconds']:.2f} CPU-s)")
for t in sys.argv[2:]:
    name = "--bands 2" if t == "bands2" else f"--threads {t}"
    s = json.load(open(f"{w}/stitch{t}.json"))
    print(f"stitch {name}: {s['seconds_total']:.2f} s ({s['cpu_seconds']:.2f} CPU-s) = "
          f"{s['seconds_total'] / floor:.2f}x convert composite, {s['seconds_total'] / both:.2f}x both converts"
          f" (CPU {s['cpu_seconds'] / (conv['cpu_seconds'] + lab['cpu_seconds']):.2f}x); peak {s['peak_rss_mb']} MB,"
          f" solver {s['solver_memory_mb']} MB, scratch {s['scratch_mb']} MB, residuals {s['relative_residuals']}")
PY
