#!/usr/bin/env python3
"""Critical-path estimate of a gdp blend from CPU samples: what its wall would be on N idle cores.

    bench/critical_path.py [--cores 2] [--freq 999] -- gdp blend -o OUT ...

Runs the command under `perf record` (every thread, FREQ samples per CPU-second, no call graphs;
--keep FILE keeps perf's data, --data FILE reads such data instead of running a command) and
splits the run into phases by the symbols sampled: seams (until the seam pass is last seen, or the
stitch's input pass first), input (until the input pass is last seen: layers decoded and swept,
guidance, right-hand side, restriction) and the rest (prolongation, output). A phase on N idle cores takes at least its
CPU / N and at least its busiest thread's CPU: the estimate is the larger, summed over phases.
--threads adds each thread's CPU per phase, by its name (gdp's I/O threads are named: gdp-decode,
gdp-encode, gdp-deflate; the others show as gdp), and its first and last sample, in seconds from
the first sample: when decoding starts, when the solver's input pass starts and ends, how long
the output's encoding runs on after the last solver thread stops.
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


def thread_names(data):
    """Each thread's last name (perf script's comm), by thread id."""
    out = subprocess.run(["perf", "script", "-i", data, "-F", "comm,tid"], check=True, capture_output=True,
                         text=True).stdout
    names = {}
    for line in out.splitlines():
        parts = line.rsplit(None, 1)
        if len(parts) == 2 and parts[1].isdigit():
            names[int(parts[1])] = parts[0].strip()
    return names


def per_thread(rows, phases_of, names, freq):
    """Prints each thread's CPU per phase, first and last sample (s from the first), largest first."""
    t0 = rows[0][1]
    seen = collections.defaultdict(lambda: [None, None, collections.Counter()])
    for tid, t, _ in rows:
        s = seen[tid]
        s[0] = t if s[0] is None else s[0]
        s[1] = t
        s[2][phases_of(t)] += 1
    print(f"{'thread':>8s} {'name':15s} {'first':>6s} {'last':>6s}   seams   input    rest  (CPU s)")
    for tid, (first, last, per) in sorted(seen.items(), key=lambda kv: -sum(kv[1][2].values())):
        cells = "".join(f"{per[p] / freq:8.2f}" for p in ("seams", "input", "rest"))
        print(f"{tid:8d} {names.get(tid, '?'):15s} {first - t0:6.2f} {last - t0:6.2f}{cells}")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--cores", type=int, default=2)
    ap.add_argument("--freq", type=int, default=999)
    ap.add_argument("--keep", help="keep perf's data in this file")
    ap.add_argument("--data", help="read this perf data instead of running a command")
    ap.add_argument("--threads", action="store_true", help="also each thread's CPU per phase, by name")
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd and a.cmd[0] == "--" else a.cmd
    with tempfile.TemporaryDirectory() as tmp:
        data = a.data or a.keep or os.path.join(tmp, "perf.data")
        rows = samples([] if a.data else cmd, a.freq, data)
        names = thread_names(data) if a.threads else {}
    if not rows:
        sys.exit("no samples")
    inputs = [t for _, t, s in rows if any(k in s for k in INPUT)]
    seams = [t for _, t, s in rows if any(k in s for k in SEAMS)]
    t1 = max(inputs) if inputs else rows[-1][1]
    t0 = min(max(seams) if seams else rows[0][1], min(inputs) if inputs else t1)
    phases = collections.OrderedDict((("seams", []), ("input", []), ("rest", [])))
    phase_of = lambda t: "seams" if t < t0 else "input" if t <= t1 else "rest"
    for tid, t, _ in rows:
        phases[phase_of(t)].append(tid)
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
    if a.threads:
        print(f"input phase: {t0 - rows[0][1]:.2f} to {t1 - rows[0][1]:.2f} s of {rows[-1][1] - rows[0][1]:.2f} s sampled")
        per_thread(rows, phase_of, names, a.freq)


if __name__ == "__main__":
    main()
