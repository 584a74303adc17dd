#!/usr/bin/env bash
# Resume after SIGKILL (docs/resume.md): a SIZE x SIZE stitch killed at KILLS random moments and
# resumed each time must give the uninterrupted run's bytes (cmp); prints each resumed run's wall
# and CPU time (user+sys) against the full run's, and the checkpointing overhead.
# Usage: bench/resume_kill.sh [SIZE=8192] [KILLS=10] [BUILD=build] [EXT=tif] [SEED=1]
set -euo pipefail
size=${1:-8192}
kills=${2:-10}
build=${3:-build}
ext=${4:-tif}
RANDOM=${5:-1}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup resume "$build"
"$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/composite.$ext" "$work/labels.$ext"
args=(stitch -c "$work/composite.$ext" -l "$work/labels.$ext" -q)

# timed LABEL CMD...: runs CMD, appends "LABEL wall user+sys" to $work/times.
timed() {
  local label=$1
  shift
  /usr/bin/time -f "$label %e %U %S" -a -o "$work/times" "$@"
}
timed full "$gdp" "${args[@]}" -o "$work/full.tif" --stats "$work/full.json"
timed checkpointed "$gdp" "${args[@]}" -o "$work/cp.tif" --checkpoint "$work/cp"
cmp "$work/full.tif" "$work/cp.tif"
[[ ! -e $work/cp ]] || { echo "checkpoint directory left after success" >&2; exit 1; }
full_wall=$(awk '$1 == "full" {print $2}' "$work/times")

for ((i = 1; i <= kills; i++)); do
  r=$RANDOM  # here, not in the command substitution's subshell (which would not advance it)
  fraction=$(awk -v r=$r 'BEGIN {printf "%.3f", 0.05 + 0.9 * r / 32768}')
  delay=$(awk -v f="$fraction" -v w="$full_wall" 'BEGIN {printf "%.2f", f * w}')
  "$gdp" "${args[@]}" -o "$work/r.tif" --checkpoint "$work/cp" &
  pid=$!
  sleep "$delay"
  kill -KILL $pid 2>/dev/null || true
  status=0
  wait $pid 2>/dev/null || status=$?
  if ((status == 0)); then  # the load varies: this run was faster than the full one
    echo "kill at $delay s: the run had finished (not counted; another moment is drawn)"
    rm -f "$work/r.tif"
    ((i--)) || true
    continue
  elif [[ ! -f $work/cp/manifest ]]; then  # killed before the solve began: nothing to resume
    progress="none"
    timed "restart$i@$fraction" "$gdp" "${args[@]}" -o "$work/r.tif" --checkpoint "$work/cp"
  else
    progress=$(grep -P '^lane\t' "$work/cp/manifest" | cut -f3 | paste -sd ';' -)
    timed "resume$i@$fraction" "$gdp" "${args[@]}" -o "$work/r.tif" --resume "$work/cp"
  fi
  cmp "$work/full.tif" "$work/r.tif"
  echo "kill $i at $delay s ($fraction of the full run's wall), checkpoint: $progress: resumed, same bytes"
  rm -f "$work/r.tif"
done

python3 - "$work/full.json" <<'PY'
import json, sys
s = json.load(open(sys.argv[1]))
print(f"full run: input read and right-hand side {s['seconds']['rhs']:.1f} s of {s['seconds_total']:.1f} s"
      " (what a resume reads again)")
PY
awk -v size="$size" '
  $1 == "full" { fw = $2; fc = $3 + $4 }
  { wall[NR] = $2; cpu[NR] = $3 + $4; name[NR] = $1 }
  END {
    printf "%dx%d stitch, full run: %.1f s wall, %.1f s CPU\n", size, size, fw, fc
    for (k = 2; k <= NR; ++k) {
      split(name[k], p, "@")
      left = p[2] == "" ? 1 : 1 - p[2]
      printf "%-22s %6.1f s wall (%.2f of full; %.2f of it was left), %6.1f s CPU (%.2f of full)\n",
             name[k], wall[k], wall[k] / fw, left, cpu[k], cpu[k] / fc
    }
  }' "$work/times"
