#!/usr/bin/python3
"""gdp sky's peak memory against the number of plates and the PQ's height (issue 18: "memory bounded
by the PQ width and the plates crossing the current rows"; docs/sky.md, "Memory").

Usage: bench/sky_memory_bench.py --gdp build/tools/gdp/gdp [--out /tmp/sky-mem] [--configs 4x3,4x12]
                                 [--size 100] [--scale 0.04] [--memory 0] [--gdp-args '...']
Each configuration NXxNY is a grid of NX x NY overlapping TAN plates (--size pixels of --scale
degrees, 0.5 degree overlaps) around RA 90, Dec 30: a synthetic sky (smooth waves and Gaussian
stars, so no data files are needed) plus a different smooth background per plate. 4x3 and 4x12
have the same width and the second is four times taller: the PQ window is as wide (nearly: TOAST's
rows are not parallels) and has more rows. gdp sky runs on each under bench/measure_run.py with
--stats; printed per run: plates, PQ window, peak RSS, wall, CPU (user + sys), the solver's scratch
in memory. --memory 0 (the default here) keeps the solver's scratch in files, so what is left is
what gdp sky itself holds; --memory '' leaves the solver's default (a quarter of physical memory).
--mpirun N runs gdp sky under `mpirun -np N` (CPU seconds are then every rank's); the line then
ends with the plate pixels each rank read (--stats plate_pixels_read) against the plates' own.
Needs python3-numpy and python3-astropy.
"""
import argparse
import json
import os
import shutil
import subprocess
import sys

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS


ap = argparse.ArgumentParser()
ap.add_argument("--gdp", required=True)
ap.add_argument("--out", default="/tmp/sky-mem")
ap.add_argument("--configs", default="4x3,4x12")
ap.add_argument("--size", type=int, default=100)
ap.add_argument("--scale", type=float, default=0.04)
ap.add_argument("--overlap", type=float, default=0.5)
ap.add_argument("--ra0", type=float, default=90.0)
ap.add_argument("--dec0", type=float, default=30.0)
ap.add_argument("--memory", default="0", help="gdp's --memory ('' for its default)")
ap.add_argument("--gdp-args", default="", help="more options for gdp sky")
ap.add_argument("--keep", action="store_true", help="keep the plates and outputs")
ap.add_argument("--mpirun", type=int, default=0, help="run gdp under mpirun -np N (N ranks)")
ap.add_argument("--plates-only", action="store_true", help="write the plates (and region.hdr) and stop")
args = ap.parse_args()


def sky(ra, dec):
    """A smooth synthetic sky with a few hundred point-like stars (fixed seed)."""
    a, d = np.radians(ra), np.radians(dec)
    x, y, z = np.cos(d) * np.cos(a), np.cos(d) * np.sin(a), np.sin(d)
    v = 0.5 + 0.2 * np.sin(9 * x + 3 * y) * np.cos(7 * z) + 0.1 * np.sin(23 * y - 11 * z)
    rng = np.random.default_rng(7)
    sr = rng.uniform(args.ra0 - 20, args.ra0 + 20, 400)
    sd = rng.uniform(args.dec0 - 40, args.dec0 + 40, 400)
    sigma = 1.5 * args.scale
    for r0, d0 in zip(sr, sd):
        near = (np.abs(dec - d0) < 6 * sigma) & (np.abs(ra - r0) * np.cos(np.radians(d0)) < 6 * sigma)
        if near.any():
            da = (ra[near] - r0) * np.cos(np.radians(d0))
            v[near] += 0.8 * np.exp(-(da ** 2 + (dec[near] - d0) ** 2) / (2 * sigma * sigma))
    return v


