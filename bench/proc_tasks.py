"""Runs a command while sampling its threads from /proc (shared by thread_cpu.py and thread_states.py).

task_stat(pid, tid) reads one thread's state, name and CPU ticks (user + sys) from
/proc/PID/task/TID/stat; run_sampled(cmd, every, visit) starts the command and calls
visit(pid, seconds_since_start, sample_index) every `every` seconds until it exits (the exited
process is left for the caller to reap: wait4 for its rusage, or Popen.wait). Linux only.
"""
import os
import subprocess
import time


def task_stat(pid, tid):
    with open(f"/proc/{pid}/task/{tid}/stat") as f:
        text = f.read()
    name = text[text.index("(") + 1:text.rindex(")")]
    fields = text.rsplit(")", 1)[1].split()
    return fields[0], name, int(fields[11]) + int(fields[12])


def task_ids(pid):
    try:
        return os.listdir(f"/proc/{pid}/task")
    except OSError:
        return []


def run_sampled(cmd, every, visit):
    start = time.time()
    proc = subprocess.Popen(cmd)
    n = 0
    while True:
        visit(proc.pid, time.time() - start, n)
        n += 1
        if os.waitid(os.P_PID, proc.pid, os.WEXITED | os.WNOHANG | os.WNOWAIT) is not None:
            return proc, start
        time.sleep(every)
