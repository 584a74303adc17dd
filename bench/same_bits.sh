#!/usr/bin/env bash
# The same-bits matrix of the schedule (issue 17): runs every case with two gdp builds, OLD and NEW,
# and says which outputs differ (cmp). Stitch of a 1536x768 composite cut from the Blue Marble
# (bench/make_composite, cells of 256), planar, cylindrical and --sphere (PQ), each as the default,
# --bands 1/2/3/4/8, --in-core, --double, --memory 0 (alone and with --bands 2) and under mpirun -np 2
# without and with --bands 2; --tolerance; gdp sharpen plain and under mpirun -np 2 (1 and 2 bands);
# gdp blend of six layers (bench/blend_layers) plain and under mpirun -np 2 (default, --bands 2,
# --seams graphcut: their rows go through the column gather). 44 cases, about a minute each build.
#
#   bench/same_bits.sh OLD NEW
#
# OLD and NEW: build folders, or folders holding copies of gdp and libgdp (mkdir -p DIR && cp
# build/tools/gdp/gdp build/lib/libgdp.so.* DIR/). The inputs are made with NEW's bench tools.
# Exit status 1 when any output differs or any run fails.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
(($# == 2)) || { sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2; }
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-same-bits.XXXXXX")
trap 'rm -rf "$work"' EXIT
bin() { [[ -x $1/tools/gdp/gdp ]] && echo "$(realpath "$1/tools/gdp/gdp") $(realpath "$1/lib")" || echo "$(realpath "$1/gdp") $(realpath "$1")"; }
tools=$(realpath "$2")/bench
[[ -x $tools/make_composite ]] || tools=$here/build/bench
mkdir -p "$work/in/layers" "$work/tmp"
"$tools/make_composite" "$photo" 1536 768 "$work/in/comp.png" "$work/in/labels.png" 256 > /dev/null
"$tools/blend_layers" cut "$photo" "$work/in/layers" --size 1024x640 --grid 3x2 > /dev/null
status=0
for side in old new; do
  read -r gdp lib < <(bin "$([[ $side == old ]] && echo "$1" || echo "$2")")
  out=$work/$side
  mkdir -p "$out"
  export LD_LIBRARY_PATH=$lib
  mpi="timeout 300 mpirun --oversubscribe --allow-run-as-root -np 2 -x LD_LIBRARY_PATH"
  run() { local name=$1; shift; $@ -o "$out/$name.tif" > "$out/$name.log" 2>&1 || { echo "$side $name failed:"; cat "$out/$name.log"; status=1; }; }
  st="$gdp stitch -c $work/in/comp.png -l $work/in/labels.png --depth float -q --threads 2 --temp $work/tmp"
  for dom in planar cylindrical sphere; do
    d="--domain $dom"
    [[ $dom == sphere ]] && d=--sphere
    run st-$dom $st $d
    for b in 1 2 3 4 8; do run st-$dom-bands$b $st $d --bands $b; done
    run st-$dom-incore $st $d --in-core
    run st-$dom-double $st $d --double
    run st-$dom-memory0 $st $d --memory 0
    run st-$dom-memory0-bands2 $st $d --memory 0 --bands 2
    run st-$dom-mpi $mpi $st $d
    run st-$dom-mpi-bands2 $mpi $st $d --bands 2
  done
  run st-tolerance $st --tolerance 1e-4
  for pre in "" "$mpi"; do
    run sh${pre:+-mpi} $pre $gdp sharpen $work/in/comp.png --depth float -q
    run bl${pre:+-mpi} $pre $gdp blend $work/in/layers/layer_0{0..5}.tif -q
  done
  run sh-mpi-bands2 $mpi $gdp sharpen $work/in/comp.png --depth float -q --bands 2
  run bl-mpi-bands2 $mpi $gdp blend $work/in/layers/layer_0{0..5}.tif -q --bands 2
  run bl-mpi-graphcut $mpi $gdp blend $work/in/layers/layer_0{0..5}.tif -q --seams graphcut
done
same=0 differ=0
for f in "$work"/old/*.tif; do
  name=$(basename "$f")
  if cmp -s "$f" "$work/new/$name"; then same=$((same + 1)); else differ=$((differ + 1)); echo "differs: ${name%.tif}"; fi
done
echo "$same cases the same bytes, $differ differ"
((differ == 0 && status == 0))
