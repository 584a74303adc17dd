#!/usr/bin/env bash
# Two gdp builds' blend, interleaved on the same layers (those of bench/blend_vs_enblend.sh): wall,
# CPU (user + sys), peak RSS and --stats phases per run, cmp of the outputs, then each build's
# critical-path estimate on 2 idle cores (bench/critical_path.py). docs/blend.md has the figures.
#
#   bench/blend_ab.sh OLD_DIR NEW_DIR [SIZE (8192)] [GRID (4x4)] [REPS (2)]
#
# Each DIR holds a copy of a build's gdp and libgdp (so a rebuild cannot change it mid-run):
#   mkdir -p DIR && cp build/tools/gdp/gdp build/lib/libgdp.so.0.1 DIR/
# Needs build/bench/blend_layers, perf, and the photo in ../shared/data (exit 2 when missing).
set -euo pipefail
cd "$(dirname "$0")/.."
old=$(realpath "$1") new=$(realpath "$2")
size=${3:-8192} grid=${4:-4x4} reps=${5:-2}
photo=../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg
[ -f "$photo" ] || { echo "missing $photo (../shared/data)" >&2; exit 2; }
dir=${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}/${size}_${grid}_v0.3
mkdir -p "$dir"
[ -f "$dir/original.tif" ] || build/bench/blend_layers cut "$photo" "$dir" --size "${size}x${size}" --grid "$grid" \
  --overlap 0.2 --offset 40 --vignette 0.3 --seed 7
layers=("$dir"/layer_*.tif)
for rep in $(seq "$reps"); do
  for side in old new; do
    d=${!side}
    load=$(cut -d' ' -f1 /proc/loadavg)
    /usr/bin/time -f "%e %U %S %M" -o "$dir/ab_time" nice -n 5 env LD_LIBRARY_PATH="$d" "$d/gdp" blend -q \
      --stats "$dir/ab_stats_$side.json" -o "$dir/ab_$side.tif" --temp "$dir" -- "${layers[@]}"
    read -r wall user sys kb < "$dir/ab_time"
    printf "%s rep %s (load %s): wall %s s  cpu %s s (user %s, sys %s)  peak %d MB  %s %s\n" "$side" "$rep" "$load" \
      "$wall" "$(echo "$user + $sys" | bc)" "$user" "$sys" $((kb / 1024)) \
      "$(grep -o '"seconds_seams": [0-9.]*' "$dir/ab_stats_$side.json")" \
      "$(grep -o '"seconds": {[^}]*}' "$dir/ab_stats_$side.json")"
  done
  cmp "$dir/ab_old.tif" "$dir/ab_new.tif" && echo "rep $rep: the outputs are identical (cmp)"
done
for side in old new; do
  echo "critical path, $side (load $(cut -d' ' -f1 /proc/loadavg)):"
  nice -n 5 bench/critical_path.py -- env LD_LIBRARY_PATH="${!side}" "${!side}/gdp" blend -q \
    -o "$dir/ab_$side.tif" --temp "$dir" -- "${layers[@]}"
done
rm -f "$dir"/ab_*.tif
