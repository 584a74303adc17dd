#!/usr/bin/env bash
# gdp blend side by side with enblend (Debian's) on nona-style layers cut from a real photo, each
# with its own exposure offset (up to +-40/255) and vignetting: colour error against the unaltered
# photo (mean removed), wall and CPU seconds, peak memory. docs/blend.md has the figures.
#
#   bench/blend_vs_enblend.sh [SIZE (8192)] [GRID (4x4)] [PHOTO] [OVERLAP (0.2)]
#
# VIGNETTE=V sets the layers' vignetting (0.3 unless set: a 30 % falloff at their corners);
# GRAPHCUT=1 adds a run with --seams graphcut; ZERO=0 leaves out the --seam-guidance zero run;
# MEMORY=0 leaves out the run with the solver's scratch in memory up to a quarter of physical memory
# (gdp blend's default is files, --memory 0: the page cache holds them and the peak is the blend's
# own; other commands keep a quarter in memory); ENBLEND=0 leaves out enblend (gdp's runs only, no ratios); PHOTOMETRIC=0 leaves out the run with --photometric (layers calibrated on their overlaps first). Ratios to enblend's figures close the output.
# Needs build/ (scripts/build.sh) and enblend (apt-get install enblend). Work files go to
# ${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}; the photo is resampled to SIZE x SIZE.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-8192}
grid=${2:-4x4}
photo=${3:-../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg}
overlap=${4:-0.2}
vignette=${VIGNETTE:-0.3}
gdp=${GDP_BIN:-build/tools/gdp/gdp}  # GDP_BIN: a copy, so that a rebuild cannot replace it mid-run
dir=${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}/${size}_${grid}_v${vignette}
mkdir -p "$dir"
if [ ! -f "$dir/original.tif" ]; then
  build/bench/blend_layers cut "$photo" "$dir" --size "${size}x${size}" --grid "$grid" --overlap "$overlap" \
    --offset 40 --vignette "$vignette" --seed 7
fi
layers=("$dir"/layer_*.tif)
echo "load average at the start: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores"
echo "canvas ${size}x${size}, ${#layers[@]} layers ($grid, overlap $overlap, vignetting $vignette), photo $(basename "$photo")"
run() {  # name, command...
  local name=$1
  shift
  /usr/bin/time -f "%e %U %S %M" -o "$dir/time_$name" "$@" > /dev/null 2> "$dir/log_$name"
  read -r wall user sys kb < "$dir/time_$name"
  local err
  err=$(build/bench/blend_layers error "$dir/out_$name.tif" "$dir/original.tif")
  printf "%-14s wall %7.1f s  cpu %7.1f s  peak %7.0f MB  %s\n" "$name" "$wall" "$(echo "$user + $sys" | bc)" \
    "$(echo "$kb / 1024" | bc)" "$err" | tee -a "$dir/results"
}
: > "$dir/results"
run gdp "$gdp" blend -o "$dir/out_gdp.tif" --temp "$dir" -- "${layers[@]}"
if [ "${PHOTOMETRIC:-1}" = 1 ]; then
  run gdp-photometric "$gdp" blend --photometric -o "$dir/out_gdp-photometric.tif" --temp "$dir" -- "${layers[@]}"
  grep -h "photometric calibration" "$dir/log_gdp-photometric" || true
fi
if [ "${MEMORY:-1}" = 1 ]; then  # scratch rows in memory, up to a quarter of physical memory
  run gdp-inmemory "$gdp" blend --memory "$(awk '/MemTotal/ {printf "%dK", $2 / 4}' /proc/meminfo)" \
    -o "$dir/out_gdp-inmemory.tif" --temp "$dir" -- "${layers[@]}"
fi
if [ "${ZERO:-1}" = 1 ]; then
  run gdp-zero "$gdp" blend --seam-guidance zero -o "$dir/out_gdp-zero.tif" --temp "$dir" -- "${layers[@]}"
fi
if [ "${GRAPHCUT:-0}" = 1 ]; then
  run gdp-graphcut "$gdp" blend --seams graphcut -o "$dir/out_gdp-graphcut.tif" --temp "$dir" -- "${layers[@]}"
fi
[ "${ENBLEND:-1}" = 1 ] || exit 0
run enblend enblend -o "$dir/out_enblend.tif" -- "${layers[@]}"
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
# Each run's wall, CPU, memory and error over enblend's (the error: the first number blend_layers prints).
awk '{v[NR] = $0; name[NR] = $1; wall[NR] = $3; cpu[NR] = $6; mb[NR] = $9; err[NR] = $12}
     END {for (i = 1; i < NR; ++i)
            printf "%-14s / enblend: wall %.3f  cpu %.3f  memory %.3f  error %.3f\n", name[i], wall[i] / wall[NR],
                   cpu[i] / cpu[NR], mb[i] / mb[NR], err[i] / err[NR]}' "$dir/results"
