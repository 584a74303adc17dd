#!/usr/bin/python3
"""gdp sky --hips and --projection HPX read by astropy and placed by astropy-healpix.

Usage: sky_hips_astropy_test.py PATH/TO/gdp
Writes TAN plates (equatorial and galactic), runs gdp sky --hips with small tiles (the galactic
one without -o: a HiPS alone) and --projection HPX, and reads them back with astropy: every FITS
tile 2-D, BITPIX -32, with data, in the right Dir; every order present; Moc.fits an IVOA MOC
whose cells are the deepest tiles (for the galactic HiPS: the ICRS cells of its pixels; MOC 1.1
is ICRS only); the properties keys HiPS 1.0 requires, hips_initial_ra/dec in ICRS (galactic too); Allsky readable. With astropy-healpix
(Debian python3-astropy-healpix; that part skipped without it), an implementation independent of
gdp's healpix_cxx: each plate pixel's value is found in the tile and tile pixel its HEALPix
nested index names, and every pixel of the HPX image is a HEALPix pixel centre (astropy's own
wcslib). With Aladin (Debian aladin), the CDS's HiPS builder lints both HiPS against IVOA HiPS
1.0 (`aladin -hipsgen in=DIR LINT`: no error, no Moc.fits warning, "compatible"). Exit 77 (skipped) without astropy.
"""
import os
import re
import shutil
import subprocess
import sys
import tempfile
import warnings

try:
    import numpy as np
    from astropy.io import fits
    from astropy.wcs import WCS, FITSFixedWarning
    from astropy.coordinates import SkyCoord
    import astropy.units as u
except ImportError:
    print("astropy not available (Debian python3-astropy): skipped")
    sys.exit(77)
try:
    from astropy_healpix import HEALPix
except ImportError:
    HEALPix = None
    print("astropy-healpix not available (Debian python3-astropy-healpix): tile positions not checked")

warnings.simplefilter("ignore", FITSFixedWarning)
gdp = sys.argv[1]
failures = []
REQUIRED = ["creator_did", "obs_title", "dataproduct_type", "hips_version", "hips_release_date", "hips_status",
            "hips_tile_format", "hips_order", "hips_frame"]


def check(ok, message):
    if not ok:
        failures.append(message)


def write_plate(path, lon, lat, galactic=False, n=40, step=0.4):
    """A TAN plate n x n of `step` degree pixels centred at (lon, lat), values 1 + 0.01 x + 0.02 y."""
    y, x = np.mgrid[0:n, 0:n]
    header = fits.Header()
    axes = ("GLON-TAN", "GLAT-TAN") if galactic else ("RA---TAN", "DEC--TAN")
    for key, value in [("CTYPE1", axes[0]), ("CTYPE2", axes[1]), ("CRVAL1", lon), ("CRVAL2", lat),
                       ("CRPIX1", (n + 1) / 2), ("CRPIX2", (n + 1) / 2), ("CDELT1", -step), ("CDELT2", step)]:
        header[key] = value
    data = (1.0 + 0.01 * x + 0.02 * y).astype(np.float32)
    fits.writeto(path, data, header)
    return data, WCS(header)


def run(args):
    r = subprocess.run([gdp, "sky", *args, "--quiet"], capture_output=True, text=True)
    if r.returncode != 0:
        print("gdp sky failed:", " ".join(args), r.stderr)
        sys.exit(1)


def read_properties(hips):
    props = {}
    with open(os.path.join(hips, "properties"), encoding="utf-8") as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                key, value = line.split("=", 1)
                props[key.strip()] = value.strip()
    for key in REQUIRED:
        check(key in props, f"{hips}/properties: no {key} (required by HiPS 1.0)")
    check(props.get("hips_version") == "1.4", f"hips_version {props.get('hips_version')}")
    check(props.get("dataproduct_type") == "image", f"dataproduct_type {props.get('dataproduct_type')}")
    check(set(props.get("hips_tile_format", "").split()) == {"png", "fits"}, "hips_tile_format")
    check(re.fullmatch(r"\d{4}-\d\d-\d\dT\d\d:\d\dZ", props.get("hips_release_date", "")) is not None,
          f"hips_release_date {props.get('hips_release_date')} (ISO 8601 YYYY-mm-ddTHH:MMZ)")
    return props


