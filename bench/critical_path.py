#!/usr/bin/env python3
"""Critical-path estimate of a gdp blend from CPU samples: what its wall would be on N idle cores.

    bench/critical_path.py [--cores 2] [--freq 999] -- gdp blend -o OUT ...

Runs the command under `perf record` (every thread, FREQ samples per CPU-second, no call graphs;
--keep FILE keeps perf's data, --data FILE reads such data instead of running a command) and
splits the run into phases by the symbols sampled: seams (until the seam pass is last seen, or the
stitch's input pass first), input (until the input pass is last seen: layers decoded and swept,
guidance, right-hand side, restriction) and the rest (prolongation, output). A phase on N idle cores takes at least its
CPU / N and at least its busiest thread's CPU: the estimate is the larger, summed over phases.
CPU seconds are samples / FREQ, so a loaded machine (threads waiting for a core) does not
inflate them. Needs perf (Debian linux-perf) and permission to record (perf_event_paranoid).
"""
import argparse
import collections
import os
import subprocess
import sys
import tempfile

INPUT = ("InputRows", "ImageGuidance", "RhsAssembler", "StitchGuidance")
SEAMS = ("SeamPasses", "chamfer_row", "compute_seam", "void (int, int), gdp::blending")


def samples(cmd, freq, data):
    if cmd:
        subprocess.run(["perf", "record", "-q", "-F", str(freq), "-o", data, "--"] + cmd, check=True,
                       stdout=subprocess.DEVNULL)
    out = subprocess.run(["perf", "script", "-i", data, "-F", "tid,time,ip,sym"], check=True,
                         capture_output=True, text=True).stdout
    rows = []
    for line in out.splitlines():
        parts = line.split(None, 2)
        if len(parts) < 2 or not parts[1].endswith(":"):
            continue
        rows.append((int(parts[0]), float(parts[1][:-1]), parts[2] if len(parts) > 2 else ""))
    return rows


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--freq", type=int, default=999)
    ap.add_argument("--keep", help="keep perf's data in this file")
    ap.add_argument("--data", help="read this perf data instead of running a command")
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd and a.cmd[0] == "--" else a.cmd
    with tempfile.TemporaryDirectory() as tmp:
        rows = samples([] if a.data else cmd, a.freq, a.data or a.keep or os.path.join(tmp, "perf.data"))
    if not rows:
        sys.exit("no samples")
    inputs = [t for _, t, s in rows if any(k in s for k in INPUT)]
    seams = [t for _, t, s in rows if any(k in s for k in SEAMS)]
    t1 = max(inputs) if inputs else rows[-1][1]
    t0 = min(max(seams) if seams else rows[0][1], min(inputs) if inputs else t1)
    phases = collections.OrderedDict((("seams", []), ("input", []), ("rest", [])))
    for tid, t, _ in rows:
        phases["seams" if t < t0 else "input" if t <= t1 else "rest"].append(tid)
    total_est = total_cpu = 0.0
    for name, tids in phases.items():
        per = collections.Counter(tids)
        cpu = len(tids) / a.freq
        busiest = max(per.values(), default=0) / a.freq
        est = max(cpu / a.cores, busiest)
        total_est += est
        total_cpu += cpu
        print(f"{name:6s} cpu {cpu:7.2f} s  busiest thread {busiest:6.2f} s  on {a.cores} idle cores {est:6.2f} s")
    print(f"total  cpu {total_cpu:7.2f} s  critical-path estimate on {a.cores} idle cores {total_est:6.2f} s")


if __name__ == "__main__":
    main()
