#!/bin/sh
# `pip install .` from the repository into a fresh virtual environment (with the system's numpy),
# offline, reusing the build tree for the compiled parts; then imports gdp there and stitches.
# Usage: pip_install.sh PYTHON SOURCE_DIR WORK_DIR [BUILD_DIR]
set -eu
python=$1 source=$2 work=$3 build=${4:-}
rm -rf "$work"
mkdir -p "$work"
"$python" -m venv --system-site-packages "$work/venv"
set -- --no-index --no-cache-dir --quiet
[ -n "$build" ] && set -- "$@" --config-settings "build-dir=$build"
"$work/venv/bin/python" -m pip install "$@" "$source"
cd "$work"
"$work/venv/bin/python" - "$work/venv" <<'PY'
import os, sys
import numpy as np
import gdp
assert gdp.__file__.startswith(sys.argv[1]), gdp.__file__  # the installed copy, not the build tree's
composite = np.zeros((32, 48, 3), np.float32)
composite[:, 24:] = 0.5
labels = np.zeros((32, 48), np.uint8)
labels[:, 24:] = 1
out = gdp.stitch(composite, labels)
assert np.abs(out - out.mean()).max() < 1e-3, "the seam should be gone"
pixels = (np.arange(32 * 48 * 3) % 256).astype(np.uint8).reshape(32, 48, 3)
gdp.write_image("t.bmp", pixels)  # BMP goes through the OpenImageIO module, packaged beside the extension
assert np.array_equal(gdp.read_image("t.bmp"), pixels.astype(np.float32) * np.float32(1 / 255))
# gdp's own shared objects (libgdp.so when the build tree's is shared, libgdp_oiio.so) are the installed ones.
mapped = {line.split()[-1] for line in open("/proc/self/maps") if "libgdp" in line}
assert mapped and all(p.startswith(sys.argv[1]) for p in mapped), mapped
print("pip install: gdp", gdp.__file__, sorted(mapped))
PY
