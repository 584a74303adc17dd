#!/usr/bin/env bash
# mpirun's CPU against the plain process, two builds interleaved (issue 17): the SIZE x SIZE stitch of
# bench/one_schedule.sh as the plain one-band process and under mpirun -np 2 (and -np 1), for a base
# folder and a new one (each holding gdp and libgdp.so*, as bench/same_bits.sh takes them).
#
#   bench/mpi_ab.sh SIZE ROUNDS BASE_DIR NEW_DIR [RUNS="plain_base mpi2_base mpi2_new plain_new"]
#
# RUNS, in the order run within each round: plain_X, mpi2_X, mpi1_X, bands2_X (the plain process with
# --bands 2) for X in base, new (and mpi2_new2 for a third folder, NEW2_DIR in the environment). Every run is
# measured by bench/measure_run.py (user + sys of mpirun and its ranks; GDP_BENCH_PAUSE, 8 s unless
# set, before each: this VM takes freed pages back after ~3 s). Prints every run's CPU and wall,
# the medians, each run's CPU against the round's plain_base, each mpirun run against the plain run of
# its own build in the same round (the issue's ratio), and whether the outputs of the same
# command agree between the builds (cmp). Needs the build folder's bench/make_composite (BUILD=build).
set -euo pipefail
size=$1
rounds=$2
base=$(cd "$3" && pwd)
new=$(cd "$4" && pwd)
runs=${5:-"plain_base mpi2_base mpi2_new plain_new"}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup mpi-ab "${BUILD:-build}"
"$here/${BUILD:-build}/bench/make_composite" "$photo" "$size" "$size" "$work/c.tif" "$work/l.tif" > /dev/null
stitch=(stitch -c "$work/c.tif" -l "$work/l.tif" --compression none -q)
mpi=(mpirun --oversubscribe --allow-run-as-root --bind-to none)
export GDP_BENCH_PAUSE=${GDP_BENCH_PAUSE:-8}
for r in $(seq 1 "$rounds"); do
  for n in $runs; do
    dir=$base
    [[ $n == *_new ]] && dir=$new
    [[ $n == *_new2 ]] && dir=$(cd "$NEW2_DIR" && pwd)
    case $n in
      plain_*) cmd=(env LD_LIBRARY_PATH="$dir" "$dir/gdp") ;;
      mpi2_*) cmd=("${mpi[@]}" -np 2 -x LD_LIBRARY_PATH="$dir" "$dir/gdp") ;;
      mpi1_*) cmd=("${mpi[@]}" -np 1 -x LD_LIBRARY_PATH="$dir" "$dir/gdp") ;;
      bands2_*) cmd=(env LD_LIBRARY_PATH="$dir" "$dir/gdp") ;;
    esac
    extra=()
    [[ $n == bands2_* ]] && extra=(--bands 2)
    python3 "$here/bench/measure_run.py" "$work/$n-$r.json" -- "${cmd[@]}" "${stitch[@]}" "${extra[@]}" -o "$work/$n.tif" > /dev/null
  done
  echo "round $r done $(date -u +%T), load $(cut -d' ' -f1 /proc/loadavg)" >&2
done
for n in $runs; do
  [[ $n == *_new* && " $runs " == *" ${n%_new*}_base "* ]] || continue
  cmp -s "$work/${n%_new*}_base.tif" "$work/$n.tif" && echo "$n output == ${n%_new*}_base output (cmp)" ||
    echo "$n output DIFFERS from ${n%_new*}_base"
done
python3 - "$work" "$rounds" "$runs" <<'PY'
import json, statistics, sys
work, rounds, runs = sys.argv[1], int(sys.argv[2]), sys.argv[3].split()
load = lambda n, r: json.load(open(f"{work}/{n}-{r}.json"))
cpu = {n: [load(n, r)["user"] + load(n, r)["sys"] for r in range(1, rounds + 1)] for n in runs}
wall = {n: [load(n, r)["wall"] for r in range(1, rounds + 1)] for n in runs}
for n in runs:
    vol = statistics.median(load(n, r)["voluntary_switches"] for r in range(1, rounds + 1))
    print(f"{n:11s} CPU " + " ".join(f"{c:.2f}" for c in cpu[n]) + f" (median {statistics.median(cpu[n]):.2f}) s;"
          " wall " + " ".join(f"{w:.2f}" for w in wall[n]) + f" s; voluntary switches (median) {vol:.0f}; user / sys"
          " (medians) " + " / ".join(f"{statistics.median(load(n, r)[k] for r in range(1, rounds + 1)):.2f}"
                                      for k in ("user", "sys")) + " s; peak RSS " +
          " ".join(f"{load(n, r)['peak_rss_kb'] / 1024:.0f}" for r in range(1, rounds + 1)) + " MB; minor faults (median) " +
          f"{statistics.median(load(n, r)['minor_faults'] for r in range(1, rounds + 1)) / 1000:.1f} k")
if "plain_base" in runs:
    for n in runs:
        ratio = [c / p for c, p in zip(cpu[n], cpu["plain_base"])]
        print(f"{n:11s} / plain_base CPU per round " + " ".join(f"{x:.3f}" for x in ratio) +
              f" (median {statistics.median(ratio):.3f})")
for n in runs:  # each mpirun run against the plain run of its own build in the same round
    own = "plain_" + n.split("_", 1)[1]
    if n.startswith(("mpi", "bands2")) and own in runs:
        ratio = [c / p for c, p in zip(cpu[n], cpu[own])]
        print(f"{n:11s} / {own:10s} CPU per round " + " ".join(f"{x:.3f}" for x in ratio) +
              f" (median {statistics.median(ratio):.3f})")
PY
