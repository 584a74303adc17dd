#!/usr/bin/env bash
# A panorama from photos through Hugin's own tools, with gdp blend as Hugin's blender:
# pto_gen, cpfind, autooptimiser and pano_modify make the project; hugin_executor stitches it
# (nona -m TIFF_m, then the blender) with gdp-blend named in Hugin's settings instead of enblend.
#
#   scripts/hugin_blend.sh OUT.tif [FOV_DEGREES [PHOTOS...]]
#
# Default photos: examples/data/budapest1-3.jpg (OpenCV's stitching test images, resized).
# Needs build/ (scripts/build.sh) and hugin-tools. Work files go to a temporary directory.
set -euo pipefail
cd "$(dirname "$0")/.."
out=$(realpath -m "${1:?usage: scripts/hugin_blend.sh OUT.tif [FOV [PHOTOS...]]}")
fov=${2:-60}
shift $(( $# > 1 ? 2 : 1 ))
photos=("$@")
if [ ${#photos[@]} -eq 0 ]; then
  photos=(examples/data/budapest{1,2,3}.jpg)
fi
for i in "${!photos[@]}"; do photos[$i]=$(realpath "${photos[$i]}"); done
blender="$PWD/build/tools/gdp/gdp-blend"
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
step() { echo "hugin_blend: $*" >&2; "$@" > "$work/log" 2>&1 || { cat "$work/log" >&2; exit 1; }; }
step pto_gen -f "$fov" -o p.pto "${photos[@]}"
step cpfind --multirow -o p.pto p.pto
step autooptimiser -a -m -l -s -o p.pto p.pto
step pano_modify --canvas=AUTO --crop=AUTO -o p.pto p.pto
# Hugin's settings (read from $HOME/.config/hugin.conf): a custom blender program.
mkdir -p home/.config
printf '[Enblend]\nCustom=1\nExe=%s\n' "$blender" > home/.config/hugin.conf
HOME="$work/home" hugin_executor --stitching --prefix=pano p.pto > log 2>&1 || { cat log >&2; exit 1; }
grep -E "^(blend:|gdp)" log >&2 || true
[ -f pano.tif ] || { cat log >&2; echo "hugin_blend: no panorama was made" >&2; exit 1; }
mv pano.tif "$out"
echo "hugin_blend: wrote $out" >&2
