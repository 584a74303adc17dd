#!/usr/bin/env bash
# Where scratch lives, interleaved (docs/how-streaming-works.md, "Scratch in O_DIRECT files"): memfds,
# O_DIRECT files and page-cache files, CPU seconds (user, sys) and wall of the vs-DMG stitch.
# Usage: bench/direct_scratch.sh SIZE [ROUNDS=2] [BUILD=build] [PAUSE=5] [MODES="memfd direct files default"]
# The composite is bench/vs_dmg.sh's (/tmp/gdp-vs-dmg/SIZE: composite.png, labels.png; run that
# script once to make it). Modes: memfd = every store in memory within the default budget
# (GDP_DIRECT_SCRATCH=off); direct = --memory 0 (every store an O_DIRECT file); files = --memory 0
# with GDP_DIRECT_SCRATCH=off (page-cache files with drop-behind, the path before O_DIRECT); default =
# neither (stores from ScratchBudget::kDirectFrom on O_DIRECT, smaller ones in memory); from=SIZE =
# the default with GDP_DIRECT_SCRATCH=SIZE (stores from SIZE on O_DIRECT). Every run
# waits PAUSE seconds first (freed memory goes back to this VM's host: docs/multigrid.md). Scratch
# files go to $TMPDIR (default /tmp). Prints each run, the medians, and checks that every mode's
# output is the same file (cmp). At 16384² and up run it under `flock /tmp/big.lock`.
set -euo pipefail
size=$1; rounds=${2:-2}; build=${3:-build}; pause=${4:-5}
modes=${5:-memfd direct files default}
here=$(cd "$(dirname "$0")/.." && pwd)
comp=/tmp/gdp-vs-dmg/$size
[[ -f $comp/composite.png && -f $comp/labels.png ]] || { echo "no composite in $comp: run bench/vs_dmg.sh $size first" >&2; exit 2; }
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-direct-scratch.XXXXXX")
trap 'rm -rf "$work"' EXIT
gdp="$here/$build/gdp"; [[ -x $gdp ]] || gdp="$here/$build/tools/gdp/gdp"
run() {  # MODE ROUND
  local env=() flags=()
  case $1 in
    memfd) env=(GDP_DIRECT_SCRATCH=off) ;;
    direct) flags=(--memory 0) ;;
    files) env=(GDP_DIRECT_SCRATCH=off); flags=(--memory 0) ;;
    default) ;;
    from=*) env=(GDP_DIRECT_SCRATCH=${1#from=}) ;;
  esac
  sleep "$pause"
  env "${env[@]}" python3 "$here/bench/measure_run.py" "$work/$1-$2.json" -- "$gdp" stitch -c "$comp/composite.png" \
    -l "$comp/labels.png" -o "$work/$1.tif" --depth 16 --compression none --threads 2 --temp "$work" -q \
    --stats "$work/$1-$2.stats.json" "${flags[@]}" > /dev/null
}
for r in $(seq 1 "$rounds"); do
  set -- $modes
  (( r % 2 == 0 )) && set -- $(printf '%s\n' $modes | tac)  # alternate the order
  for m in "$@"; do run "$m" "$r"; done
done
first=${modes%% *}
for m in $modes; do cmp -s "$work/$first.tif" "$work/$m.tif" || echo "output of $m DIFFERS from $first"; done
python3 - "$work" "$size" "$rounds" $modes <<'PY'
import json, statistics, sys
work, size, rounds, modes = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), sys.argv[4:]
med = {}
for m in modes:
    runs = [json.load(open(f"{work}/{m}-{r}.json")) for r in range(1, rounds + 1)]
    st = json.load(open(f"{work}/{m}-1.stats.json"))
    cpu = [x["user"] + x["sys"] for x in runs]
    med[m] = statistics.median(cpu)
    print(f"{size}² {m:8s} CPU " + ", ".join(f"{x['user'] + x['sys']:.2f} ({x['user']:.2f}+{x['sys']:.2f})" for x in runs)
          + "; wall " + ", ".join(f"{x['wall']:.1f}" for x in runs)
          + f"; to disk {runs[0]['write_bytes'] / 1e9:.2f} GB; scratch memory {st.get('scratch_memory_mb', '?')} MB,"
          f" disk {st.get('scratch_disk_mb', '?')} MB; peak RSS {runs[0]['peak_rss_kb'] // 1024} MB")
base = modes[0]
print(f"medians of {rounds}, CPU against {base}: " + ", ".join(f"{m} {med[m] / med[base]:.2f}x" for m in modes))
PY
