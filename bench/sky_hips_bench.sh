#!/usr/bin/env bash
# gdp sky with and without --hips on the plates of bench/sky_bench.py: time, CPU, peak memory, tiles (docs/sky.md).
# Usage: bench/sky_hips_bench.sh build/tools/gdp/gdp /tmp/sky-bench [TILE_WIDTH]
#   /tmp/sky-bench: the --out directory of a bench/sky_bench.py run (raw/plate*.fits, region.hdr).
set -euo pipefail
gdp=$1 bench=$2 tile=${3:-512}
if ! ls "$bench"/raw/plate*.fits > /dev/null 2>&1 || [ ! -f "$bench/region.hdr" ]; then
  echo "sky_hips_bench: no plates in $bench/raw or no $bench/region.hdr: run bench/sky_bench.py --out $bench first" >&2
  exit 2
fi
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
measure() {  # label, command...: one line of wall, user + sys, peak RSS
  local label=$1; shift
  local start end
  start=$(date +%s.%N)
  /usr/bin/time -v "$@" 2> "$out/time.txt" > /dev/null
  end=$(date +%s.%N)
  awk -v label="$label" -v wall="$(echo "$end - $start" | bc)" '
    /User time/ {cpu += $NF} /System time/ {cpu += $NF} /Maximum resident/ {rss = $NF / 1024}
    END {printf "%-28s wall %6.2f s  CPU %6.2f s  peak RSS %6.1f MiB\n", label, wall, cpu, rss}' "$out/time.txt"
}
plates=("$bench"/raw/plate*.fits)
measure "gdp sky" "$gdp" sky "${plates[@]}" --header "$bench/region.hdr" -o "$out/a.fits" --tolerance 1e-4 --quiet
measure "gdp sky --hips" "$gdp" sky "${plates[@]}" --header "$bench/region.hdr" -o "$out/b.fits" --tolerance 1e-4 \
  --hips "$out/hips" --hips-tile "$tile" --quiet
order=$(sed -n 's/^hips_order *= *//p' "$out/hips/properties")
echo "HiPS: hips_order $order, tile width $tile, $(find "$out/hips" -name 'Npix*.fits' | wc -l) FITS tiles" \
  "($(find "$out/hips/Norder$order" -name 'Npix*.fits' | wc -l) at the deepest order)," \
  "$(du -sm "$out/hips" | cut -f1) MiB"
