#!/usr/bin/env bash
# The README's demo command: installs dependencies, builds, and stitches the bundled sample.
set -euo pipefail
cd "$(dirname "$0")/.."
scripts/install-deps.sh
scripts/build.sh
out="$(pwd)/out"
mkdir -p "$out"
build/tools/gdp/gdp stitch --composite examples/data/weir_composite.png \
  --labels examples/data/weir_labels.png -o "$out/weir_stitched.png" --stats "$out/weir_stitched.json"
echo "demo: wrote $out/weir_stitched.png (statistics in $out/weir_stitched.json)"
