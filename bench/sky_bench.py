#!/usr/bin/python3
"""gdp sky against Montage on realistic plates with known truth (issue 18's acceptance; docs/sky.md).

Usage: bench/sky_bench.py --gdp build/tools/gdp/gdp --truth ../shared/data/equirect/stellarium/milkyway.png
                          [--out /tmp/sky-bench] [--nx 4 --ny 3 --size 100 --scale 0.15 --overlap 2]
The truth: a real all-sky map (equirectangular, column 0 at RA 180, RA growing to the left),
turned into one grey channel by `gdp convert`. Plates: nx x ny TAN plates of size x size pixels
of `scale` degrees, neighbours overlapping by `overlap` degrees, each the truth (bilinear) plus
its own smooth background (offset + plane + radial term, seeded). Both pipelines make a TAN
mosaic on the same template header; both and the uncorrected seamed mosaic (gdp --no-blend) are
compared with the truth on that grid after a 3x3 median filter: background rms (error's mean
removed) and seam visibility (99.9th percentile of the error's pixel-to-pixel step); the sky alone
through gdp --no-blend (no backgrounds) gives the resampling's own share. With --stars N, every
pipeline runs again on the plates with N Gaussian stars added (stars/): a star's flux is the aperture
sum of that result less the one without stars (for gdp on the same seams: --seams-from), against
the same sum of the star sampled on the target grid (see the comment at the star fluxes below and
docs/sky.md).
With --projected, gdp starts where Montage's background steps do: Montage's projdir (mProjExec's
images on the template, with their area images) goes to `gdp sky --projected`, beside mOverlaps,
mDiffExec, mFitExec, mBgModel, mBgExec and mAdd on the same directory, and beside mAdd alone (no
correction); mProjExec's time is shared and reported apart.
With --graphcut, gdp also runs with --seams graphcut (its result "gdp_gc.fits", compared and
timed beside the others; not with --stars' flux runs).
Needs Debian python3-astropy, python3-numpy and montage.
"""
import argparse
import glob
import os
import re
import shlex
import subprocess
import sys
import time

import numpy as np
from astropy.io import fits
from astropy.wcs import WCS

ap = argparse.ArgumentParser()
ap.add_argument("--gdp", required=True)
ap.add_argument("--truth", required=True)
ap.add_argument("--out", default="/tmp/sky-bench")
ap.add_argument("--nx", type=int, default=4)
ap.add_argument("--ny", type=int, default=3)
ap.add_argument("--size", type=int, default=100)
ap.add_argument("--scale", type=float, default=0.15)
ap.add_argument("--overlap", type=float, default=2.0)
ap.add_argument("--seed", type=int, default=18)
ap.add_argument("--ra0", type=float, default=0.0, help="centre of the mosaic (RA 0, Dec 0 crosses a PQ fold)")
ap.add_argument("--dec0", type=float, default=0.0)
ap.add_argument("--stars", type=int, default=0, help="Gaussian stars added to the truth: the flux check")
ap.add_argument("--projected", action="store_true", help="gdp sky --projected on Montage's projdir (mProjExec output)")
ap.add_argument("--graphcut", action="store_true", help="also gdp with --seams graphcut, compared beside the others")
ap.add_argument("--gdp-args", default="", help="more options for gdp sky (e.g. '--no-fit-backgrounds'; --projected too)")
args = ap.parse_args()
out = args.out
raw = os.path.join(out, "raw")
os.makedirs(raw, exist_ok=True)


def run(cmd, log):
    """Runs cmd under /usr/bin/time -v; returns (wall, user + sys, peak RSS MiB)."""
    t = time.time()
    r = subprocess.run(["/usr/bin/time", "-v"] + cmd, capture_output=True, text=True)
    wall = time.time() - t
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed:\n{r.stdout}\n{r.stderr}")
    cpu = sum(float(m) for m in re.findall(r"(?:User|System) time \(seconds\): ([\d.]+)", r.stderr))
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", r.stderr).group(1)) / 1024
    log.append((os.path.basename(cmd[0]), wall, cpu, rss))
    return r


