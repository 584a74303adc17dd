#!/usr/bin/env python3
"""Runs one command and writes its cost as JSON (the kernel's rusage and I/O accounting).

    bench/measure_run.py OUT.json -- COMMAND [ARGS...]

OUT.json: start/end (epoch seconds), wall, user, sys (CPU seconds of the command and its
children), peak_rss_kb, minor_faults, voluntary_switches (waits: a lock, a queue, I/O),
involuntary_switches (preempted), rc, and the kernel's I/O accounting of the command:
wchar (bytes passed to write(), files and pipes alike), write_bytes (bytes sent towards the
disk), cancelled_write_bytes (of those, dropped because the file was deleted or truncated
first). The I/O counters are read from /proc/PID/io after the command has exited but before
it is reaped (waitid WNOWAIT), the rest from wait4()'s rusage (the same numbers /usr/bin/time -v
prints, which some machines lack). Linux only. The command's stdout and stderr pass through;
the exit status is the command's (128 + N when signal N ended it).

GDP_BENCH_PAUSE=S sleeps S seconds before the command starts (not timed): this VM takes freed
pages back after about 3 s, so a run that closely follows another pays less for fresh memory and
back-to-back pairs favour the later run (docs/how-streaming-works.md). Every bench script that
measures through this file takes it.
"""
import json
import os
import subprocess
import sys
import time


def main(argv):
    if len(argv) < 4 or argv[2] != "--":
        sys.stderr.write("usage: measure_run.py OUT.json -- COMMAND [ARGS...]\n")
        return 2
    out_path, command = argv[1], argv[3:]
    time.sleep(float(os.environ.get("GDP_BENCH_PAUSE", "0") or 0))
    start = time.time()
    proc = subprocess.Popen(command)
    os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT)
    end = time.time()
    with open(f"/proc/{proc.pid}/io") as f:
        io = {k: int(v) for k, v in (line.split(": ") for line in f.read().splitlines())}
    _, status, usage = os.wait4(proc.pid, 0)
    proc.returncode = code = os.waitstatus_to_exitcode(status)
    rc = code if code >= 0 else 128 - code
    result = dict(user=usage.ru_utime, sys=usage.ru_stime, peak_rss_kb=usage.ru_maxrss,
                  minor_faults=usage.ru_minflt, voluntary_switches=usage.ru_nvcsw,
                  involuntary_switches=usage.ru_nivcsw, start=start, end=end, wall=end - start,
                  rc=rc, wchar=io["wchar"], write_bytes=io["write_bytes"],
                  cancelled_write_bytes=io["cancelled_write_bytes"])
    with open(out_path, "w") as f:
        json.dump(result, f)
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv))
