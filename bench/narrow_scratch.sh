#!/usr/bin/env bash
# Narrow scratch (the default) against float scratch (--scratch float) on the stitch, in one run.
# Usage: bench/narrow_scratch.sh [SIZE=8192] [BUILD=build] [RUNS=2]
# Cuts a SIZE x SIZE composite, label map (uncompressed TIFF) and held-out truth from a real photo
# (bench/make_composite; ../shared/data, named in one line when missing), then runs `gdp stitch`
# (16-bit uncompressed TIFF out) RUNS times each way, interleaved, under bench/measure_run.py, and
# prints wall, CPU (user+sys), scratch bytes (per pixel), peak RSS, the RMS error against the
# truth (blend_layers error: per value, each channel's mean difference removed, x255 in 8-bit
# levels) and the two outputs' difference, with the narrow/float ratios of the best runs.
set -euo pipefail
size=${1:-8192}
build=${2:-build}
runs=${3:-2}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup narrow-scratch "$build"
"$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/comp.tif" "$work/labels.tif" 1024 "$work/truth.tif"
for run in $(seq "$runs"); do
  for scratch in narrow float; do
    python3 "$here/bench/measure_run.py" "$work/run-$scratch-$run.json" -- "$gdp" stitch -c "$work/comp.tif" \
      -l "$work/labels.tif" -o "$work/out-$scratch.tif" --depth 16 --compression none -q --scratch "$scratch" \
      --stats "$work/stats-$scratch-$run.json"
    "$here/$build/bench/blend_layers" error "$work/out-$scratch.tif" "$work/truth.tif" > "$work/error-$scratch-$run"
  done
done
"$here/$build/bench/blend_layers" error "$work/out-narrow.tif" "$work/out-float.tif" > "$work/narrow-vs-float"
python3 - "$work" "$size" "$runs" <<'PY'
import json, sys
work, size, runs = sys.argv[1], int(sys.argv[2]), int(sys.argv[3])
mpix = size * size / 1e6
best = {}
for r in range(1, runs + 1):
    for scratch in ("narrow", "float"):
        m = json.load(open(f"{work}/run-{scratch}-{r}.json"))
        s = json.load(open(f"{work}/stats-{scratch}-{r}.json"))
        err = open(f"{work}/error-{scratch}-{r}").read().split()
        cpu = m["user"] + m["sys"]
        row = (m["wall"], cpu, m["sys"], s["scratch_mb"], s["scratch_bytes_per_pixel"], m["peak_rss_kb"] / 1024,
               float(err[1]))
        print(f"{size}² --scratch {scratch:6s} run {r}: wall {row[0]:.1f} s, CPU {cpu:.1f} s (sys {row[2]:.1f}),"
              f" scratch {row[3]:.0f} MB = {row[4]:.2f} B/pixel, peak RSS {row[5]:.0f} MB,"
              f" rms error {row[6]:.6f} (x255: {row[6] * 255:.4f})")
        best[scratch] = min(best.get(scratch, row), row)
n, f = best["narrow"], best["float"]
print(f"{size}² best of {runs}: narrow/float wall {n[0] / f[0]:.2f}x, CPU {n[1] / f[1]:.2f}x, scratch {n[3] / f[3]:.2f}x,"
      f" peak RSS {n[5] / f[5]:.2f}x")
print("narrow against float:", open(f"{work}/narrow-vs-float").read().strip())
PY
