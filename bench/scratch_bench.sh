#!/usr/bin/env bash
# Scratch in memory (--memory: default budget) against scratch in files (--memory 0) on the stitch.
# Usage: bench/scratch_bench.sh [SIZES="8192 16384"] [BUILD=build] [RUNS=2] [PRECISION=yes]
# Per size: makes a composite + label map from a real photo (bench/make_composite, uncompressed
# TIFF), then runs `gdp stitch` RUNS times each way, interleaved, under bench/measure_run.py, and
# prints wall, CPU (user+sys), minor page faults per Mpix, bytes written towards the disk, scratch
# in memory / in files and scratch bytes per pixel, with the ratios of the two ways in one run.
# First (unless PRECISION=no) it prints scratch_precision on a 2048² composite: half against
# float per quantity.
set -euo pipefail
sizes=${1:-"8192 16384"}
build=${2:-build}
runs=${3:-2}
precision=${4:-yes}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup scratch-bench "$build"
if [[ $precision != no ]]; then
  "$here/$build/bench/make_composite" "$photo" 2048 2048 "$work/small.tif" "$work/small_labels.tif"
  "$here/$build/bench/scratch_precision" "$work/small.tif" "$work/small_labels.tif"
fi
for size in $sizes; do
  "$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/comp.tif" "$work/labels.tif"
  for run in $(seq "$runs"); do
    for mem in default 0; do
      flag=(); [[ $mem == default ]] || flag=(--memory "$mem")
      python3 "$here/bench/measure_run.py" "$work/run-$size-$mem-$run.json" -- "$gdp" stitch -c "$work/comp.tif" \
        -l "$work/labels.tif" -o "$work/out.tif" --compression none -q "${flag[@]}" \
        --stats "$work/stats-$size-$mem-$run.json"
    done
  done
  rm -f "$work/comp.tif" "$work/labels.tif" "$work/out.tif"
done
python3 - "$work" "$sizes" "$runs" <<'PY'
import json, sys
work, sizes, runs = sys.argv[1], sys.argv[2].split(), int(sys.argv[3])
for size in sizes:
    mpix = int(size) ** 2 / 1e6
    best = {}
    for mem in ("default", "0"):
        rows = []
        for r in range(1, runs + 1):
            m = json.load(open(f"{work}/run-{size}-{mem}-{r}.json"))
            s = json.load(open(f"{work}/stats-{size}-{mem}-{r}.json"))
            cpu = m["user"] + m["sys"]
            scratch = (s["scratch_memory_mb"] + s["scratch_disk_mb"]) * 1048576 / (mpix * 1e6)
            rows.append((m["wall"], cpu, m["sys"], m["minor_faults"] / mpix, m.get("write_bytes", 0) / 1e9,
                         s["scratch_memory_mb"], s["scratch_disk_mb"], scratch, m["peak_rss_kb"] / 1024))
            print(f"{size}² --memory {mem:7s} run {r}: wall {rows[-1][0]:.1f} s, CPU {cpu:.1f} s (sys {m['sys']:.1f}),"
                  f" {rows[-1][3]:.0f} minor faults/Mpix, {rows[-1][4]:.2f} GB written to disk, scratch"
                  f" {rows[-1][5]:.0f} MB in memory + {rows[-1][6]:.0f} MB in files = {scratch:.2f} B/pixel,"
                  f" peak RSS {rows[-1][8]:.0f} MB")
        best[mem] = min(rows)
    d, z = best["default"], best["0"]
    print(f"{size}² best of {runs}: default/files wall {d[0] / z[0]:.2f}x, CPU {d[1] / z[1]:.2f}x")
PY