# The truth map as one grey channel.
truth_fits = os.path.join(out, "truth.fits")
if not os.path.exists(truth_fits):
    run([args.gdp, "convert", args.truth, "-o", truth_fits, "--depth", "float", "--quiet"], [])
t = fits.getdata(truth_fits).astype(np.float64)
truth = t.mean(axis=0) if t.ndim == 3 else t
truth = truth[::-1]  # FITS rows bottom first -> image rows top down
H, W = truth.shape


def sky(ra, dec):
    """Bilinear truth at (RA, Dec) in degrees."""
    x = ((180.0 - ra) / 360.0 * W - 0.5) % W
    y = np.clip((90.0 - dec) / 180.0 * H - 0.5, 0, H - 1.001)
    x0, y0 = np.floor(x).astype(int), np.floor(y).astype(int)
    fx, fy = x - x0, y - y0
    x1 = (x0 + 1) % W
    return ((1 - fy) * ((1 - fx) * truth[y0, x0] + fx * truth[y0, x1]) +
            fy * ((1 - fx) * truth[y0 + 1, x0] + fx * truth[y0 + 1, x1]))


rng = np.random.default_rng(args.seed)
n, s = args.size, args.scale
step = n * s - args.overlap
centres = [(args.ra0 + (i - (args.nx - 1) / 2) * step / np.cos(np.radians(args.dec0)), args.dec0 + (j - (args.ny - 1) / 2) * step)
           for j in range(args.ny) for i in range(args.nx)]
# Stars: Gaussian profiles (sigma 1.5 plate pixels) at random places inside the mosaic, fluxes
# (integrals over the sphere, in value x square degrees) 5..20 plate pixel areas (peaks 0.35..1.4).
extent_x, extent_y = args.nx * step / 2 - 3 * s, args.ny * step / 2 - 3 * s
star_rng = np.random.default_rng(args.seed + 1)  # the backgrounds do not depend on --stars
star_ra = args.ra0 + star_rng.uniform(-extent_x, extent_x, args.stars) / np.cos(np.radians(args.dec0))
star_dec = args.dec0 + star_rng.uniform(-extent_y, extent_y, args.stars)
star_flux = star_rng.uniform(5.0, 20.0, args.stars) * s * s
sigma = 1.5 * s


def stars(ra, dec):
    out = np.zeros_like(np.asarray(ra, dtype=np.float64))
    for a, d, f in zip(star_ra, star_dec, star_flux):
        da = ((ra - a + 180.0) % 360.0 - 180.0) * np.cos(np.radians(d))
        out += f / (2 * np.pi * sigma * sigma) * np.exp(-((da ** 2 + (dec - d) ** 2) / (2 * sigma * sigma)))
    return out


# Plate sets: raw/ the sky plus each plate's background (what the figures are measured on),
# raw_truth/ the sky alone (the resampling's own error), raw_stars/ raw/ plus the stars (--stars).
true_backgrounds = []
sets = {"raw": True, "raw_truth": False} | ({"raw_stars": True} if args.stars else {})
for d in sets:
    os.makedirs(os.path.join(out, d), exist_ok=True)
