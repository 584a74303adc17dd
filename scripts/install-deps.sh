#!/usr/bin/env bash
# Installs every build and test dependency of gdp from Debian packages (needs root or sudo).
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  libpng-dev libtiff-dev libjpeg-dev     # gdp's own PNG, TIFF and JPEG codecs (zlib comes with them)
  libopenexr-dev                         # gdp's own OpenEXR codec
  libdeflate-dev                         # TIFF strips deflated on two threads
  libcfitsio-dev wcslib-dev              # FITS and its world coordinates (gdp sky)
  libhealpix-cxx-dev                     # HEALPix tiles of gdp sky --hips
  libopenimageio-dev openimageio-tools   # other formats (HDR, WebP, ...) in the loadable module; oiiotool
  libboost-graph-dev                     # Boykov-Kolmogorov max-flow for gdp blend --seams graphcut (header-only)
  libeigen3-dev                          # linear algebra of the photometric and sky fits (header-only)
  libcli11-dev libfmt-dev                # command line parsing, formatting
  libgtest-dev libbenchmark-dev          # tests and benchmarks
  libopenmpi-dev openmpi-bin             # distributed band solver (mpirun; issue 4)
  python3
  python3-dev pybind11-dev python3-numpy # the Python module (python/)
  python3-pytest python3-venv python3-pip # its tests, and `pip install .` into a virtual environment
  python3-astropy                        # tests: sky positions checked against astropy
  python3-astropy-healpix                # tests: HiPS tile and HPX pixel positions against an independent HEALPix
  aladin                                 # tests: Aladin's HiPS builder lints gdp's HiPS (IVOA HiPS 1.0; needs a JRE)
  xvfb                                   # bench/sky_hips_aladin.sh: Aladin renders under xvfb-run (no test needs it)
  enblend hugin-tools                    # gdp blend beside enblend (bench/blend_vs_enblend.sh), Hugin's pipeline (scripts/hugin_blend.sh)
  montage                                # bench/sky_bench.py: Montage's pipeline beside gdp sky (and --projected)
  libtiff-tools                          # bench/blend_huge.sh: tiffdump/tiffinfo check the BigTIFF it writes
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all packages present"
  exit 0
fi

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
echo "install-deps: installing ${missing[*]}"
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
