#!/usr/bin/python3
"""gdp's pixel -> sky positions (tests/tools/wcs_probe.cc) against astropy's, within 0.1 pixel.

Usage: sky_astropy_test.py PATH/TO/gdp_wcs_probe tests/data/astro
Real files (tests/data/astro) and synthetic headers written here (CD and PC + CDELT, rotation,
SIP and TPV distortions, several projections, galactic axes). Also checks pixel values and
orientation (gdp's row y is FITS row NAXIS2 - y). Exit 77 (skipped) without astropy.
"""
import math
import os
import subprocess
import sys
import tempfile
import warnings

try:
    import numpy as np
    from astropy.io import fits
    from astropy.wcs import WCS, FITSFixedWarning
except ImportError:
    print("astropy not available (Debian python3-astropy): skipped")
    sys.exit(77)

warnings.simplefilter("ignore", FITSFixedWarning)
probe, data = sys.argv[1], sys.argv[2]
failures = []


def run_probe(path):
    out = subprocess.run([probe, path], capture_output=True, text=True)
    if out.returncode != 0:
        failures.append(f"{path}: probe failed: {out.stderr.strip()}")
        return None, [], []
    size, pix, val = None, [], []
    for line in out.stdout.splitlines():
        f = line.split()
        if f[0] == "size":
            size = (int(f[1]), int(f[2]))
        elif f[0] == "pix":
            pix.append(tuple(map(float, f[1:])))
        else:
            val.append((int(f[1]), int(f[2]), float(f[3])))
    return size, pix, val


def separation(lon1, lat1, lon2, lat2):
    a1, d1, a2, d2 = map(math.radians, (lon1, lat1, lon2, lat2))
    c = math.sin(d1) * math.sin(d2) + math.cos(d1) * math.cos(d2) * math.cos(a1 - a2)
    s = math.hypot(math.cos(d2) * math.sin(a2 - a1),
                   math.cos(d1) * math.sin(d2) - math.sin(d1) * math.cos(d2) * math.cos(a2 - a1))
    return math.degrees(math.atan2(s, c))


def check(name, path, header, data_array=None):
    size, pix, val = run_probe(path)
    if size is None:
        return
    w, h = size
    wcs = WCS(header, naxis=2)
    scale = min(abs(float(getattr(s, "value", s))) for s in wcs.proj_plane_pixel_scales())  # degrees
    worst = 0.0
    seen = set()
    for x, y, lon, lat in pix:
        seen.add((round(x, 4), round(y, 4)))
        ra, dec = wcs.all_pix2world([[x + 0.5, h + 0.5 - y]], 1)[0]
        if not (np.isfinite(ra) and np.isfinite(dec)):
            failures.append(f"{name}: gdp has a position at ({x}, {y}), astropy none")
            continue
        worst = max(worst, separation(lon, lat, ra, dec) / scale)
    # Points gdp leaves out must have no position in astropy either.
    for a in range(9):
        for b in range(9):
            x, y = w * a / 8.0 + 0.13 * (a % 3), h * b / 8.0 + 0.29 * (b % 2)
            if (round(x, 4), round(y, 4)) in seen:
                continue
            ra, dec = wcs.all_pix2world([[x + 0.5, h + 0.5 - y]], 1)[0]
            if np.isfinite(ra) and np.isfinite(dec):
                failures.append(f"{name}: no gdp position at ({x}, {y}), astropy has ({ra}, {dec})")
    print(f"{name}: {len(pix)} points, worst {worst:.2e} pixel")
    if worst > 0.1:
        failures.append(f"{name}: positions differ by {worst} pixel (> 0.1)")
    if data_array is not None:
        for i, j, v in val:
            want = data_array[h - 1 - j, i]
            if not ((np.isnan(want) and math.isnan(v)) or abs(float(want) - v) <= 1e-6 * max(1.0, abs(float(want)))):
                failures.append(f"{name}: pixel ({i}, {j}) is {v}, astropy reads {want}")


def hdr_text(cards):
    value = lambda v: f"{v:.12E}" if isinstance(v, float) else str(v)
    return "\n".join(f"{k:<8}= {value(v)}" for k, v in cards) + "\nEND\n"


# Real files: a primary image (PC + CDELT after cropping) and an image extension with blanks.
for name in ("wcs512_crop.fits.gz", "herschel_spire_crop.fits.gz"):
    path = os.path.join(data, name)
    with fits.open(path) as hdus:
        hdu = next(x for x in hdus if x.data is not None)
        check(name, path, hdu.header, np.asarray(hdu.data, dtype=np.float64))