for k, (ra, dec) in enumerate(centres):
    h = fits.Header()
    for key, v in [("CTYPE1", "RA---TAN"), ("CTYPE2", "DEC--TAN"), ("CRVAL1", ra % 360.0), ("CRVAL2", dec),
                   ("CRPIX1", (n + 1) / 2), ("CRPIX2", (n + 1) / 2), ("CDELT1", -s), ("CDELT2", s),
                   ("CUNIT1", "deg"), ("CUNIT2", "deg")]:
        h[key] = v
    w = WCS(h)
    yy, xx = np.mgrid[0:n, 0:n]  # FITS order: row 0 is the bottom
    ra_p, dec_p = w.all_pix2world(xx + 1.0, yy + 1.0, 1)
    u, v = (xx - n / 2) / n, (yy - n / 2) / n
    a, b, c, d = rng.uniform(-0.1, 0.1), rng.uniform(-0.05, 0.05), rng.uniform(-0.05, 0.05), rng.uniform(-0.1, 0.1)
    background = a + b * u + c * v + d * (u * u + v * v)
    true_backgrounds.append((a, b, c, d))
    for name, with_background in sets.items():
        data = sky(ra_p, dec_p) + (background if with_background else 0.0) + (stars(ra_p, dec_p) if name == "raw_stars" else 0.0)
        fits.PrimaryHDU(data.astype(np.float32), h).writeto(os.path.join(out, name, f"plate{k:02d}.fits"), overwrite=True)

# The template: TAN over the plates' extent.
mw = int(round((args.nx * step + args.overlap) / s))
mh = int(round((args.ny * step + args.overlap) / s))
hdr = os.path.join(out, "region.hdr")
with open(hdr, "w") as f:
    f.write("\n".join([
        "SIMPLE  = T", "BITPIX  = -64", "NAXIS   = 2", f"NAXIS1  = {mw}", f"NAXIS2  = {mh}",
        "CTYPE1  = 'RA---TAN'", "CTYPE2  = 'DEC--TAN'", f"CRVAL1  = {args.ra0}", f"CRVAL2  = {args.dec0}",
        f"CRPIX1  = {(mw + 1) / 2}", f"CRPIX2  = {(mh + 1) / 2}", f"CDELT1  = {-s}", f"CDELT2  = {s}",
        "CUNIT1  = 'deg'", "CUNIT2  = 'deg'", "END"]) + "\n")
target = WCS(fits.Header.fromtextfile(hdr))
yy, xx = np.mgrid[0:mh, 0:mw]
ra_t, dec_t = target.all_pix2world(xx + 1.0, yy + 1.0, 1)
truth_t = sky(ra_t % 360.0, dec_t)
np.save(os.path.join(out, "truth_t.npy"), truth_t)  # FITS row order, for looking at error maps


def pipelines(raw, base):
    """Runs gdp, the uncorrected mosaic and Montage on the plates in raw/, results and Montage's
    directories in base/; returns the logs (gdp, seamed, montage, shared mProjExec)."""
    m = lambda *p: os.path.join(base, *p)
    for d in ("proj", "diff", "corr"):
        os.makedirs(m(d), exist_ok=True)
    plates = sorted(os.path.join(raw, p) for p in os.listdir(raw))
    project = [["mImgtbl", raw, m("images.tbl")],
               ["mProjExec", "-q", "-p", raw, m("images.tbl"), hdr, m("proj"), m("stats.tbl")]]
    background = [["mImgtbl", m("proj"), m("pimages.tbl")],
                  ["mOverlaps", m("pimages.tbl"), m("diffs.tbl")],
                  ["mDiffExec", "-p", m("proj"), m("diffs.tbl"), hdr, m("diff")],
                  ["mFitExec", m("diffs.tbl"), m("fits.tbl"), m("diff")],
                  ["mBgModel", m("pimages.tbl"), m("fits.tbl"), m("corrections.tbl")],
                  ["mBgExec", "-p", m("proj"), m("pimages.tbl"), m("corrections.tbl"), m("corr")],
                  # mImgtbl writes absolute file names when given an absolute directory, and mAdd then
                  # reads those, not -p's: the corrected images need a table of their own.
                  ["mImgtbl", m("corr"), m("cimages.tbl")],
                  ["mAdd", "-e", "-p", m("corr"), m("cimages.tbl"), hdr, m("montage.fits")]]
    gdp_log, seamed_log, montage_log, project_log = [], [], [], []
    if args.graphcut and base == out:
        more = ["--projected", m("proj")] if args.projected else plates
        if args.projected:
            run(project[0], project_log)
            run(project[1], project_log)
        run([args.gdp, "sky", *more, "--header", hdr, "-o", m("gdp_gc.fits"), "--tolerance", "1e-4", "--quiet",
             "--seams", "graphcut", *shlex.split(args.gdp_args)], graphcut_log)
        project = project if not args.projected else []
    if args.projected:
        # Both start from mProjExec's directory; "mAdd only" co-adds it uncorrected.
        for cmd in project:
            run(cmd, project_log)
        run([args.gdp, "sky", "--projected", m("proj"), "--header", hdr, "-o", m("gdp.fits"), "--tolerance", "1e-4",
             "--quiet", *shlex.split(args.gdp_args)], gdp_log)
        for cmd in background:
            run(cmd, montage_log)
        run(["mAdd", "-e", "-p", m("proj"), m("pimages.tbl"), hdr, m("seamed.fits")], seamed_log)
    else:
        r = run([args.gdp, "sky", *plates, "--header", hdr, "-o", m("gdp.fits"), "--tolerance", "1e-4", "--verbose",
                 *shlex.split(args.gdp_args)], gdp_log)
        fitted.setdefault(raw, r.stderr)
        run([args.gdp, "sky", *plates, "--header", hdr, "-o", m("seamed.fits"), "--no-blend", "--quiet"], seamed_log)
        for cmd in project + background:
            run(cmd, montage_log)
    return gdp_log, seamed_log, montage_log, project_log


