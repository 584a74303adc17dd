#!/usr/bin/env python3
"""Runs one command under /usr/bin/time -v and writes its cost as JSON, bytes written included.

    bench/measure_run.py OUT.json -- COMMAND [ARGS...]

OUT.json: start/end (epoch seconds), wall, user, sys (CPU seconds of the command and its
children), peak_rss_kb, minor_faults, voluntary_switches (waits: a lock, a queue, I/O),
involuntary_switches (preempted), rc, and the kernel's I/O accounting of the command:
wchar (bytes passed to write(), files and pipes alike), write_bytes (bytes sent towards the
disk), cancelled_write_bytes (of those, dropped because the file was deleted or truncated
first). The I/O counters are read from /proc/PID/io of the `time` process after it has
exited but before it is reaped (waitid WNOWAIT): by then it has reaped the command, whose
counters the kernel adds to its parent's. Linux only. The command's stdout and stderr pass
through; the exit status is the command's.
"""
import json
import os
import subprocess
import sys
import tempfile
import time


def parse_time_v(text):
    """The fields of /usr/bin/time -v that the benchmarks report."""
    keys = {
        "User time (seconds)": ("user", float),
        "System time (seconds)": ("sys", float),
        "Maximum resident set size (kbytes)": ("peak_rss_kb", int),
        "Minor (reclaiming a frame) page faults": ("minor_faults", int),
        "Voluntary context switches": ("voluntary_switches", int),
        "Involuntary context switches": ("involuntary_switches", int),
    }
    out = {}
    for line in text.splitlines():
        name, _, value = line.strip().rpartition(": ")
        if name in keys:
            key, kind = keys[name]
            out[key] = kind(value)
    return out


def main(argv):
    if len(argv) < 4 or argv[2] != "--":
        sys.stderr.write("usage: measure_run.py OUT.json -- COMMAND [ARGS...]\n")
        return 2
    out_path, command = argv[1], argv[3:]
    with tempfile.NamedTemporaryFile("r", suffix=".time") as report:
        start = time.time()
        proc = subprocess.Popen(["/usr/bin/time", "-v", "-o", report.name] + command)
        os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOWAIT)
        end = time.time()
        with open(f"/proc/{proc.pid}/io") as f:
            io = {k: int(v) for k, v in (line.split(": ") for line in f.read().splitlines())}
        rc = proc.wait()
        result = parse_time_v(report.read())
    result.update(start=start, end=end, wall=end - start, rc=rc, wchar=io["wchar"],
                  write_bytes=io["write_bytes"], cancelled_write_bytes=io["cancelled_write_bytes"])
    with open(out_path, "w") as f:
        json.dump(result, f)
    return rc


if __name__ == "__main__":
    sys.exit(main(sys.argv))
