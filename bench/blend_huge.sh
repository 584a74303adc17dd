#!/usr/bin/env bash
# gdp blend on a canvas past 2^31 pixels to BigTIFF: wall, CPU, peak RSS, scratch and disk, the output checked.
#
#   bench/blend_huge.sh [WIDTHxHEIGHT] [PHOTO]        (default 65536x40000, 2.62 gigapixels)
#
# Layers: TILE x TILE (TILE=4608) nona-style 8-bit RGBA TIFFs (XPOSITION/YPOSITION, LZW), 12.5 % overlap,
# cut by `blend_layers tiles` from PHOTO (default: NASA's Blue Marble in ../shared/data) enlarged
# UPSCALE times (UPSCALE=4: smooth enough to compress, so the layers take a few GB) and repeated
# mirrored, its values mapped to [0.1, 0.9], each with an exposure offset up to +-20/255 (so nothing
# clips) and no vignetting: the error check below then measures the blend alone. The grid covers the
# canvas; `-f` crops it (JOBS=N cutter processes make the layers). Then, under `nice -n ${NICE:-5}`:
#   gdp blend -f WxH --stats ... $GDP_BLEND_OPTS (default: --half-scratch) -o out.tif tile_*.tif
# measured by bench/measure_run.py (wall, user + sys, peak RSS); this script's own disk use (files in
# the work directory and the unlinked scratch files gdp holds open there) is sampled every 10 s.
# Checks: tiffdump says BigTIFF, tiffinfo the size and 4 samples (alpha); `blend_layers tiles-error`
# streams the output against the scene: RMS error (mean removed) and the largest step between
# neighbouring 256x256 blocks' mean errors (a level step left between layers, a seam, shows there). Work directory:
# ${GDP_BENCH_DIR:-/tmp/gdp-blend-huge}, removed at the end unless KEEP=1. Needs build/ or GDP_BIN=DIR.
set -euo pipefail
cd "$(dirname "$0")/.."
size=${1:-65536x40000}
photo=${2:-../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg}
if [ ! -f "$photo" ]; then
  echo "blend_huge: $photo is missing (../shared is not part of the repository); give a photo" >&2
  exit 2