def moc_cells(hips, order):
    """Moc.fits's cells expanded to `order`."""
    with fits.open(os.path.join(hips, "Moc.fits")) as moc:
        uniq = np.asarray(moc[1].data["UNIQ"], dtype=np.int64)
    covered = set()
    for cell in uniq:
        k = (int(cell).bit_length() - 3) // 2  # 4 * 4^k <= u < 16 * 4^k
        npix = int(cell) - 4 * 4**k
        shift = 4 ** (order - k)
        covered.update(range(npix * shift, (npix + 1) * shift))
    return covered


def check_galactic_moc(hips, props):
    """A galactic HiPS's Moc.fits lists the ICRS cells holding its deepest tiles' finite pixel centres
    (astropy's galactic -> ICRS; its FK5 frame bias may move a pixel within 0.02 arcsec of a cell edge)."""
    order, width = int(props["hips_order"]), int(props["hips_tile_width"])
    shift = width.bit_length() - 1
    pixels, cells = HEALPix(nside=2 ** (order + shift), order="nested"), HEALPix(nside=2 ** order, order="nested")
    want = set()
    for root, _, names in os.walk(os.path.join(hips, f"Norder{order}")):
        for name in names:
            m = re.fullmatch(r"Npix(\d+)\.fits", name)
            if not m:
                continue
            with fits.open(os.path.join(root, name)) as t:
                data = t[0].data[::-1]  # rows top down: row r, column c
            r, c = np.nonzero(np.isfinite(data))
            sub = np.zeros(len(r), dtype=np.int64)
            for bit in range(shift):
                sub |= ((r >> bit) & 1) << (2 * bit) | ((c >> bit) & 1) << (2 * bit + 1)
            lon, lat = pixels.healpix_to_lonlat(int(m.group(1)) * width * width + sub)
            icrs = SkyCoord(lon, lat, frame="galactic").icrs
            want.update(cells.lonlat_to_healpix(icrs.ra, icrs.dec).tolist())
    got = moc_cells(hips, order)
    check(len(want ^ got) <= 2 and want & got, f"{hips}: ICRS MOC of {len(got)} cells, astropy finds {len(want)}, "
          f"{len(want ^ got)} differ")


