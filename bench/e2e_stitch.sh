#!/usr/bin/env bash
# End-to-end stitch time against the I/O floor (gdp convert), on a real photo crop.
# Usage: bench/e2e_stitch.sh [SIZE=2048] [BUILD=build]; needs oiiotool and python3.
set -euo pipefail
size=${1:-2048}
build=${2:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
gdp="$here/$build/tools/gdp/gdp"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
src="$here/../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg"
oiiotool "$src" --cut "${size}x${size}+1024+0" -o "$work/composite.png"
oiiotool --pattern checker:width=512:height=512:color1=0.2,0.2,0.2:color2=0.6,0.6,0.6 \
  "${size}x${size}" 3 -d uint8 -o "$work/labels.png"
"$gdp" convert "$work/composite.png" -o "$work/copy.tif" --stats "$work/convert.json" -q
for t in 1 2; do
  "$gdp" stitch -c "$work/composite.png" -l "$work/labels.png" -o "$work/out.tif" --threads $t \
    --stats "$work/stitch$t.json" -q
done
python3 - "$work" <<'PY'
import json, sys
w = sys.argv[1]
conv = json.load(open(f"{w}/convert.json"))
print(f"convert: {conv['seconds_total']:.2f} s  {conv['seconds']}")
for t in (1, 2):
    s = json.load(open(f"{w}/stitch{t}.json"))
    print(f"stitch --threads {t}: {s['seconds_total']:.2f} s = {s['seconds_total'] / conv['seconds_total']:.2f}x convert;"
          f" phases {s['seconds']}, peak {s['peak_rss_mb']} MB")
PY
