#!/usr/bin/env bash
# Fuzzes gdp's decoders: builds fuzz/ (libFuzzer, clang-14, ASan + UBSan) into build-fuzz/ and runs
# each codec's target for SECONDS (default 600), one after the other. Usage: scripts/fuzz.sh [SECONDS [CODEC...]]
# Corpora grow in build-fuzz/corpus/CODEC; a finding is saved as build-fuzz/findings/CODEC-*; logs
# in build-fuzz/logs. Exits 1 when any target found a crash, hang, leak or sanitizer report.
set -euo pipefail
cd "$(dirname "$0")/.."
seconds=${1:-600}
shift || true
codecs=("$@")
[ ${#codecs[@]} -gt 0 ] || codecs=(png tiff jpeg exr fits)
if ! command -v clang++-14 > /dev/null; then
  echo "fuzz.sh: needs clang++-14 and libFuzzer: apt-get install clang-14 libclang-rt-14-dev" >&2
  exit 2
fi
launcher=()
command -v ccache > /dev/null && launcher=(-DCMAKE_CXX_COMPILER_LAUNCHER=ccache)
cmake -S fuzz -B build-fuzz -G Ninja -DCMAKE_CXX_COMPILER=clang++-14 "${launcher[@]}" > /dev/null
cmake --build build-fuzz --parallel "$(nproc)"
mkdir -p build-fuzz/logs build-fuzz/findings
rm -rf build-fuzz/seeds
build-fuzz/gdp_fuzz_seeds build-fuzz/seeds
# Small real files from the test data join the generated seeds.
for f in tests/data/*/*; do
  [ "$(stat -c %s "$f")" -le 65536 ] || continue
  case "$f" in
    *.png) cp "$f" build-fuzz/seeds/png/ ;;
    *.jpg) cp "$f" build-fuzz/seeds/jpeg/ ;;
    *.fits) cp "$f" build-fuzz/seeds/fits/ ;;
  esac
done
status=0
printf '%-6s %8s %12s %8s %s\n' codec seconds executions corpus result
for codec in "${codecs[@]}"; do
  mkdir -p "build-fuzz/corpus/$codec"
  log="build-fuzz/logs/$codec.log"
  start=$(date +%s)
  result=ok
  "build-fuzz/${codec}_fuzzer" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=65536 \
    -print_final_stats=1 -artifact_prefix="build-fuzz/findings/$codec-" \
    "build-fuzz/corpus/$codec" "build-fuzz/seeds/$codec" > "$log" 2>&1 || { result="FINDING (see $log)"; status=1; }
  runs=$(sed -n 's/^stat::number_of_executed_units: *//p' "$log" | tail -1)
  printf '%-6s %8s %12s %8s %s\n' "$codec" $(($(date +%s) - start)) "${runs:-?}" \
    "$(find "build-fuzz/corpus/$codec" -type f | wc -l)" "$result"
done
exit $status
