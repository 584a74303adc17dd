#!/usr/bin/env bash
# An all-sky HiPS from one equirectangular map (gdp sky --hips, no -o), linted and rendered by Aladin (docs/sky.md).
# Usage: bench/sky_hips_aladin.sh build/tools/gdp/gdp OUTDIR [equirect/stellarium/milkyway.png]
#   The map (in ../shared/data) becomes one galactic CAR plate (l = 0 at its centre, l growing to the
#   left), gdp sky writes OUTDIR/hips (64-pixel tiles), Aladin's HipsGen lints it against IVOA HiPS
#   1.0 and Aladin (under Xvfb) saves OUTDIR/aladin_allsky.png and aladin_60deg.png, centred on
#   hips_initial_ra/dec. Needs Debian aladin, xvfb and python3-astropy.
set -euo pipefail
source "$(dirname "$0")/shared_data.sh"
gdp=$1 out=$2
map=$(shared_data "${3:-equirect/stellarium/milkyway.png}")
for tool in aladin xvfb-run /usr/bin/python3; do
  command -v "$tool" > /dev/null || { echo "sky_hips_aladin: needs $tool (Debian aladin, xvfb, python3-astropy)" >&2; exit 2; }
done
mkdir -p "$out"
rm -rf "$out/hips"
"$gdp" convert "$map" -o "$out/map.fits" --depth float --quiet
/usr/bin/python3 - "$out/map.fits" "$out/plate.fits" <<'PY'
import sys
import numpy as np
from astropy.io import fits
with fits.open(sys.argv[1]) as f:
    data = f[0].data.astype(np.float32)
if data.ndim == 3:  # colour planes (and alpha): the mean of the colours
    data = data[:3].mean(axis=0)
h, w = data.shape
header = fits.Header()
for key, value in [("CTYPE1", "GLON-CAR"), ("CTYPE2", "GLAT-CAR"), ("CRVAL1", 0.0), ("CRVAL2", 0.0),
                   ("CRPIX1", (w + 1) / 2), ("CRPIX2", (h + 1) / 2), ("CDELT1", -360.0 / w), ("CDELT2", 180.0 / h)]:
    header[key] = value
fits.writeto(sys.argv[2], data, header, overwrite=True)
PY
/usr/bin/time -f "gdp sky --hips: %e s wall, %U + %S s CPU, %M KiB peak" "$gdp" sky "$out/plate.fits" --hips "$out/hips" --hips-tile 64
aladin -hipsgen in="$out/hips" out="$out/hips" LINT 2>&1 | grep -E "compatible|ERROR|WARN"
ra=$(awk -F= '/^hips_initial_ra/ {print $2}' "$out/hips/properties" | tr -d ' ')
dec=$(awk -F= '/^hips_initial_dec/ {print $2}' "$out/hips/properties" | tr -d ' ')
for view in "allsky 180deg" "60deg 60deg"; do
  set -- $view
  timeout 300 xvfb-run -a -s "-screen 0 1280x1024x24" java -Xmx1024m -jar /usr/share/java/aladin.jar -local \
    "-script=load $out/hips;sync;$ra $dec;zoom $2;sync;save $out/aladin_$1.png;quit" > "$out/aladin_$1.log" 2>&1
  echo "Aladin's view -> $out/aladin_$1.png"
done
