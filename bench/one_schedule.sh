#!/usr/bin/env bash
# One schedule (issue 17): CPU seconds and wall of one stitch as the default, --bands 1, --bands 2,
# mpirun -np 2 without --bands (one band per rank), mpirun -np 1 (one rank against the plain process)
# and --in-core, interleaved, in one run.
# Usage: bench/one_schedule.sh [SIZE=4096] [ROUNDS=2] [BUILD=build] [RUNS="default bands1 bands2 mpi2 mpi1 incore"]
# Makes a SIZE x SIZE composite + label map (uncompressed TIFF, so decoding is cheap) from a real
# photo with bench/make_composite, then runs the six commands ROUNDS times in turn under
# bench/measure_run.py (user + sys of the command and its children, mpirun's ranks included) and
# prints each run and the median of each command against the default's. The default and --bands 1
# are the same plan, and --in-core the reference (the outputs are compared byte for byte); RUNS picks
# some of the commands (the default is always run: the ratios are against it). mpirun gets --bind-to none
# (GDP_MPIRUN_ARGS to change): by default Open MPI binds each of 2 ranks to one core, which
# confines a rank's worker and its reading and writing threads to it. GDP_BENCH_PAUSE=S sleeps S
# seconds before each timed run (bench/measure_run.py; this VM takes freed pages back after ~3 s).
set -euo pipefail
size=${1:-4096}
rounds=${2:-2}
build=${3:-build}
runs=" default ${4:-bands1 bands2 mpi2 mpi1 incore} "
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup one-schedule "$build"
"$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/composite.tif" "$work/labels.tif"
stitch=(stitch -c "$work/composite.tif" -l "$work/labels.tif" --compression none -q)
mpi=(mpirun --oversubscribe --allow-run-as-root ${GDP_MPIRUN_ARGS:---bind-to none})
measure() {
  [[ $runs == *" $1 "* ]] && python3 "$here/bench/measure_run.py" "$work/$1-$2.json" -- "${@:3}" > /dev/null || true
}
for r in $(seq 1 "$rounds"); do
  measure default "$r" "$gdp" "${stitch[@]}" -o "$work/default.tif"
  measure bands1 "$r" "$gdp" "${stitch[@]}" -o "$work/bands1.tif" --bands 1
  measure bands2 "$r" "$gdp" "${stitch[@]}" -o "$work/bands2.tif" --bands 2
  measure mpi2 "$r" "${mpi[@]}" -np 2 "$gdp" "${stitch[@]}" -o "$work/mpi2.tif"
  measure mpi1 "$r" "${mpi[@]}" -np 1 "$gdp" "${stitch[@]}" -o "$work/mpi1.tif"
  measure incore "$r" "$gdp" "${stitch[@]}" -o "$work/incore.tif" --in-core
done
for n in bands1 mpi1 incore; do
  [[ -f $work/$n.tif ]] || continue
  cmp -s "$work/default.tif" "$work/$n.tif" && echo "$n output == default output (cmp)" ||
    echo "$n output DIFFERS from the default"
done
python3 - "$work" "$size" "$rounds" "$runs" <<'PY'
import json, statistics, sys
work, size, rounds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
names = {"default": "default", "bands1": "--bands 1", "bands2": "--bands 2", "mpi2": "mpirun -np 2",
         "mpi1": "mpirun -np 1", "incore": "--in-core"}
names = {n: label for n, label in names.items() if n in sys.argv[4].split()}
runs = {n: [json.load(open(f"{work}/{n}-{r}.json")) for r in range(1, rounds + 1)] for n in names}
med = {}
for n, label in names.items():
    cpu = [x["user"] + x["sys"] for x in runs[n]]
    wall = [x["wall"] for x in runs[n]]
    med[n] = (statistics.median(cpu), statistics.median(wall))
    print(f"{label:14s} CPU " + ", ".join(f"{c:.2f}" for c in cpu) + " s; wall " +
          ", ".join(f"{w:.2f}" for w in wall) + " s; peak " +
          ", ".join(f"{x['peak_rss_kb'] // 1024}" for x in runs[n]) + " MB; minor faults/Mpix " +
          ", ".join(f"{x['minor_faults'] / (size * size / 1e6):.0f}" for x in runs[n]))
print(f"{size}x{size} stitch, medians of {rounds} against the default (one band):")
for n, label in names.items():
    print(f"  {label:14s} CPU {med[n][0]:.2f} s ({med[n][0] / med['default'][0]:.2f}x), "
          f"wall {med[n][1]:.2f} s ({med[n][1] / med['default'][1]:.2f}x)")
PY
