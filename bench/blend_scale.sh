#!/usr/bin/env bash
# gdp blend at scale: peak memory against the canvas height, and thousands of small tiles (time per
# tile, memory bounded). Wall and CPU seconds and peak RSS from /usr/bin/time -v. docs/blend.md has the figures.
#
#   bench/blend_scale.sh [height|tiles|all (height tiles)] [PHOTO]
#
#   height: a WIDTH-wide canvas (-f; WIDTH=8192 unless set) WIDTH and 4 x WIDTH rows tall, 4 layers
#           across (WIDTH x 5/16 pixels, 25 % overlap)
#   tiles:  TILE x TILE tiles (TILE=512 unless set), 10 % overlap, 25 across and 10, 20, 40, 80 down
#           (250 ... 2000 tiles), given as a --layers list as a microscope's stage positions would
#           be (no canvas tags: each subset is a canvas of its own); least-squares slope
#   (a canvas past 2^31 pixels to BigTIFF: bench/blend_huge.sh)
# Layers are cut from PHOTO (default: NASA's Blue Marble in ../shared/data) repeated mirrored at its
# own resolution, each with an exposure offset (up to +-20/255) and a 10 % falloff to its corners.
# Needs build/ (scripts/build.sh), or GDP_BIN=DIR holding copies of gdp and blend_layers (so a rebuild
# cannot replace them mid-run). Work files: ${GDP_BENCH_DIR:-/tmp/gdp-blend-scale} (removed as it goes).
set -euo pipefail
cd "$(dirname "$0")/.."
what=${1:-all}
photo=${2:-../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg}
if [ ! -f "$photo" ]; then
  echo "blend_scale: $photo is missing (../shared is not part of the repository); give a photo" >&2
  exit 2
fi
dir=${GDP_BENCH_DIR:-/tmp/gdp-blend-scale}
mkdir -p "$dir"
gdp=${GDP_BIN:+$GDP_BIN/gdp}
gdp=${gdp:-build/tools/gdp/gdp}
cutter=${GDP_BIN:+$GDP_BIN/blend_layers}
cutter=${cutter:-build/bench/blend_layers}

# run NAME LIST [gdp blend options...]: one blend, one line of figures (also appended to $dir/results).
run() {
  local name=$1 list=$2
  shift 2
  /usr/bin/time -v -o "$dir/time_$name" "$gdp" blend -q --temp "$dir" --layers "$list" -o "$dir/out_$name.tif" "$@"
  local wall user sys kb
  wall=$(awk -F': ' '/Elapsed/ {n = split($2, t, ":"); s = 0; for (i = 1; i <= n; ++i) s = s * 60 + t[i]; print s}' "$dir/time_$name")
  user=$(awk -F': ' '/User time/ {print $2}' "$dir/time_$name")
  sys=$(awk -F': ' '/System time/ {print $2}' "$dir/time_$name")
  kb=$(awk -F': ' '/Maximum resident/ {print $2}' "$dir/time_$name")
  printf "%-12s %6d layers  wall %8.1f s  cpu %8.1f s  peak %6.0f MB\n" "$name" "$(grep -c . "$list")" "$wall" \
    "$(echo "$user + $sys" | bc)" "$(echo "$kb / 1024" | bc)" | tee -a "$dir/results"
  rm -f "$dir/out_$name.tif"
}

height() {
  local d=$dir/height
  mkdir -p "$d"
  local w=${WIDTH:-8192}
  [ -f "$d/tiles.txt" ] || "$cutter" tiles "$photo" "$d" --tile $((w * 5 / 16)) --grid 4x17 --overlap 0.25 --offset 20 --vignette 0.1 --seed 3
  head -n 20 "$d/tiles.txt" > "$d/short.txt"  # the rows of layers that reach into the first WIDTH rows
  run "h$w" "$d/short.txt" -f "${w}x${w}"
  run "h$((4 * w))" "$d/tiles.txt" -f "${w}x$((4 * w))"
  rm -rf "$d"
}

tiles() {
  local d=$dir/tiles
  mkdir -p "$d"
  [ -f "$d/tiles.txt" ] || "$cutter" tiles "$photo" "$d" --tile "${TILE:-512}" --grid 25x80 --overlap 0.1 --offset 20 --vignette 0.1 --seed 5
  : > "$dir/fit"
  for n in 250 500 1000 2000; do
    head -n "$n" "$d/tiles.txt" > "$d/first_$n.txt"
    run "tiles$n" "$d/first_$n.txt"
    tail -n 1 "$dir/results" | awk -v n="$n" '{print n, $5, $8, $11}' >> "$dir/fit"
  done
  # Least squares of wall and CPU seconds against the tile count: slope, intercept, r^2.
  awk '{n++; x += $1; xx += $1 * $1; for (k = 2; k <= 3; ++k) {y[k] += $k; xy[k] += $1 * $k; yy[k] += $k * $k}}
       END {split("- wall cpu", name, " ");
            for (k = 2; k <= 3; ++k) {b = (n * xy[k] - x * y[k]) / (n * xx - x * x); a = (y[k] - b * x) / n;
              r = (n * xy[k] - x * y[k]) / sqrt((n * xx - x * x) * (n * yy[k] - y[k] * y[k]));
              printf "%s: %.4f s per tile + %.1f s, r^2 %.4f\n", name[k], b, a, r * r}}' "$dir/fit" | tee -a "$dir/results"
  rm -rf "$d"
}

case $what in
  height) height ;;
  tiles) tiles ;;
  all) height; tiles ;;
  *) echo "usage: bench/blend_scale.sh [height|tiles|all] [PHOTO]" >&2; exit 2 ;;
esac
