#!/usr/bin/env bash
# Issue 17's figures in one run, one after another on a quiet machine (docs/reproduce.md): V-cycle
# throughput, gdp against DMG at 8192² and 16384², the 8192² stitch against its I/O floor, one
# schedule's CPU (bands, ranks, in-core) and the 1-gigapixel stitch.
# Usage: bench/issue17_figures.sh DMG_SRC [BUILD=build] [LOGS=/tmp/issue17-figures]
# DMG_SRC: a checkout or bare clone of github.com/mkazhdan/DMG (bench/vs_dmg.sh builds it outside
# the repository). Each bench writes LOGS/NAME.log; the composites come from ../shared/data (the
# benches say so in one line when it is missing). About 25 minutes on the 2-core VM of the docs;
# every timed run waits 8 s first (this VM takes freed pages back after ~3 s).
set -euo pipefail
[[ $# -ge 1 ]] || { echo "usage: $0 DMG_SRC [BUILD=build] [LOGS=/tmp/issue17-figures]" >&2; exit 2; }
dmg=$1; build=${2:-build}; logs=${3:-/tmp/issue17-figures}
cd "$(dirname "$0")/.."
mkdir -p "$logs" /tmp/e2e-in
run() { local name=$1; shift; echo "$(date -u +%H:%M:%S) $name" >&2; "$@" > "$logs/$name.log" 2>&1; }
run vcycle bash -c "for i in 1 2 3; do '$build'/bench/vcycle_bench --benchmark_filter='BM_VCycle/8192' | grep BM_VCycle; done"
run dmg8192 bench/vs_dmg.sh --dmg "$dmg" --runs 1 8192
run dmg16384 bench/vs_dmg.sh --dmg "$dmg" --runs 2 16384
export E2E_PAUSE=8 E2E_STITCHES=2 E2E_INPUTS=/tmp/e2e-in GDP_BENCH_PAUSE=8
run e2e bash -c "for r in 1 2 3 4; do bench/e2e_stitch.sh 8192 '$build'; done"
run one_schedule bench/one_schedule.sh 8192 5 "$build" "default bands2 mpi2 incore"
run giga bench/giga_stitch.sh 32768 "$build" 0
grep -h 'Mpix/s' "$logs/vcycle.log" || true
grep -h -A3 '| figure' "$logs"/dmg*.log | grep -E 'wall|CPU' || true
grep -h 'stitch --threads' "$logs/e2e.log" || true
tail -5 "$logs/one_schedule.log"
grep -h 'exit' "$logs/giga.log" || true
