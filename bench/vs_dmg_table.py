#!/usr/bin/env python3
"""Prints bench/vs_dmg.sh's table for one size from its work directory: one row per run, then
each figure's range over the runs and the gdp/DMG ratio of each interleaved pair (with their median
when there are several: on a shared machine one slow spell can spoil a single pair). gdp's peak MB is
its peak RSS plus its scratch held in memory (--stats scratch_memory_mb; memfds it never maps).

    bench/vs_dmg_table.py DIR SIZE RUNS
"""
import json
import os
import re
import statistics
import sys


def error_levels(path):
    """RMS error in 8-bit levels from `blend_layers error` ("... (x255: 1.234) ...")."""
    return float(re.search(r"x255: ([0-9.]+)", open(path).read()).group(1))


def load(d, tool, r):
    """One run's figures; DMG's are its server and client together."""
    parts = [f"{d}/gdp_{r}.json"] if tool == "gdp" else [f"{d}/dmg_server_{r}.json", f"{d}/dmg_client_{r}.json"]
    runs = [json.load(open(p)) for p in parts]
    out_bytes = int(open(f"{d}/{tool}_outbytes_{r}").read())
    written = sum(x["wchar"] for x in runs)
    disk = sum(x["write_bytes"] - x["cancelled_write_bytes"] for x in runs)
    # gdp's scratch in memory is memfd pages it never maps: not in its RSS, so added from --stats.
    stats = f"{d}/gdp_stats_{r}.json"
    in_memfd = float(json.load(open(stats))["scratch_memory_mb"]) if tool == "gdp" and os.path.exists(stats) else 0
    return {
        "wall": max(x["end"] for x in runs) - min(x["start"] for x in runs),
        "cpu": sum(x["user"] + x["sys"] for x in runs),
        "sys": sum(x["sys"] for x in runs),
        "peak": sum(x["peak_rss_kb"] for x in runs) / 1024.0 + in_memfd,
        "scratch": (written - out_bytes) / 1e9,
        "disk": max(disk - out_bytes, 0) / 1e9,
        "faults": sum(x["minor_faults"] for x in runs),
        "waits": sum(x["voluntary_switches"] for x in runs),
        "error": error_levels(f"{d}/{tool}_error_{r}"),
    }


COLUMNS = (("wall", "wall s", "{:.2f}"), ("cpu", "CPU s", "{:.2f}"), ("sys", "sys s", "{:.2f}"),
           ("peak", "peak MB", "{:.0f}"), ("scratch", "scratch GB", "{:.3f}"), ("disk", "disk GB", "{:.3f}"),
           ("faults", "minor faults", "{:.0f}"),
           ("waits", "voluntary switches", "{:.0f}"), ("error", "rms err (levels)", "{:.3f}"))


def span(values, fmt):
    lo, hi = min(values), max(values)
    return fmt.format(lo) if fmt.format(lo) == fmt.format(hi) else f"{fmt.format(lo)}-{fmt.format(hi)}"


def main(d, size, runs):
    rows = {tool: [load(d, tool, r) for r in range(1, runs + 1)] for tool in ("gdp", "dmg")}
    print(f"\n{size}x{size} stitch, {runs} interleaved run(s) each (CPU = user+sys; DMG = server + client);"
          f" load average now {os.getloadavg()[0]:.1f} on {os.cpu_count()} CPUs")
    print("| run | tool | " + " | ".join(c[1] for c in COLUMNS) + " |")
    print("|---" * (len(COLUMNS) + 2) + "|")
    for r in range(runs):
        for tool in ("gdp", "dmg"):
            cells = [fmt.format(rows[tool][r][key]) for key, _, fmt in COLUMNS]
            print(f"| {r + 1} | {'gdp' if tool == 'gdp' else 'DMG'} | " + " | ".join(cells) + " |")
    print("\n| figure | gdp | DMG | gdp/DMG (per pair) |")
    print("|---|---|---|---|")
    for key, name, fmt in COLUMNS:
        g, m = [x[key] for x in rows["gdp"]], [x[key] for x in rows["dmg"]]
        ratios = [a / b for a, b in zip(g, m) if float(fmt.format(b)) > 0]  # none against a zero as printed
        each = span(ratios, '{:.2f}x') if ratios else '-'
        if len(ratios) > 1:
            each += f" (median {statistics.median(ratios):.2f}x)"
        print(f"| {name} | {span(g, fmt)} | {span(m, fmt)} | {each} |")
    cg = [re.search(r"Server Conjugate Gradient: *([0-9.]+)", open(f"{d}/dmg_server_{r}.log").read())
          for r in range(1, runs + 1)]
    if all(cg):
        print(f"\nDMG's server, conjugate gradients on its coarsest level (its --verbose):"
              f" {span([float(m.group(1)) for m in cg], '{:.2f}')} s wall")
    stats = json.load(open(f"{d}/gdp_stats_1.json"))
    print(f"gdp's own count of its scratch: {float(stats['scratch_mb']) * 1048576 / 1e9:.3f} GB;"
          f" gdp against DMG (last pair): {error_levels(f'{d}/gdp_vs_dmg_error'):.3f} levels rms")


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2], int(sys.argv[3]))
