#!/usr/bin/env bash
# The README's demo command: installs dependencies, builds, stitches the bundled sample, and
# makes a panorama from the bundled photos with Hugin's tools and gdp-blend as the blender.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
out="$(pwd)/out"
mkdir -p "$out"
build/tools/gdp/gdp stitch --composite examples/data/weir_composite.png \
  --labels examples/data/weir_labels.png -o "$out/weir_stitched.png" --stats "$out/weir_stitched.json"
echo "demo: wrote $out/weir_stitched.png (statistics in $out/weir_stitched.json)"
scripts/hugin_blend.sh "$out/budapest_pano.tif" 60
echo "demo: wrote $out/budapest_pano.tif (three photos: Hugin's pto_gen, cpfind, autooptimiser, nona; gdp-blend)"
