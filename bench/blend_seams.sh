#!/usr/bin/env bash
# gdp blend's seams side by side: depth (distance transform) and graph cut, on nona-style layers cut
# from a real photo with exposure offsets and moving objects (ghosts) in the overlaps: wall and CPU
# seconds, peak memory, seam cost and colour error against the unaltered photo. docs/blend.md has the figures.
#
#   bench/blend_seams.sh [SIZE (2048)] [GRID (4x4)] [GHOSTS per layer (2)] [PHOTO] [VIGNETTE (0)]
#
# Needs build/ (scripts/build.sh). Work files go to ${GDP_BENCH_DIR:-/tmp/gdp-seams-bench}; the photo
# (default: the shared data's Blue Marble; say so plainly when it is missing) is resampled to SIZE x SIZE.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-2048}
grid=${2:-4x4}
ghosts=${3:-2}
photo=${4:-../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg}
vignette=${5:-0}
if [ ! -f "$photo" ]; then
  echo "blend_seams: the photo $photo is missing (the shared data is not here); give another as the 4th argument" >&2
  exit 1
fi
dir=${GDP_BENCH_DIR:-/tmp/gdp-seams-bench}/${size}_${grid}_${ghosts}_${vignette}
mkdir -p "$dir"
if [ ! -f "$dir/original.tif" ]; then
  build/bench/blend_layers cut "$photo" "$dir" --size "${size}x${size}" --grid "$grid" --overlap 0.2 \
    --offset 40 --vignette "$vignette" --ghosts "$ghosts" --seed 7
fi
layers=("$dir"/layer_*.tif)
echo "canvas ${size}x${size}, ${#layers[@]} layers ($grid, overlap 0.2, $ghosts ghosts each, vignette $vignette)"
for seams in depth graphcut; do
  /usr/bin/time -f "%e %U %S %M" -o "$dir/time_$seams" build/tools/gdp/gdp blend --seams "$seams" \
    --stats "$dir/stats_$seams.json" -o "$dir/out_$seams.tif" --temp "$dir" -- "${layers[@]}" > /dev/null 2> "$dir/log_$seams"
  read -r wall user sys kb < "$dir/time_$seams"
  err=$(build/bench/blend_layers error "$dir/out_$seams.tif" "$dir/original.tif")
  stats=$(python3 -c "import json,sys; s=json.load(open(sys.argv[1])); print('seams %.1f s, seam cost %s (depth seams %s)' % (float(s['seconds_seams']), s.get('seam_cost', '-'), s.get('seam_cost_depth', '-')))" "$dir/stats_$seams.json")
  printf "%-9s wall %6.1f s  cpu %6.1f s  peak %5.0f MB  %s; %s\n" "$seams" "$wall" "$(echo "$user + $sys" | bc)" \
    "$(echo "$kb / 1024" | bc)" "$stats" "$err"
done
