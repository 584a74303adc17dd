#!/usr/bin/env bash
# End-to-end stitch time and memory against the I/O floor (gdp convert of the same files).
# Usage: bench/e2e_stitch.sh [SIZE=2048] [BUILD=build] [EXT=png]
# Makes a SIZE x SIZE composite + label map from a real photo (bench/make_composite: mirrored
# tiles, Voronoi regions with exposure offsets), then times `gdp convert` of each input to the
# output format and `gdp stitch` with 1 and 2 threads and with 2 bands (all in one run: compare
# the ratios).
set -euo pipefail
size=${1:-2048}
build=${2:-build}
ext=${3:-png}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup e2e "$build"
"$here/$build/bench/make_composite" "$photo" \
  "$size" "$size" "$work/composite.$ext" "$work/labels.$ext"
"$gdp" convert "$work/composite.$ext" -o "$work/copy.tif" --stats "$work/convert.json" -q
"$gdp" convert "$work/labels.$ext" -o "$work/copy_labels.tif" --stats "$work/convert_labels.json" -q
for t in 1 2; do
  "$gdp" stitch -c "$work/composite.$ext" -l "$work/labels.$ext" -o "$work/out.tif" --threads $t \
    --stats "$work/stitch$t.json" -q
done
"$gdp" stitch -c "$work/composite.$ext" -l "$work/labels.$ext" -o "$work/out.tif" --bands 2 \
  --stats "$work/stitch_bands2.json" -q
python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
conv = json.load(open(f"{w}/convert.json"))
lab = json.load(open(f"{w}/convert_labels.json"))
floor = conv['seconds_total']
print(f"convert composite: {floor:.2f} s, peak {conv['peak_rss_mb']} MB; convert labels: {lab['seconds_total']:.2f} s")
for t, name in ((1, "--threads 1"), (2, "--threads 2"), ("_bands2", "--bands 2")):
    s = json.load(open(f"{w}/stitch{t}.json"))
    print(f"stitch {name}: {s['seconds_total']:.2f} s = {s['seconds_total'] / floor:.2f}x convert composite,"
          f" {s['seconds_total'] / (floor + lab['seconds_total']):.2f}x both converts; peak {s['peak_rss_mb']} MB,"
          f" solver {s['solver_memory_mb']} MB, scratch {s['scratch_mb']} MB, residuals {s['relative_residuals']}")
PY