def check_tree(hips, props, frame):
    """The tiles, Moc.fits (ICRS: COORDSYS C for every frame) and Allsky; returns {order: {npix}}."""
    order, width = int(props["hips_order"]), int(props["hips_tile_width"])
    tiles = {}
    for root, _, names in os.walk(hips):
        for name in names:
            m = re.fullmatch(r"Npix(\d+)\.fits", name)
            if not m:
                continue
            k = int(re.search(r"Norder(\d+)", root).group(1))
            npix = int(m.group(1))
            check(os.path.basename(root) == f"Dir{npix // 10000 * 10000}", f"{root}/{name}: wrong Dir")
            check(os.path.exists(os.path.join(root, f"Npix{npix}.png")), f"{root}/{name}: no PNG beside it")
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
        for key, value in [("PIXTYPE", "HEALPIX"), ("ORDERING", "NUNIQ"), ("COORDSYS", "C"), ("MOCORDER", order),
                           ("TTYPE1", "UNIQ"), ("MOCDIM", "SPACE"), ("MOCORD_S", order)]:
            check(h.get(key) == value, f"Moc.fits: {key} = {h.get(key)!r}, not {value!r}")
        check(h.get("TFORM1") in ("1J", "1K"), f"Moc.fits: TFORM1 {h.get('TFORM1')}")
        uniq = np.asarray(table.data["UNIQ"], dtype=np.int64)
        check(np.all(np.diff(uniq) > 0), "Moc.fits: UNIQ not strictly increasing")
        if frame == "C":  # the deepest tiles themselves
            covered = moc_cells(hips, order)
            check(covered == tiles.get(order, set()), f"Moc.fits covers {sorted(covered)}, tiles {sorted(tiles.get(order, []))}")
        fraction = sum(4.0 ** -((int(c).bit_length() - 3) // 2) / 12 for c in uniq)
        check(abs(fraction - float(props["moc_sky_fraction"])) < 1e-9, f"moc_sky_fraction {props['moc_sky_fraction']}")

    check_allsky(hips, min(3, order), width, tiles)
    return tiles


def check_allsky(hips, k, width, tiles):
    """NorderK/Allsky: int(sqrt(12 * 4^k)) tiles a row, tile npix at (npix % cols, npix // cols) from
    the top left as displayed (FITS rows bottom up), each its tile reduced to min(64, width) pixels."""
    cols, small = int(np.sqrt(12 * 4**k)), min(64, width)
    rows = -(-12 * 4**k // cols)
    with fits.open(os.path.join(hips, f"Norder{k}", "Allsky.fits")) as a:
        allsky = a[0].data[::-1]  # displayed: top row first
    check(allsky.shape == (rows * small, cols * small), f"Norder{k}/Allsky.fits: shape {allsky.shape}")
    png = os.path.join(hips, f"Norder{k}", "Allsky.png")
    check(os.path.exists(png), f"{png}: missing")
    f = width // small
    worst = 0.0
    for npix in tiles.get(k, ()):
        with fits.open(os.path.join(hips, f"Norder{k}", f"Dir{npix // 10000 * 10000}", f"Npix{npix}.fits")) as t:
            tile = t[0].data[::-1].astype(np.float64)
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", RuntimeWarning)  # all-NaN blocks
            reduced = np.nanmean(tile.reshape(small, f, small, f), axis=(1, 3))
        r, c = divmod(npix, cols)
        block = allsky[r * small:(r + 1) * small, c * small:(c + 1) * small]
        check(np.array_equal(np.isfinite(block), np.isfinite(reduced)), f"Allsky: tile {npix}'s blanks differ")
        both = np.isfinite(block) & np.isfinite(reduced)
        if both.any():
            worst = max(worst, float(np.abs(block[both] - reduced[both]).max()))
    check(worst < 1e-5, f"Norder{k}/Allsky.fits differs from its tiles by {worst}")


def lint(hips):
    """Aladin's HiPS 1.0 linter: mandatory keywords, Moc.fits, tile tree, Allsky."""
    r = subprocess.run(["aladin", "-hipsgen", f"in={hips}", f"out={hips}", "LINT"], capture_output=True, text=True,
                       timeout=300)
    text = re.sub(r"\x1b\[[0-9;]*m", "", r.stdout + r.stderr)
    errors = [line for line in text.splitlines() if "ERROR" in line or ("WARN" in line and "Moc.fits" in line)]
    check(not errors and re.search(r"is IVOA HiPS 1\.0 compatible", text) is not None,
          f"{hips}: Aladin's LINT: {errors or text[-400:]}")


def deinterleave(v):
    """Nested sub-index -> (even bits, odd bits)."""
    a = b = 0
    for bit in range(16):
        a |= ((v >> (2 * bit)) & 1) << bit
        b |= ((v >> (2 * bit + 1)) & 1) << bit
    return a, b


def check_positions(hips, props, data, wcs, frame):
    """Each plate pixel's value at the tile pixel HEALPix names (astropy-healpix): tile pixel
    (column c, row r from the top; FITS row width - 1 - r) of nested index npix * w^2 + sub, r in
    sub's even bits, c in its odd bits (docs/sky.md)."""
    order, width = int(props["hips_order"]), int(props["hips_tile_width"])
    shift = width.bit_length() - 1
    hp = HEALPix(nside=2 ** (order + shift), order="nested")
    n = data.shape[0]
    y, x = np.mgrid[2:n - 2:3, 2:n - 2:3]
    sky = wcs.pixel_to_world(x, y)
    lon, lat = (sky.l, sky.b) if frame == "G" else (sky.ra, sky.dec)
    index = hp.lonlat_to_healpix(lon, lat)
    errors, worst_wcs = [], 0.0
    for ipix, want in zip(index.ravel(), data[y, x].ravel()):
        tile, sub = divmod(int(ipix), width * width)
        r, c = deinterleave(sub)
        with fits.open(os.path.join(hips, f"Norder{order}", f"Dir{tile // 10000 * 10000}", f"Npix{tile}.fits")) as t:
            errors.append(abs(float(t[0].data[width - 1 - r, c]) - float(want)))
            # The tile's HPX WCS (HiPS's enabler) puts that pixel at the HEALPix pixel's centre.
            at = WCS(t[0].header).pixel_to_world(c, width - 1 - r)
        lon_c, lat_c = hp.healpix_to_lonlat(int(ipix))
        centre = SkyCoord(lon_c, lat_c, frame="galactic" if frame == "G" else "icrs")
        worst_wcs = max(worst_wcs, at.separation(centre).deg)
    check(worst_wcs < 1e-6, f"{hips}: tile WCS places pixels up to {worst_wcs} degrees from their HEALPix centres")
    errors = np.asarray(errors)
    # 0.46-degree HEALPix pixels against 0.4-degree plate pixels whose values change by 0.05 a degree.
    check(np.median(errors) < 0.01 and errors.max() < 0.04,
          f"{hips}: plate values at HEALPix positions: median error {np.median(errors):.4f}, worst {errors.max():.4f}")
    return len(errors)


def check_hpx_image(path):
    """Every pixel of gdp's HPX image that astropy places on the sky is a HEALPix pixel centre."""
    with fits.open(path) as f:
        header, shape = f[0].header, f[0].data.shape
    wcs = WCS(header)
    nside = shape[0] // 5
    hp = HEALPix(nside=nside, order="nested")
    y, x = np.mgrid[0:shape[0], 0:shape[1]]
    sky = wcs.pixel_to_world(x.ravel(), y.ravel())
    ok = np.isfinite(sky.ra.deg)
    centre = SkyCoord(*hp.healpix_to_lonlat(hp.lonlat_to_healpix(sky.ra[ok], sky.dec[ok])), frame="icrs")
    worst = sky[ok].separation(centre).deg.max()
    check(worst < 1e-6, f"{path}: pixel centres up to {worst} degrees from HEALPix centres")
    count = len(set(hp.lonlat_to_healpix(sky.ra[ok], sky.dec[ok]).tolist()))
    check(count == 12 * nside * nside, f"{path}: {count} HEALPix pixels of {12 * nside * nside}")


with tempfile.TemporaryDirectory() as tmp:
    plate = os.path.join(tmp, "plate.fits")
    data, wcs = write_plate(plate, 210.0, 20.0)
    hips = os.path.join(tmp, "hips")
    run([plate, "--center", "210,20", "--size", "20,20", "--scale", "0.5", "-o", os.path.join(tmp, "out.fits"),
         "--hips", hips, "--hips-tile", "32", "--pq-height", "128"])
    props = read_properties(hips)
    check(int(props["hips_tile_width"]) == 32, f"hips_tile_width {props['hips_tile_width']}")
    check(props["hips_frame"] == "equatorial", f"hips_frame {props['hips_frame']}")
    check(abs(float(props["hips_initial_ra"]) - 210.0) < 1.0 and abs(float(props["hips_initial_dec"]) - 20.0) < 1.0,
          f"initial view {props['hips_initial_ra']}, {props['hips_initial_dec']} for a plate at 210, 20")
    tiles = check_tree(hips, props, "C")

    # Galactic plates, no -o: the HiPS alone; its initial view and its MOC in ICRS (HiPS 1.0).
    gplate = os.path.join(tmp, "galactic.fits")
    gdata, gwcs = write_plate(gplate, 30.0, 10.0, galactic=True)
    ghips = os.path.join(tmp, "ghips")
    # Tiles of 8 (hips_order 4): Aladin 12's LINT skips the MOC of a partial non-ICRS HiPS and then
    # picks a random entry of Norder{hips_order} as a Dir, which fails on Allsky files (order <= 3).
    run([gplate, "--hips", ghips, "--hips-tile", "8", "--pq-height", "128"])
    gprops = read_properties(ghips)
    check(gprops["hips_frame"] == "galactic", f"hips_frame {gprops['hips_frame']}")
    icrs = SkyCoord(l=30.0 * u.deg, b=10.0 * u.deg, frame="galactic").icrs
    initial = SkyCoord(ra=float(gprops["hips_initial_ra"]) * u.deg, dec=float(gprops["hips_initial_dec"]) * u.deg)
    check(initial.separation(icrs).deg < 1.0,
          f"galactic HiPS: initial view {initial.ra.deg:.3f}, {initial.dec.deg:.3f}, the plate is at "
          f"{icrs.ra.deg:.3f}, {icrs.dec.deg:.3f} (ICRS)")
    check_tree(ghips, gprops, "G")

    placed = 0
    if HEALPix is not None:
        placed += check_positions(hips, props, data, wcs, "C")
        placed += check_positions(ghips, gprops, gdata, gwcs, "G")
        check_galactic_moc(ghips, gprops)
        hpx = os.path.join(tmp, "hpx.fits")
        run([plate, "--projection", "HPX", "--scale", "5", "-o", hpx, "--pq-height", "128"])
        check_hpx_image(hpx)
    if shutil.which("aladin"):
        lint(hips)
        lint(ghips)
    else:
        print("aladin not available (Debian aladin): HiPS not linted")

if failures:
    print("\n".join(failures))
    sys.exit(1)
print(f"HiPS read by astropy: {sum(len(t) for t in tiles.values())} tiles; {placed} plate pixels at their HEALPix tiles")
