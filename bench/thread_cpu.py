#!/usr/bin/env python3
"""Runs one command and writes the CPU seconds (user + sys) of each of its threads as JSON.

    bench/thread_cpu.py OUT.json -- COMMAND [ARGS...]

Samples /proc/PID/task/*/stat every 20 ms and keeps each thread's last figure (a thread that
ends between two samples loses up to 20 ms). OUT.json: wall, cpu (user + sys of the whole
command, from wait4), main (the process's first thread) and threads (the others, largest first).
Linux only; the command's output passes through and its exit status is returned.
"""
import json
import os
import sys
import time

from proc_tasks import run_sampled, task_ids, task_stat


def sample(pid, seen, tick):
    for tid in task_ids(pid):
        try:
            seen[int(tid)] = task_stat(pid, tid)[2] / tick  # utime + stime
        except OSError:
            continue


def main(argv):
    if len(argv) < 4 or argv[2] != "--":
        sys.stderr.write("usage: thread_cpu.py OUT.json -- COMMAND [ARGS...]\n")
        return 2
    tick = os.sysconf("SC_CLK_TCK")
    seen = {}
    proc, start = run_sampled(argv[3:], 0.02, lambda pid, t, n: sample(pid, seen, tick))
    sample(proc.pid, seen, tick)
    _, status, usage = os.wait4(proc.pid, 0)
    main_cpu = seen.pop(proc.pid, 0.0)
    result = dict(wall=time.time() - start, cpu=usage.ru_utime + usage.ru_stime, main=main_cpu,
                  threads=sorted(seen.values(), reverse=True), rc=os.waitstatus_to_exitcode(status))
    with open(argv[1], "w") as f:
        json.dump(result, f)
    return result["rc"] if result["rc"] >= 0 else 128 - result["rc"]


if __name__ == "__main__":
    sys.exit(main(sys.argv))
