#!/usr/bin/env python3
"""Runs one command and samples its threads' states: who wants a core when, and how often each sleeps.

    bench/thread_states.py [--every MS] [--bins N] -- COMMAND [ARGS...]

Every MS milliseconds (default 3) reads /proc/PID/task/*/stat (state, CPU) and, every tenth
sample, .../status (voluntary and involuntary context switches). Prints, per thread (by name:
gdp names its I/O threads gdp-decode, gdp-encode, gdp-deflate), its CPU seconds, its switches
(voluntary: it slept on a lock, a queue or I/O) and a strip of N bins over the run showing the
fraction of samples in which it was runnable (R: running or waiting for a core); then the
fraction of samples with 0, 1, 2 and 3+ runnable threads (and a strip of the samples with fewer
than 2, by time: where the run leaves a core idle). On an idle 2-core machine, time with
fewer than 2 runnable threads is a core left idle; on a loaded one a thread also waits for a core,
so read the strips for who paces whom. Linux only; the command's exit status is returned.
"""
import argparse
import collections
import os
import sys
import time

from proc_tasks import run_sampled, task_ids, task_stat


def read_task(pid, tid, with_status):
    state, name, cpu = task_stat(pid, tid)
    switches = None
    if with_status:
        with open(f"/proc/{pid}/task/{tid}/status") as f:
            d = dict(line.split(":", 1) for line in f if ":" in line)
        switches = (int(d["voluntary_ctxt_switches"]), int(d["nonvoluntary_ctxt_switches"]))
    return state, name, cpu, switches


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--every", type=float, default=3.0)
    ap.add_argument("--bins", type=int, default=60)
    ap.add_argument("cmd", nargs=argparse.REMAINDER)
    a = ap.parse_args()
    cmd = a.cmd[1:] if a.cmd and a.cmd[0] == "--" else a.cmd
    tick = os.sysconf("SC_CLK_TCK")
    samples, last = [], {}

    def visit(pid, now, n):
        states = {}
        for tid in task_ids(pid):
            try:
                state, name, cpu, sw = read_task(pid, tid, n % 10 == 0)
            except (OSError, ValueError, KeyError):
                continue
            states[int(tid)] = state
            old = last.get(int(tid), (name, 0, (0, 0), now))
            last[int(tid)] = (name, cpu, sw or old[2], old[3])
        samples.append((now, states))

    proc, start = run_sampled(cmd, a.every / 1000, visit)
    rc = proc.wait()
    wall = time.time() - start
    dt = wall / a.bins
    runnable = collections.defaultdict(lambda: [0] * a.bins)
    total = [0] * a.bins
    short = [0] * a.bins  # samples with fewer than 2 runnable threads (a core idle on 2 idle cores)
    counts = collections.Counter()
    for t, states in samples:
        b = min(int(t / dt), a.bins - 1)
        total[b] += 1
        r = [tid for tid, s in states.items() if s == "R"]
        counts[min(len(r), 3)] += 1
        short[b] += len(r) < 2
        for tid in r:
            runnable[tid][b] += 1
    print(f"wall {wall:.2f} s, {len(samples)} samples, bins of {dt:.2f} s (runnable fraction: ' ' none ... '@' all)")
    for tid, (name, cpu, (vol, invol), first) in sorted(last.items(), key=lambda kv: kv[1][3]):
        strip = "".join(" .:-=+*#%@"[min(9, int(x / max(total[i], 1) * 9.99))] for i, x in enumerate(runnable[tid]))
        print(f"{tid:8d} {name:15s} from {first:6.2f} s cpu {cpu / tick:6.2f} s vol {vol:6d} invol {invol:6d} |{strip}|")
    strip = "".join(" .:-=+*#%@"[min(9, int(x / max(total[i], 1) * 9.99))] for i, x in enumerate(short))
    print(f"{'':8s} {'< 2 runnable':15s} {'':34s} |{strip}|")
    print("runnable threads: " + ", ".join(f"{k}{'+' if k == 3 else ''}: {counts[k] / len(samples) * 100:.0f}%"
                                           for k in range(4)))
    return rc if rc >= 0 else 128 - rc


if __name__ == "__main__":
    sys.exit(main())