fi
W=${size%x*}
H=${size#*x}
tile=${TILE:-4608}
up=${UPSCALE:-4}
step=$((tile * 7 / 8))  # 12.5 % overlap
cols=$(((W - tile + step - 1) / step + 1))
rows=$(((H - tile + step - 1) / step + 1))
dir=${GDP_BENCH_DIR:-/tmp/gdp-blend-huge}
[ -z "${GDP_BIN:-}" ] || PATH="$GDP_BIN:$PATH"  # a packed bin/ may bring tiffinfo and tiffdump
gdp=${GDP_BIN:+$GDP_BIN/gdp}
gdp=${gdp:-build/tools/gdp/gdp}
cutter=${GDP_BIN:+$GDP_BIN/blend_layers}
cutter=${cutter:-build/bench/blend_layers}
opts=${GDP_BLEND_OPTS:---half-scratch}
mkdir -p "$dir"
sampler=
cleanup() {
  [ -z "$sampler" ] || kill "$sampler" 2>/dev/null || true
  [ "${KEEP:-0}" = 1 ] || rm -rf "$dir"
}
trap cleanup EXIT
since() { awk -v s="$1" -v e="$(date +%s.%N)" 'BEGIN { printf "%.1f", e - s }'; }
echo "blend_huge: $W x $H ($(awk -v p=$((W * H)) 'BEGIN { printf "%.3f", p / 1e9 }') Gpix), $cols x $rows layers of $tile², in $dir"
df -h "$dir" | tail -1

start=$(date +%s.%N)
jobs=${JOBS:-1}  # cutter processes (each writes every JOBS-th tile)
for ((k = 0; k < jobs; ++k)); do
  "$cutter" tiles "$photo" "$dir" --tile "$tile" --grid "${cols}x$rows" --overlap 0.125 --offset 20 --vignette 0 \
    --seed 9 --upscale "$up" --headroom 0.1 --part "$k/$jobs" > /dev/null &
done
for ((k = 0; k < jobs; ++k)); do wait -n; done
echo "layers: $(find "$dir" -name "tile_*.tif" | wc -l) files, $(du -sh "$dir" | cut -f1), $(since "$start") s to make"

# Disk held by this run: the work directory plus the unlinked scratch files gdp keeps open in it.
sample_disk() {
  local peak=0 now fd
  while sleep 10; do
    now=$(du -sB1 "$dir" | cut -f1)
    for fd in $(pgrep -f "gdp blend .*$dir" | sed 's|.*|/proc/&/fd/*|'); do
      case $(readlink "$fd" 2>/dev/null) in
        "$dir"/*) now=$((now + $(stat -L -c '%b * %B' "$fd" 2>/dev/null || echo 0))) ;;
      esac
    done
    [ "$now" -gt "$peak" ] && peak=$now && echo "$peak" > "$dir/disk_peak"
  done
}
sample_disk &
sampler=$!
# shellcheck disable=SC2086  # the options are words
bench/measure_run.py "$dir/run.json" -- nice -n "${NICE:-5}" "$gdp" blend -q -f "${W}x$H" --temp "$dir" --stats "$dir/stats.json" \
  $opts -o "$dir/out.tif" "$dir"/tile_*.tif
kill "$sampler"
sampler=
python3 - "$dir/run.json" "$dir/stats.json" "$dir/out.tif" "$dir/disk_peak" <<'EOF'
import json, os, sys
run, stats = json.load(open(sys.argv[1])), json.load(open(sys.argv[2]))
disk = int(open(sys.argv[4]).read()) if os.path.exists(sys.argv[4]) else 0
print(f"blend: wall {run['wall']:.1f} s, cpu {run['user'] + run['sys']:.1f} s (user {run['user']:.1f} + sys {run['sys']:.1f}), "
      f"peak RSS {run['peak_rss_kb'] / 1024:.0f} MB")
print(f"phases: seams {stats.get('seconds_seams')} s, solve {stats.get('seconds_solve')} s; "
      f"solver scratch {stats.get('scratch_mb')} MB (in memory at most {stats.get('scratch_memory_mb')} MB, "
      f"on disk at most {stats.get('scratch_disk_mb')} MB), blend scratch {int(stats.get('blend_scratch_bytes', 0)) / 2**20:.0f} MB")
print(f"disk held (sampled every 10 s, layers and output included): {disk / 1e9:.1f} GB; output "
      f"{os.path.getsize(sys.argv[3]) / 1e9:.2f} GB; bytes written {run.get('write_bytes', 0) / 1e9:.1f} GB; "
      f"residuals {stats.get('relative_residuals')}")
EOF
# The TIFF encoder switches to BigTIFF past 3.5 GiB of uncompressed samples (8-bit RGBA: 4 bytes a pixel).
magic=$(tiffdump "$dir/out.tif" | sed -n 2p)
echo "$magic"
if [ $((W * H * 4)) -gt $((7 << 29)) ] && ! echo "$magic" | grep -q BigTIFF; then
  echo "blend_huge: the output is not BigTIFF" >&2
  exit 1
fi
tiffinfo "$dir/out.tif" 2>/dev/null | grep -E "Image Width|Samples/Pixel|Extra Samples|Bits/Sample" | tr -s ' ' | paste -sd ';'
tiffinfo "$dir/out.tif" 2>/dev/null | grep -q "Image Width: $W Image Length: $H" || { echo "blend_huge: wrong size" >&2; exit 1; }
tiffinfo "$dir/out.tif" 2>/dev/null | grep -q "Samples/Pixel: 4" || { echo "blend_huge: no alpha" >&2; exit 1; }
if [ "${CHECK:-1}" = 1 ]; then  # CHECK=0 skips the error pass (one thread over the whole canvas)
  start=$(date +%s.%N)
  "$cutter" tiles-error "$dir/out.tif" "$photo" --upscale "$up" --headroom 0.1
  echo "check: $(since "$start") s"
fi
