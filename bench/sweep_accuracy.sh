#!/usr/bin/env bash
# One-V-cycle stitch error and CPU against the sweep count k (--iters): docs/multigrid.md, "The smoother's sweep count".
#
#   bench/sweep_accuracy.sh [--build DIR (build)] [--rounds N (1)] SIZE [K ...] (K: 1 2 3 4 5; or PRE/POST, e.g. 2/3)
#
# Inputs: the held-out composite of bench/vs_dmg.sh, ${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/SIZE/{composite.png,
# labels.png,truth.tif} (made here with bench/make_composite from ../shared/data when missing, as vs_dmg.sh
# does). The reference is the converged solve `gdp stitch --double --vcycles 8 --depth float`, made once and
# kept in ${SWEEP_DIR:-/tmp/gdp-sweeps}/SIZE/reference.tif (805 MB at 8192²). Per round, per K (interleaved):
# `gdp stitch -k K --threads 2 --depth float --compression none` (streaming, one V-cycle, the other
# defaults), its CPU (user+sys, bench/measure_run.py) and wall, the relative residual before and after the
# V-cycle (--stats with --residuals: two residual sweeps more, about 4 % of the CPU), and the RMS error in 8-bit levels, each channel's mean difference removed
# (`blend_layers error`, as vs_dmg.sh scores), against the held-out photo and against the reference.
# Extra gdp flags: $GDP_ARGS. Outputs are deleted once scored.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
me=$(basename "$0")
build=build rounds=1 size="" ks=()
while (($#)); do
  case $1 in
    --build) build=$2; shift 2 ;;
    --rounds) rounds=$2; shift 2 ;;
    -h|--help) sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//'; exit 0 ;;
    *) if [[ -z $size ]]; then size=$1; else ks+=("$1"); fi; shift ;;
  esac
done
[[ -n $size ]] || { echo "$me: SIZE is needed (e.g. 2048 or 8192)" >&2; exit 2; }
((${#ks[@]})) || ks=(1 2 3 4 5)
gdp="$here/$build/tools/gdp/gdp"
for exe in "$gdp" "$here/$build/bench/make_composite" "$here/$build/bench/blend_layers"; do
  [[ -x $exe ]] || { echo "$me: missing $exe (scripts/build.sh)" >&2; exit 2; }
done
in=${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/$size
d=${SWEEP_DIR:-/tmp/gdp-sweeps}/$size
mkdir -p "$in" "$d"
trap 'rm -f "$d"/out_*.tif "$d"/reference.part.tif' EXIT
trap 'exit 130' INT TERM
if [[ ! -f $in/truth.tif ]]; then
  source "$here/bench/shared_data.sh"
  photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
  "$here/$build/bench/make_composite" "$photo" "$size" "$size" "$in/composite.png" "$in/labels.png" 1024 \
    "$in/truth.part.tif"
  mv "$in/truth.part.tif" "$in/truth.tif"
fi
stitch=("$gdp" stitch -c "$in/composite.png" -l "$in/labels.png" --compression none --threads 2 -q)
if [[ ! -f $d/reference.tif ]]; then
  echo "$me: converged reference (--double --vcycles 8) into $d/reference.tif" >&2
  "${stitch[@]}" -o "$d/reference.part.tif" --depth float --double --vcycles 8
  mv "$d/reference.part.tif" "$d/reference.tif"
fi
field() { python3 -c 'import json,sys; print(eval(sys.argv[2], {}, json.load(open(sys.argv[1]))))' "$@"; }
level() { awk '/^rms_error/ { printf "%.4f", 255 * $2 }' "$1"; }  # 8-bit levels, from the 6-decimal fraction
printf '%-5s %-4s %8s %8s %11s %11s %9s %9s\n' round k CPU-s wall r_before r_after vs_photo vs_ref
for ((r = 1; r <= rounds; ++r)); do
  for k in "${ks[@]}"; do
    t=${k//\//-}  # PRE/POST: PRE-POST in file names
    out=$d/out_$t.tif
    "$here/bench/measure_run.py" "$d/run_$t.json" -- "${stitch[@]}" -o "$out" --depth float -k "$k" \
      --stats "$d/stats_$t.json" --residuals ${GDP_ARGS:-}
    "$here/$build/bench/blend_layers" error "$out" "$in/truth.tif" > "$d/photo_$t"
    "$here/$build/bench/blend_layers" error "$out" "$d/reference.tif" > "$d/ref_$t"
    rm -f "$out"
    printf '%-5s %-4s %8.2f %8.2f %11.4e %11.4e %9s %9s\n' "$r" "$k" "$(field "$d/run_$t.json" 'user+sys')" \
      "$(field "$d/run_$t.json" wall)" "$(field "$d/stats_$t.json" 'relative_residuals[0]')" \
      "$(field "$d/stats_$t.json" 'relative_residuals[-1]')" "$(level "$d/photo_$t")" "$(level "$d/ref_$t")"
  done
done
