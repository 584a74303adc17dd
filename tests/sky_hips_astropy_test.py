#!/usr/bin/python3
"""gdp sky --hips read by astropy: Moc.fits is an IVOA MOC whose cells are the tiles written, tiles are FITS images.

Usage: sky_hips_astropy_test.py PATH/TO/gdp
Writes a TAN plate, runs gdp sky --hips with small tiles, and reads the HiPS back with astropy
(the tiles' pixel directions are checked against HEALPix in tests/sky_hips_test.cc).
Exit 77 (skipped) without astropy.
"""
import os
import re
import subprocess
import sys
import tempfile

try:
    import numpy as np
    from astropy.io import fits
except ImportError:
    print("astropy not available (Debian python3-astropy): skipped")
    sys.exit(77)

gdp = sys.argv[1]
failures = []


def check(ok, message):
    if not ok:
        failures.append(message)


with tempfile.TemporaryDirectory() as tmp:
    n = 40
    y, x = np.mgrid[0:n, 0:n]
    header = fits.Header()
    for key, value in [("CTYPE1", "RA---TAN"), ("CTYPE2", "DEC--TAN"), ("CRVAL1", 210.0), ("CRVAL2", 20.0),
                       ("CRPIX1", 20.5), ("CRPIX2", 20.5), ("CDELT1", -0.4), ("CDELT2", 0.4)]:
        header[key] = value
    fits.writeto(os.path.join(tmp, "plate.fits"), (1.0 + 0.01 * x + 0.02 * y).astype(np.float32), header)
    hips = os.path.join(tmp, "hips")
    run = subprocess.run([gdp, "sky", os.path.join(tmp, "plate.fits"), "--center", "210,20", "--size", "20,20",
                          "--scale", "0.5", "-o", os.path.join(tmp, "out.fits"), "--hips", hips, "--hips-tile", "32",
                          "--pq-height", "128", "--quiet"], capture_output=True, text=True)
    if run.returncode != 0:
        print("gdp sky failed:", run.stderr)
        sys.exit(1)
    props = {}
    with open(os.path.join(hips, "properties"), encoding="utf-8") as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                key, value = line.split("=", 1)
                props[key.strip()] = value.strip()
    order, width = int(props["hips_order"]), int(props["hips_tile_width"])
    check(width == 32, f"hips_tile_width {width}")

    tiles = {}  # order -> npix set
    for root, _, names in os.walk(hips):
        for name in names:
            m = re.fullmatch(r"Npix(\d+)\.fits", name)
            if not m:
                continue
            k = int(re.search(r"Norder(\d+)", root).group(1))
            npix = int(m.group(1))
            check(os.path.basename(root) == f"Dir{npix // 10000 * 10000}", f"{root}/{name}: wrong Dir")
            tiles.setdefault(k, set()).add(npix)
            with fits.open(os.path.join(root, name)) as t:
                data = t[0].data
                check(data.shape == (width, width), f"{name}: shape {data.shape}")
                check(data.dtype.kind == "f" and t[0].header["BITPIX"] == -32, f"{name}: BITPIX {t[0].header['BITPIX']}")
                check(np.isfinite(data).any(), f"Norder{k}/{name}: written without data")
    check(sorted(tiles) == list(range(order + 1)), f"orders {sorted(tiles)} for hips_order {order}")

    with fits.open(os.path.join(hips, "Moc.fits")) as moc:
        table = moc[1]
        check(isinstance(table, fits.BinTableHDU), "Moc.fits: HDU 1 is not a binary table")
        h = table.header
        for key, value in [("PIXTYPE", "HEALPIX"), ("ORDERING", "NUNIQ"), ("COORDSYS", "C"), ("MOCORDER", order)]:
            check(h.get(key) == value, f"Moc.fits: {key} = {h.get(key)!r}, not {value!r}")
        uniq = np.asarray(table.data["UNIQ"], dtype=np.int64)
        check(np.all(np.diff(uniq) > 0), "Moc.fits: UNIQ not strictly increasing")
        covered = set()
        for u in uniq:
            k = (int(u).bit_length() - 3) // 2  # 4 * 4^k <= u < 16 * 4^k
            npix = int(u) - 4 * 4**k
            shift = 4 ** (order - k)
            covered.update(range(npix * shift, (npix + 1) * shift))
        check(covered == tiles.get(order, set()), f"Moc.fits covers {sorted(covered)}, tiles {sorted(tiles.get(order, []))}")

    allsky = os.path.join(hips, f"Norder{min(3, order)}", "Allsky.fits")
    with fits.open(allsky) as a:
        check(a[0].data.ndim == 2 and np.isfinite(a[0].data).any(), "Allsky.fits: no data")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"HiPS read by astropy: {sum(len(t) for t in tiles.values())} tiles, MOC of {len(uniq)} cells")
