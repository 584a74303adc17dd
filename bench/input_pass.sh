#!/usr/bin/env bash
# The input pass of a stitch (issue 17): two gdp binaries, interleaved, --bands 1 and 2, CPU per thread.
# Usage: bench/input_pass.sh OLD_GDP [SIZE=8192] [ROUNDS=2] [BUILD=build]
# Makes a SIZE x SIZE composite + label map (uncompressed TIFF, so decoding is cheap) from a real
# photo with bench/make_composite, then runs `gdp stitch` with OLD_GDP (say a copy of main's
# binary) and BUILD's gdp in turn, --bands 1 then --bands 2, ROUNDS times, under
# bench/thread_cpu.py (CPU seconds of each thread) with --stats. Prints per run the input pass
# (--stats seconds.rhs; this branch's binary also splits its CPU into the decoding thread's and the
# readers'), the main thread's CPU (it reads, or decodes, and writes), the busiest other threads, the
# whole CPU and wall; and whether the two binaries' outputs are the same bytes (cmp).
# MAKE_COMPOSITE: the generator to use where BUILD has none.
set -euo pipefail
old=$(realpath "$1")
size=${2:-8192}
rounds=${3:-2}
build=${4:-build}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup input-pass "$build"
"${MAKE_COMPOSITE:-$here/$build/bench/make_composite}" "$photo" "$size" "$size" "$work/composite.tif" "$work/labels.tif" $((size / 16))
stitch=(stitch -c "$work/composite.tif" -l "$work/labels.tif" --compression none -q)
for r in $(seq 1 "$rounds"); do
  for bands in 1 2; do
    for which in old new; do
      exe=$old
      [[ $which == new ]] && exe=$gdp
      python3 "$here/bench/thread_cpu.py" "$work/$which-$bands-$r.json" -- \
        "$exe" "${stitch[@]}" --bands "$bands" -o "$work/$which-$bands.tif" --stats "$work/$which-$bands-$r.stats.json"
    done
  done
done
for bands in 1 2; do
  cmp -s "$work/old-$bands.tif" "$work/new-$bands.tif" && echo "--bands $bands: same output bytes (cmp)" ||
    echo "--bands $bands: outputs DIFFER"
done
python3 - "$work" "$size" "$rounds" <<'PY'
import json, sys
work, size, rounds = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
px = size * size
print(f"{size}x{size} stitch; seconds.rhs = the input pass (old: time inside its serial input rows; new: decode start to the last reader done)")
for r in range(1, rounds + 1):
    for bands in (1, 2):
        for which in ("old", "new"):
            t = json.load(open(f"{work}/{which}-{bands}-{r}.json"))
            s = json.load(open(f"{work}/{which}-{bands}-{r}.stats.json"))["seconds"]
            split = ""
            if "rhs_decode_cpu" in s:
                split = (f", decode thread {s['rhs_decode_cpu']:.2f} CPU-s ({1e9 * s['rhs_decode_cpu'] / px:.1f} ns/px)"
                         f", readers {s['rhs_columns_cpu']:.2f} CPU-s")
            print(f"round {r} --bands {bands} {which}: rhs {s['rhs']:.2f} s{split}; main thread {t['main']:.2f} CPU-s "
                  f"({1e9 * t['main'] / px:.1f} ns/px), others " + ", ".join(f"{c:.2f}" for c in t["threads"][:4]) +
                  f"; total {t['cpu']:.2f} CPU-s, wall {t['wall']:.2f} s")
PY
