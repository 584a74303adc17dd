#!/usr/bin/env bash
# Acceptance figures of the band schedule: one worker against two (threads, then MPI ranks), end to end.
# Usage: bench/band_scaling.sh [SIZE=8192] [BUILD=build]
# Makes a SIZE x SIZE RGB image from a real photo (uncompressed float TIFF, so decoding is
# cheap), then runs `gdp sharpen` with 1 band, 2 thread bands, 1 rank x 1 band and 2 ranks x
# 1 band, and prints per run the solve phase ("vcycles": V-cycle passes with right-hand side
# assembly and reading excluded), the input phase (reading, guidance, right-hand side), the
# end-to-end time, and the ratios against one worker.
# One run of each, back to back: compare within a run. GDP_MPIRUN_ARGS goes to mpirun: Open MPI
# binds every rank to one core by default with up to 2 ranks, which confines one rank's worker and
# its reading and writing threads to one core; GDP_MPIRUN_ARGS="--bind-to none" lets them spread.
set -euo pipefail
size=${1:-8192}
build=${2:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup scaling "$build"
oiiotool "$photo" --resize "${size}x${size}" \
  -d float --compression none -o "$work/in.tif"
args=(sharpen "$work/in.tif" -o "$work/out.tif" --compression none -q --beta 1.5)
"$gdp" "${args[@]}" --bands 1 --stats "$work/threads1.json"
"$gdp" "${args[@]}" --bands 2 --stats "$work/threads2.json"
mpi=(mpirun --oversubscribe --allow-run-as-root ${GDP_MPIRUN_ARGS:-})
"${mpi[@]}" -np 1 "$gdp" "${args[@]}" --bands 1 --stats "$work/ranks1.json"
"${mpi[@]}" -np 2 "$gdp" "${args[@]}" --bands 1 --stats "$work/ranks2.json"
python3 - "$work" "$size" <<'PY'
import json, sys
work, size = sys.argv[1], int(sys.argv[2])
mpix = size * size / 1e6
s = {n: json.load(open(f"{work}/{n}.json"))["seconds"] for n in ("threads1", "threads2", "ranks1", "ranks2")}
for n, v in s.items():
    print(f"{n}: solve {v['vcycles']:.2f} s ({mpix / v['vcycles']:.1f} Mpix/s), input {v['rhs']:.2f} s, "
          f"end to end {v['total']:.2f} s")
for one, two in (("threads1", "threads2"), ("ranks1", "ranks2")):
    print(f"{two} / {one}: solve {s[one]['vcycles'] / s[two]['vcycles']:.2f}x, end to end {s[one]['total'] / s[two]['total']:.2f}x")
PY
