#!/usr/bin/env bash
# gdp blend's error and CPU against the sweep count (--iters PRE/POST), 8-bit and 16-bit output: docs/blend.md, "The solver's sweeps".
#
#   bench/blend_sweeps.sh [--build DIR (build)] [--rounds N (1)] SIZE [GRID (4x4)] [-- K ...] (K: 3/3 2/3 2/2 1/2 1/1, or "default")
#
# Layers: bench/blend_vs_enblend.sh's (blend_layers cut of the blue-marble photo, overlap 0.2, offsets
# up to +-40/255, vignetting 0.3, seed 7), made once into ${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}.
# Reference: the converged solve of the same blend, `gdp blend --double --vcycles 8 --depth float`,
# made once per size and kept there (reference.tif, 16 bytes a pixel). Per round, per K (interleaved),
# per output (the layers' 8-bit, then --depth 16): `gdp blend -k K` as the bench runs it (its other
# defaults, --temp in the work folder), its wall and CPU seconds (user+sys), `blend_layers compare`
# against the reference (RMS, largest and mean difference in 8-bit levels; the fraction of samples
# whose 8-bit value differs from the reference's rounded one) and `blend_layers error` against the
# original photo (RMS in 8-bit levels, each channel's mean removed, as blend_vs_enblend.sh scores).
# K "default" runs without -k (the build's own default for that output). Extra gdp flags: $GDP_ARGS.
# Outputs are deleted once scored.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
me=$(basename "$0")
build=build rounds=1 size="" grid=4x4 ks=()
while (($#)); do
  case $1 in
    --build) build=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    --) shift; ks=("$@"); break ;;
    *) if [[ -z $size ]]; then size=$1; else grid=$1; fi; shift ;;
  esac
done
[[ -n $size ]] || { echo "$me: SIZE is needed (e.g. 2048, 4096 or 8192)" >&2; exit 2; }
((${#ks[@]})) || ks=(3/3 2/3 2/2 1/2 1/1)
gdp="$here/$build/tools/gdp/gdp" layers_tool="$here/$build/bench/blend_layers"
for exe in "$gdp" "$layers_tool"; do
  [[ -x $exe ]] || { echo "$me: $exe is missing (scripts/build.sh)" >&2; exit 2; }
done
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
dir=${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}/${size}_${grid}_v0.3
mkdir -p "$dir"
if [[ ! -f $dir/original.tif ]]; then
  "$layers_tool" cut "$photo" "$dir" --size "${size}x${size}" --grid "$grid" --overlap 0.2 --offset 40 --vignette 0.3 \
    --seed 7 > /dev/null
fi
layers=("$dir"/layer_*.tif)
extra=(${GDP_ARGS:-})
if [[ ! -f $dir/reference.tif ]]; then
  "$gdp" blend -q -k 3 --double --vcycles 8 --depth float --compression none --temp "$dir" -o "$dir/reference.tif" \
    "${extra[@]}" -- "${layers[@]}"
fi
echo "load average at the start: $(cut -d' ' -f1-3 /proc/loadavg) on $(nproc) cores; canvas ${size}x${size}, ${#layers[@]} layers"
echo "reference vs photo: $("$layers_tool" error "$dir/reference.tif" "$dir/original.tif")"
printf "%-8s %-6s %7s %7s  %s | %s\n" K output wall_s cpu_s "vs reference (8-bit levels)" "vs photo"
for ((r = 1; r <= rounds; ++r)); do
  for k in "${ks[@]}"; do
    for depth in layers 16; do
      out="$dir/sweeps_out.tif"
      args=(blend -q --temp "$dir" -o "$out" --stats "$dir/sweeps_stats.json")
      [[ $k == default ]] || args+=(-k "$k")
      [[ $depth == layers ]] || args+=(--depth "$depth")
      /usr/bin/time -f "%e %U %S" -o "$dir/sweeps_time" "$gdp" "${args[@]}" "${extra[@]}" -- "${layers[@]}"
      read -r wall user sys < "$dir/sweeps_time"
      cmp=$("$layers_tool" compare "$out" "$dir/reference.tif")
      err=$("$layers_tool" error "$out" "$dir/original.tif" | sed 's/.*x255: \([0-9.]*\).*/\1/')
      sweeps=$(grep -o '"sweeps": "[^"]*"' "$dir/sweeps_stats.json" | cut -d'"' -f4 || true)
      printf "%-8s %-6s %7.2f %7.2f  %s | %s%s\n" "$k" "$([[ $depth == layers ]] && echo 8 || echo 16)" "$wall" \
        "$(echo "$user + $sys" | bc)" "$cmp" "$err" "${sweeps:+ (ran $sweeps)}"
      rm -f "$out"
    done
  done
done
echo "load average at the end: $(cut -d' ' -f1-3 /proc/loadavg)"
