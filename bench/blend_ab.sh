#!/usr/bin/env bash
# Two gdp builds on the same blend, alternated in one run (A B A B ...): CPU seconds (user + sys)
# and wall per run and the B/A ratio of the CPU medians, for a change's cost on a shared machine.
#
#   bench/blend_ab.sh GDP_A GDP_B [SIZE (4096)] [ROUNDS (3)] [blend options...]
#
# GDP_A/GDP_B: gdp binaries (a copied binary finds its libgdp through LD_LIBRARY_PATH_A /
# LD_LIBRARY_PATH_B when set). The layers are bench/blend_seams.sh's: the shared data's Blue Marble
# resampled to SIZE x SIZE, cut into 4x4 nona layers (20 % overlap, offsets up to 40/255); say so
# plainly when the photo is missing. Work files in ${GDP_BENCH_DIR:-/tmp/gdp-ab-bench} (deleted after).
set -euo pipefail
cd "$(dirname "$0")/.."
a=$1 b=$2 size=${3:-4096} rounds=${4:-3}
shift $(( $# < 4 ? $# : 4 ))
photo=../shared/data/equirect/three-globe-npm/earth-blue-marble.jpg
if [ ! -f "$photo" ]; then
  echo "blend_ab: the photo $photo is missing (the shared data is not here)" >&2
  exit 1
fi
dir=${GDP_BENCH_DIR:-/tmp/gdp-ab-bench}/$size
mkdir -p "$dir"
trap 'rm -rf "$dir"' EXIT
build/bench/blend_layers cut "$photo" "$dir" --size "${size}x${size}" --grid 4x4 --overlap 0.2 --offset 40 --seed 7 > /dev/null
layers=("$dir"/layer_*.tif)
declare -A cpu
for r in $(seq "$rounds"); do
  for which in A B; do
    bin=$a lib=${LD_LIBRARY_PATH_A:-}
    [ "$which" = B ] && bin=$b lib=${LD_LIBRARY_PATH_B:-}
    LD_LIBRARY_PATH=$lib /usr/bin/time -f "%e %U %S %M" -o "$dir/time" "$bin" blend -q "$@" -o "$dir/out_$which.tif" \
      --temp "$dir" -- "${layers[@]}"
    read -r wall user sys kb < "$dir/time"
    c=$(echo "$user + $sys" | bc)
    cpu[$which]="${cpu[$which]:-} $c"
    printf "round %d %s: cpu %6.2f s (user %.2f sys %.2f)  wall %6.2f s  peak %4d MB\n" "$r" "$which" "$c" "$user" "$sys" "$wall" "$((kb / 1024))"
  done
done
median() { tr ' ' '\n' <<< "$1" | sed '/^$/d' | sort -g | awk '{v[NR]=$1} END {print (NR % 2) ? v[(NR+1)/2] : (v[NR/2]+v[NR/2+1])/2}'; }
ma=$(median "${cpu[A]}") mb=$(median "${cpu[B]}")
echo "median cpu A $ma s, B $mb s, B/A $(echo "scale=3; $mb / $ma" | bc)"
echo "A against the photo: $(build/bench/blend_layers error "$dir/out_A.tif" "$dir/original.tif")"
echo "B against the photo: $(build/bench/blend_layers error "$dir/out_B.tif" "$dir/original.tif")"