graphcut_log = []  # gdp --seams graphcut's run (--graphcut)
fitted = {}  # gdp's notes (its fitted backgrounds with --fit-backgrounds) per plate set
m = lambda *p: os.path.join(out, *p)
gdp_log, seamed_log, montage_log, project_log = pipelines(m("raw"), out)
if args.projected:
    os.makedirs(m("proj_truth"), exist_ok=True)
    for cmd in (["mImgtbl", m("raw_truth"), m("timages.tbl")],
                ["mProjExec", "-q", "-p", m("raw_truth"), m("timages.tbl"), hdr, m("proj_truth"), m("tstats.tbl")],
                ["mImgtbl", m("proj_truth"), m("ptimages.tbl")],
                ["mAdd", "-e", "-p", m("proj_truth"), m("ptimages.tbl"), hdr, m("truth_proj.fits")],
                [args.gdp, "sky", "--projected", m("proj_truth"), "--header", hdr, "-o", m("truth_gdp.fits"),
                 "--tolerance", "1e-4", "--quiet", *shlex.split(args.gdp_args)]):
        run(cmd, [])
    if args.graphcut:  # the truth through the graph cut's own seams
        run([args.gdp, "sky", "--projected", m("proj_truth"), "--header", hdr, "-o", m("truth_gdp_gc.fits"),
             "--tolerance", "1e-4", "--quiet", "--seams", "graphcut", *shlex.split(args.gdp_args)], [])
    names = {"gdp": "gdp --projected", "montage": "Montage bg+add", "seamed": "mAdd only"}
    if args.graphcut:
        names["gdp_gc"] = "gdp --projected --seams graphcut"
else:
    # The sky alone through gdp's resampling (plate -> PQ -> target): the seam measure's floor.
    run([args.gdp, "sky", *sorted(glob.glob(m("raw_truth", "*.fits"))), "--header", hdr, "-o", m("floor.fits"),
         "--no-blend", "--quiet"], [])
    names = {"gdp": "gdp sky", "montage": "Montage", "seamed": "gdp --no-blend", "floor": "sky alone, gdp --no-blend"}
    if args.graphcut:
        names["gdp_gc"] = "gdp sky --seams graphcut"
