#!/usr/bin/env bash
# --in-core against streaming (issue 17): CPU seconds (user + sys), wall, peak memory and minor
# faults of one stitch, OLD's streaming and --in-core runs and NEW's --in-core run, interleaved.
# Usage: bench/incore_ab.sh OLD NEW [SIZE=8192] [ROUNDS=3] [PAUSE=5]
# OLD and NEW are folders holding gdp and libgdp.so* (as for bench/same_bits.sh). The composite is
# bench/make_composite's of the shared photo (uncompressed TIFF, so decoding is cheap). Every run
# waits PAUSE seconds first: on a guest whose freed memory goes back to the host (free page
# reporting, about 2 s after it is freed), a run started at once reuses the last run's pages and
# pays far less for fresh memory than a run on its own (docs/multigrid.md, "In-core memory on a PVM
# guest"). Prints each run and the medians; NEW's output is compared with OLD's (cmp).
set -euo pipefail
old=$(cd "$1" && pwd); new=$(cd "$2" && pwd)
size=${3:-8192}; rounds=${4:-3}; pause=${5:-5}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup incore-ab build
"$here/build/bench/make_composite" "$photo" "$size" "$size" "$work/composite.tif" "$work/labels.tif"
run() {  # NAME DIR ROUND [FLAGS]
  sleep "$pause"
  LD_LIBRARY_PATH=$2 python3 "$here/bench/measure_run.py" "$work/$1-$3.json" -- "$2/gdp" stitch -c "$work/composite.tif" \
    -l "$work/labels.tif" --compression none -q -o "$work/$1.tif" "${@:4}" > /dev/null
}
for r in $(seq 1 "$rounds"); do
  run old-streaming "$old" "$r"
  run old-incore "$old" "$r" --in-core
  run new-incore "$new" "$r" --in-core
done
for n in old-incore old-streaming; do
  cmp -s "$work/new-incore.tif" "$work/$n.tif" && echo "new --in-core output == $n output (cmp)" ||
    echo "new --in-core output DIFFERS from $n"
done
python3 - "$work" "$size" "$rounds" <<'PY'
import json, statistics, sys
work, size, rounds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
med = {}
for n in ("old-streaming", "old-incore", "new-incore"):
    runs = [json.load(open(f"{work}/{n}-{r}.json")) for r in range(1, rounds + 1)]
    cpu = [x["user"] + x["sys"] for x in runs]
    med[n] = statistics.median(cpu)
    print(f"{n:14s} CPU " + ", ".join(f"{x['user'] + x['sys']:.2f} ({x['sys']:.2f} sys)" for x in runs) +
          "; wall " + ", ".join(f"{x['wall']:.1f}" for x in runs) + f"; peak RSS {runs[0]['peak_rss_kb'] // 1024} MB"
          f"; minor faults/Mpix {runs[0]['minor_faults'] / (size * size / 1e6):.0f}")
print(f"{size}x{size}, medians of {rounds}: --in-core / streaming CPU: old {med['old-incore'] / med['old-streaming']:.2f}x, "
      f"new {med['new-incore'] / med['old-streaming']:.2f}x; new / old --in-core {med['new-incore'] / med['old-incore']:.2f}x")
PY
