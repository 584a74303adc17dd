#!/usr/bin/env bash
# The 1-gigapixel stitch of issue 17's acceptance (32768x32768 in bounded memory), measured once with the machine's load beside it.
# Usage: bench/giga_stitch.sh [SIZE=32768] [BUILD=build] [MEMORY=0]
# Cuts a SIZE x SIZE composite and label map (uncompressed 8-bit TIFF, 3.2 GB each at 32768²)
# from the blue-marble photo (bench/make_composite, cells of SIZE/16; ../shared/data, named in
# one line when missing), then runs `gdp stitch --compression none --memory MEMORY` (0: every
# scratch store in a file under $TMPDIR, so memory stays bounded; 16.4 GB of narrow scratch at
# 32768²) under bench/measure_run.py and prints wall, user+sys CPU, CPU/2 (what the wall would be
# on two idle cores), peak RSS, scratch bytes (--stats) and bytes written towards the disk, and
# the 1-minute load average sampled every 5 s during the run (other processes inflate the wall,
# not the CPU seconds). Needs about 3.3x the output's size free in $TMPDIR (26 GB at 32768²).
set -euo pipefail
size=${1:-32768}
build=${2:-build}
memory=${3:-0}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup giga "$build"
start=$SECONDS
"$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/comp.tif" "$work/labels.tif" $((size / 16))
echo "inputs made in $((SECONDS - start)) s"
(while sleep 5; do cut -d' ' -f1 /proc/loadavg; done) > "$work/load" &
sampler=$!
rc=0
python3 "$here/bench/measure_run.py" "$work/run.json" -- "$gdp" stitch -c "$work/comp.tif" -l "$work/labels.tif" \
  -o "$work/out.tif" --compression none -q --memory "$memory" --temp "$work" --stats "$work/stats.json" || rc=$?
kill "$sampler"
python3 - "$work" "$size" "$memory" "$rc" <<'PY'
import json, sys
work, size, memory, rc = sys.argv[1], int(sys.argv[2]), sys.argv[3], int(sys.argv[4])
m = json.load(open(f"{work}/run.json"))
load = [float(v) for v in open(f"{work}/load").read().split()]
cpu = m["user"] + m["sys"]
print(f"{size}² stitch, --memory {memory}: exit {rc}, wall {m['wall']:.1f} s, CPU {cpu:.1f} s "
      f"({m['user']:.1f} user + {m['sys']:.1f} sys; /2 = {cpu / 2:.1f} s), peak RSS {m['peak_rss_kb'] / 1024:.0f} MB, "
      f"written towards the disk {m['write_bytes'] / 1e9:.2f} GB")
if load:
    print(f"load average (1 min) during the run: mean {sum(load) / len(load):.1f}, min {min(load):.1f}, "
          f"max {max(load):.1f} over {len(load)} samples")
if rc == 0:
    s = json.load(open(f"{work}/stats.json"))
    keys = ("scratch_mb", "scratch_memory_mb", "scratch_disk_mb", "scratch_bytes_per_pixel", "relative_residuals",
            "seconds", "minor_faults_per_mpix")
    print(json.dumps({k: s.get(k) for k in keys}))
PY
exit "$rc"