if args.stars:
    os.makedirs(m("stars"), exist_ok=True)
    pipelines(m("raw_stars"), m("stars"))
    if not args.projected:
        # gdp's seams go around the stars: its star-free reference takes the seams of the plates with
        # stars (--seams-from), so that the difference is the stars, not a moved seam.
        star_plates = sorted(glob.glob(m("raw_stars", "*.fits")))
        for name, extra in (("gdp", ["--tolerance", "1e-4"]), ("seamed", ["--no-blend"])):
            run([args.gdp, "sky", *sorted(glob.glob(m("raw", "*.fits"))), "--header", hdr, "-o", m("stars", name + "_ref.fits"),
                 *extra, "--quiet", "--seams-from", *star_plates], [])


# gdp's fitted backgrounds against the true ones, on each plate's pixels, each model's mean over
# the plate removed: what the fit got wrong, plate by plate (a part common to all plates is what
# overlaps cannot see); with --stars also the fit on the plates with stars (the robust fit's test:
# stars in the overlaps should not move it).
def fit_errors(raw):
    notes = re.findall(r"plate(\d+)\.fits: background fitted: offset \S+, slope u (\S+), slope v (\S+), radial (\S+)",
                       fitted.get(raw, ""))
    yy, xx = np.mgrid[0:n, 0:n]
    u, v = (xx - n / 2) / n, (yy - n / 2) / n
    ug, vg = u + 0.5 / n, -v - 0.5 / n  # gdp's pixel coordinates: rows top down, pixel centres at +0.5
    rows = {}
    for k, su, sv, rad in notes:
        a, b, c, d = true_backgrounds[int(k)]
        su, sv, rad = float(su), float(sv), float(rad)
        diff = (su * ug + sv * vg + rad * (ug * ug + vg * vg)) - (b * u + c * v + d * (u * u + v * v))
        rows[int(k)] = ((b, c, d), (su, -sv, rad), np.std(diff))
    return rows


errors, star_errors = fit_errors(m("raw")), fit_errors(m("raw_stars"))
if errors:
    print("plate  true: plane u, v, radial   fitted (same axes): plane u, v, radial   rms(fitted - true)" +
          ("   with stars" if star_errors else ""))
    for k, (t, f, e) in sorted(errors.items()):
        extra = f"   {star_errors[k][2]:.4f}" if k in star_errors else ""
        print(f"  {k:3d}  {t[0]:+.4f} {t[1]:+.4f} {t[2]:+.4f}   {f[0]:+.4f} {f[1]:+.4f} {f[2]:+.4f}   {e:.4f}{extra}")
    print(f"  mean rms(fitted - true): {np.mean([e[2] for e in errors.values()]):.4f}" +
          (f", with stars {np.mean([e[2] for e in star_errors.values()]):.4f}" if star_errors else ""))


def median3(a):
    p = np.pad(a, 1, constant_values=np.nan)
    win = np.lib.stride_tricks.sliding_window_view(p, (3, 3))
    with np.errstate(all="ignore"):
        import warnings
        with warnings.catch_warnings():
            warnings.simplefilter("ignore")
            return np.nanmedian(win.reshape(a.shape + (9,)), axis=-1)


def rows_top_down(path):
    return fits.getdata(path).astype(np.float64)[::-1]


results = {name: rows_top_down(m(name + ".fits")) for name in names}
valid = np.isfinite(truth_t[::-1])
for r in results.values():
    valid &= np.isfinite(r)
print(f"{len(centres)} plates of {n}x{n} at {s} deg, {args.overlap} deg overlaps; mosaic {mw}x{mh} TAN; "
      f"{valid.mean():.1%} of it compared")
# --projected: also against the truth as Montage's projection and each pipeline's co-addition
# give it (gdp's seams on the truth's projdir; mAdd's mean of overlapping images): the same
# resampling and compositing as the result, which leaves only the background correction.
truths = [("the truth", {name: truth_t[::-1] for name in results})]
if args.projected:
    added = rows_top_down(m("truth_proj.fits"))
    truths.append(("the truth through mProjExec -q and the same co-addition",
                   {"gdp": rows_top_down(m("truth_gdp.fits")), "montage": added, "seamed": added,
                    "gdp_gc": rows_top_down(m("truth_gdp_gc.fits")) if args.graphcut else None}))