def make_plates(nx, ny, d):
    os.makedirs(d, exist_ok=True)
    n, s = args.size, args.scale
    step = n * s - args.overlap
    rng = np.random.default_rng(18)
    for j in range(ny):
        for i in range(nx):
            dec = args.dec0 + (j - (ny - 1) / 2) * step
            ra = args.ra0 + (i - (nx - 1) / 2) * step / np.cos(np.radians(dec))
            h = fits.Header()
            for key, v in [("CTYPE1", "RA---TAN"), ("CTYPE2", "DEC--TAN"), ("CRVAL1", ra % 360.0), ("CRVAL2", dec),
                           ("CRPIX1", (n + 1) / 2), ("CRPIX2", (n + 1) / 2), ("CDELT1", -s), ("CDELT2", s)]:
                h[key] = v
            yy, xx = np.mgrid[0:n, 0:n]
            ra_p, dec_p = WCS(h).all_pix2world(xx + 1.0, yy + 1.0, 1)
            u, v = (xx - n / 2) / n, (yy - n / 2) / n
            b = rng.uniform(-0.1, 0.1) + rng.uniform(-0.05, 0.05) * u + rng.uniform(-0.05, 0.05) * v
            fits.PrimaryHDU((sky(ra_p, dec_p) + b).astype(np.float32), h).writeto(
                os.path.join(d, f"plate{j * nx + i:03d}.fits"), overwrite=True)
    # The target: TAN over the mosaic at the plates' scale.
    w, hgt = int(round(nx * step / s)), int(round(ny * step / s))
    with open(os.path.join(d, "region.hdr"), "w") as f:
        for key, v in [("SIMPLE", "T"), ("BITPIX", "-32"), ("NAXIS", "2"), ("NAXIS1", w), ("NAXIS2", hgt),
                       ("CTYPE1", "'RA---TAN'"), ("CTYPE2", "'DEC--TAN'"), ("CRVAL1", args.ra0), ("CRVAL2", args.dec0),
                       ("CRPIX1", (w + 1) / 2), ("CRPIX2", (hgt + 1) / 2), ("CDELT1", -s), ("CDELT2", s)]:
            f.write(f"{key:8s}= {v}\n")
        f.write("END\n")


def run(cmd, record):
    """Wall, CPU (user + sys) seconds and peak RSS (MiB) of cmd, by bench/measure_run.py."""
    measure = os.path.join(os.path.dirname(os.path.abspath(__file__)), "measure_run.py")
    r = subprocess.run([sys.executable, measure, record, "--"] + cmd, capture_output=True, text=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stderr}")
    cost = json.load(open(record))
    return cost["wall"], cost["user"] + cost["sys"], cost["peak_rss_kb"] / 1024

print(f"{'plates':>7} {'PQ H':>6} {'window':>13} {'peak RSS MiB':>12} {'wall s':>7} {'CPU s':>6} {'scratch MiB':>11}")
for config in args.configs.split(","):
    nx, ny = (int(v) for v in config.split("x"))
    d = os.path.join(args.out, config)
    if not os.path.exists(os.path.join(d, "region.hdr")):
        make_plates(nx, ny, d)
    if args.plates_only:
        continue
    plates = sorted(os.path.join(d, f) for f in os.listdir(d) if f.endswith(".fits") and f.startswith("plate"))
    stats = os.path.join(d, "stats.json")
    mpi = ["mpirun", "--oversubscribe", "--allow-run-as-root", "-np", str(args.mpirun)] if args.mpirun else []
    cmd = mpi + [args.gdp, "sky", "-q", "--header", os.path.join(d, "region.hdr"), "-o", os.path.join(d, "out.fits"),
           "--stats", stats] + (["--memory", args.memory] if args.memory else []) + args.gdp_args.split() + plates
    wall, cpu, rss = run(cmd, os.path.join(d, "run.json"))
    s = json.load(open(stats))
    win = s.get("pq_window", "")
    print(f"{len(plates):>7} {s.get('pq_height', '?'):>6} {str(win):>13} {rss:>12.1f} {wall:>7.2f} {cpu:>6.2f} "
          f"{float(s.get('scratch_memory_mb', 0)):>11.1f}  plate pixels read {s.get('plate_pixels_read')} "
          f"of {s.get('plate_pixels_in_files')}", flush=True)
    if not args.keep:
        shutil.rmtree(d)