with tempfile.TemporaryDirectory() as tmp:
    # The Gemini header (rotated PC matrix) as a template for an image of 1280 x 874.
    gemini = fits.getheader(os.path.join(data, "geminiann11015a_wcs.fits"))
    gemini["NAXIS"] = 2
    gemini["NAXIS1"] = 1280
    gemini["NAXIS2"] = 874
    path = os.path.join(tmp, "gemini.hdr")
    with open(path, "w") as f:
        f.write("\n".join(c.image.rstrip() for c in gemini.cards) + "\nEND\n")
    check("geminiann11015a_wcs.fits", path, gemini)

    base = [("NAXIS", 2), ("NAXIS1", 300), ("NAXIS2", 200)]
    cases = {
        "CD rotated TAN": [("CTYPE1", "'RA---TAN'"), ("CTYPE2", "'DEC--TAN'"), ("CRVAL1", 83.6), ("CRVAL2", 22.0),
                           ("CRPIX1", 140.5), ("CRPIX2", 90.25), ("CD1_1", -2.1e-4), ("CD1_2", 0.6e-4),
                           ("CD2_1", 0.5e-4), ("CD2_2", 2.0e-4)],
        "TAN-SIP": [("CTYPE1", "'RA---TAN-SIP'"), ("CTYPE2", "'DEC--TAN-SIP'"), ("CRVAL1", 10.0), ("CRVAL2", 41.0),
                    ("CRPIX1", 150.0), ("CRPIX2", 100.0), ("CD1_1", -1e-3), ("CD1_2", 1e-5), ("CD2_1", 0.0),
                    ("CD2_2", 1e-3), ("A_ORDER", 2), ("B_ORDER", 2), ("A_2_0", 2e-5), ("A_1_1", -1e-5),
                    ("A_0_2", 3e-6), ("B_2_0", -1e-6), ("B_1_1", 2e-5), ("B_0_2", 1e-5)],
        "TPV": [("CTYPE1", "'RA---TPV'"), ("CTYPE2", "'DEC--TPV'"), ("CRVAL1", 150.1), ("CRVAL2", 2.2),
                ("CRPIX1", 150.0), ("CRPIX2", 100.0), ("CD1_1", -7e-5), ("CD1_2", 0.0), ("CD2_1", 0.0),
                ("CD2_2", 7e-5), ("PV1_0", 0.0), ("PV1_1", 1.0), ("PV1_2", 0.0), ("PV1_4", 0.002),
                ("PV1_7", 0.05), ("PV2_0", 0.0), ("PV2_1", 1.0), ("PV2_2", 0.0), ("PV2_5", -0.003)],
        "ZEA south pole": [("CTYPE1", "'RA---ZEA'"), ("CTYPE2", "'DEC--ZEA'"), ("CRVAL1", 0.0), ("CRVAL2", -90.0),
                           ("CRPIX1", 150.5), ("CRPIX2", 100.5), ("CDELT1", -0.2), ("CDELT2", 0.2)],
        "SIN": [("CTYPE1", "'RA---SIN'"), ("CTYPE2", "'DEC--SIN'"), ("CRVAL1", 200.0), ("CRVAL2", 60.0),
                ("CRPIX1", 150.5), ("CRPIX2", 100.5), ("CDELT1", -0.3), ("CDELT2", 0.3)],
        "AIT all-sky": [("CTYPE1", "'RA---AIT'"), ("CTYPE2", "'DEC--AIT'"), ("CRVAL1", 180.0), ("CRVAL2", 0.0),
                        ("CRPIX1", 150.5), ("CRPIX2", 100.5), ("CDELT1", -1.2), ("CDELT2", 1.2)],
        "galactic CAR": [("CTYPE1", "'GLON-CAR'"), ("CTYPE2", "'GLAT-CAR'"), ("CRVAL1", 0.0), ("CRVAL2", 0.0),
                         ("CRPIX1", 150.5), ("CRPIX2", 100.5), ("CDELT1", -1.2), ("CDELT2", 0.9)],
        "STG PC": [("CTYPE1", "'RA---STG'"), ("CTYPE2", "'DEC--STG'"), ("CRVAL1", 30.0), ("CRVAL2", 10.0),
                   ("CRPIX1", 10.0), ("CRPIX2", 190.0), ("CDELT1", -0.01), ("CDELT2", 0.01),
                   ("PC1_1", 0.8), ("PC1_2", -0.6), ("PC2_1", 0.6), ("PC2_2", 0.8)],
    }
    for name, cards in cases.items():
        path = os.path.join(tmp, name.replace(" ", "_") + ".hdr")
        with open(path, "w") as f:
            f.write(hdr_text(base + cards))
        check(name, path, fits.Header.fromstring(hdr_text(base + cards), sep="\n"))

if failures:
    print("\n".join(failures))
    sys.exit(1)
print("all positions within 0.1 pixel of astropy's")