for label, truth_of in truths:
    print(f"{'against ' + label:56s} {'bg rms':>9s} {'seam p99.9':>11s}")
    for name, r in results.items():
        e = median3(r) - median3(truth_of[name])
        e[~valid] = np.nan
        e -= np.nanmean(e)
        steps = np.concatenate([np.abs(np.diff(e, axis=1)).ravel(), np.abs(np.diff(e, axis=0)).ravel()])
        steps = steps[np.isfinite(steps)]
        print(f"  {names[name]:54s} {np.sqrt(np.nanmean(e * e)):9.4f} {np.percentile(steps, 99.9):11.4f}")
# Star fluxes. Each pipeline also ran on the plates with stars added (stars/); its image of the
# stars is that result less the one without them, so neither the sky's structure under a star nor
# the background correction's error enters the flux (the pipelines are linear in the data, up to
# what the stars move Montage's plane fits and gdp's plate levels). Flux: the sum over the target
# pixels within 6.5 pixels (4.3 sigma) of the star, less the median of the pixels 9 or more (6 sigma) pixels
# out (beyond the star: a border at 4 sigma sits on its wings, which resampling widens: +8e-4); the
# truth: the same sum of the stars alone sampled at the target pixel centres (a sum of a sampled
# Gaussian of sigma >= 1 pixel is its integral to 1e-8; an interpolation kernel that sums to 1 keeps it).
# Against the truth: resampling and correction together; gdp against gdp --no-blend: the solve's
# own change to the star (the same resampling on both sides).
sx, sy = target.all_world2pix(star_ra % 360.0, star_dec, 0)
sx, sy = np.round(sx).astype(int), np.round(sy).astype(int)


ry, rx = np.mgrid[-12:13, -12:13]
radius = np.hypot(rx, ry)


def fluxes(img):  # img in FITS order (row 0 at the bottom), as the world2pix positions
    f = []
    for x, y in zip(sx, sy):
        box = img[y - 12:y + 13, x - 12:x + 13] if y >= 12 and x >= 12 else np.zeros((0, 0))
        if box.shape != (25, 25) or not np.all(np.isfinite(box)):
            f.append(np.nan)
            continue
        f.append(np.sum(box[radius <= 6.5] - np.median(box[radius >= 9])))
    return np.array(f)


def star_image(name):  # FITS order
    ref = m("stars", name + "_ref.fits")
    return (rows_top_down(m("stars", name + ".fits")) - (rows_top_down(ref) if os.path.exists(ref) else results[name]))[::-1]


if args.stars:
    truth_flux = fluxes(stars(ra_t, dec_t))
    print(f"star fluxes ({args.stars} stars): relative error of the aperture flux: median, median |.|, worst |.|")
    compared = [(names[k], fluxes(star_image(k)), truth_flux) for k in ("gdp", "montage", "seamed")]
    if not args.projected:
        compared.append(("gdp sky against gdp --no-blend", fluxes(star_image("gdp")), fluxes(star_image("seamed"))))
    for label, f, ref in compared:
        rel = f / ref - 1.0
        rel = rel[np.isfinite(rel)]
        print(f"  {label:32s} {np.median(rel):+.2e} {np.median(np.abs(rel)):.2e} {np.max(np.abs(rel)):.2e} "
              f"({len(rel)} stars)")
logs = [(names["gdp"], gdp_log), (names["seamed"], seamed_log), (names["montage"], montage_log)]
if args.graphcut:
    logs.append((names["gdp_gc"], graphcut_log))
for name, log in logs + ([("mProjExec (shared)", project_log)] if args.projected else []):
    wall, cpu, rss = sum(x[1] for x in log), sum(x[2] for x in log), max(x[3] for x in log)
    print(f"{name:18s} wall {wall:6.2f} s  cpu {cpu:6.2f} s  peak {rss:6.1f} MiB  ({len(log)} command(s))")
