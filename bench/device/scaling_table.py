#!/usr/bin/env python3
"""Turns the runs of bench/device/scaling.sh into OUTDIR/scaling.json and a markdown table, OUTDIR/scaling.md.

    scaling_table.py RUNS.jsonl MACHINE.json OUTDIR

RUNS.jsonl: one line per run (name, size, bands, memory, depth, ref, rc, and what its
measure_run.py JSON, its `gdp --stats` JSON and its image_diff JSON held, or null). Per run: wall,
user+sys CPU seconds, CPU/wall (cores kept busy), peak RSS, scratch in memory and in files,
Mpix/s end to end and of the V-cycle phase, Mpix/s per band (the paper's Table III measure),
speedup over the first run of its size with the same memory setting, and the check against the
reference run: float and half outputs within 2e-4 of the value range (docs/how-bands-work.md: 1e-4 up
to 512 columns, 2e-4 on wider images, where the phases hold more groups), 8- and 16-bit outputs
within one step more (banded results that close can round to neighbouring steps).
"""
import json
import sys

STEP = {"8": 1 / 255, "16": 1 / 65535}
TOLERANCE = 2e-4


def check(run, diff):
    if diff is None:
        return None, "-"
    allowed = TOLERANCE * diff["range"] + STEP.get(run["depth"], 0.0)
    ok = diff["max_abs"] <= allowed
    return ok, f"{'pass' if ok else 'FAIL'} ({diff['max_rel']:.1e} of range, rms {diff['rms']:.1e})"


def row(run, first):
    t, s = run["time"], run["stats"] or {}
    mpix = run["size"] ** 2 / 1e6
    r = dict(name=run["name"], size=run["size"], bands=run["bands"], memory=run["memory"], depth=run["depth"],
             rc=run["rc"], reference=run["ref"] or None)
    if run["rc"] != 0 or t is None:
        return r
    cpu = t["user"] + t["sys"]
    r.update(wall_s=round(t["wall"], 2), cpu_s=round(cpu, 2), user_s=t["user"], sys_s=t["sys"],
             busy_cores=round(cpu / t["wall"], 2), peak_rss_mb=round(t["peak_rss_kb"] / 1024, 1),
             minor_faults=t["minor_faults"], write_bytes=t["write_bytes"], mpix=mpix,
             mpix_per_s=round(mpix / t["wall"], 2), mpix_per_s_per_band=round(mpix / t["wall"] / run["bands"], 3),
             vcycle_s=s.get("seconds", {}).get("vcycles"), scratch_memory_mb=s.get("scratch_memory_mb"),
             scratch_disk_mb=s.get("scratch_disk_mb"), scratch_mb=s.get("scratch_mb"),
             relative_residuals=s.get("relative_residuals"))
    if r["vcycle_s"]:
        r["vcycle_mpix_per_s"] = round(mpix / r["vcycle_s"], 2)
    if first and first.get("wall_s"):
        r["speedup"] = round(first["wall_s"] / r["wall_s"], 2)
    r["check_ok"], r["check"] = check(run, run["diff"])
    r["diff"] = run["diff"]
    return r


def fmt(v, spec=""):
    return "-" if v is None else format(v, spec)


def main(argv):
    if len(argv) != 4:
        sys.stderr.write("usage: scaling_table.py RUNS.jsonl MACHINE.json OUTDIR\n")
        return 2
    runs = [json.loads(line) for line in open(argv[1]) if line.strip()]
    with open(argv[2]) as f:
        machine = json.load(f)
    rows, firsts = [], {}
    for run in runs:
        key = run["size"]  # speedups against the first run of the size (the in-memory one band)
        r = row(run, firsts.get(key))
        if key not in firsts:
            firsts[key] = r
            if "wall_s" in r:
                r["speedup"] = 1.0
        rows.append(r)
    with open(f"{argv[3]}/scaling.json", "w") as f:
        json.dump(dict(machine=machine, runs=rows), f, indent=1)
    lines = [f"Machine: {machine.get('cores', '?')} cores ({machine.get('cpu', '?')}), "
             f"{machine.get('memory_gib', '?')} GiB, {machine.get('glibc', '?')}; `--threads` {machine.get('threads', 'bands + 2')}, "
             f"inputs, outputs and scratch in {machine.get('scratch_dir', '/tmp')}; `--memory "
             f"{machine.get('memory_option', '?')}` (scratch in memory) unless the row says 0 (scratch in files).", "",
             "| size | bands | --memory | out | wall s | CPU s (user+sys) | CPU/wall | peak RSS MB | scratch mem + files MB "
             "| Mpix/s | Mpix/s per band | V-cycle Mpix/s | speedup | check vs reference |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for r in rows:
        if "wall_s" not in r:
            lines.append(f"| {r['size']}² | {r['bands']} | {r['memory']} | {r['depth']} | failed (exit {r['rc']}) "
                         "| | | | | | | | | |")
            continue
        lines.append(
            f"| {r['size']}² | {r['bands']} | {r['memory']} | {r['depth']} | {r['wall_s']:.1f} | {r['cpu_s']:.1f} "
            f"({r['sys_s']:.1f} sys) | {r['busy_cores']:.1f} | {r['peak_rss_mb']:.0f} | "
            f"{fmt(r['scratch_memory_mb'], '.0f')} + {fmt(r['scratch_disk_mb'], '.0f')} | {r['mpix_per_s']:.1f} | "
            f"{r['mpix_per_s_per_band']:.2f} | {fmt(r.get('vcycle_mpix_per_s'), '.1f')} | "
            f"{fmt(r.get('speedup'), '.2f')}x | {r['check']} |")
    with open(f"{argv[3]}/scaling.md", "w") as f:
        f.write("\n".join(lines) + "\n")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
