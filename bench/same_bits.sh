#!/usr/bin/env bash
# The same-bits matrix: two gdp builds, A (before) and B (after), on small stitches of the blue-marble
# photo (planar, cylindrical, PQ via --sphere; 1-8 bands; in-core, double, --memory 0, 3 V-cycles;
# merged stages of 4, 7 and 8 bands; checkpoints killed after 3, 17 and 60 saves by one build and
# resumed by the other (killed by B too where B refuses A's state version: the case's line says so);
# mpirun -np 2 with and without --bands; --tolerance; gdp sharpen and gdp blend of six layers plain
# and under mpirun -np 2, whose rows go through the column gather). Prints "same" or "DIFF" a case.
#
#   bench/same_bits.sh OLD NEW      OLD, NEW: folders holding copies of gdp and libgdp.so* (so that
#                                   a rebuild cannot change them mid-run: mkdir -p DIR && cp
#                                   build/tools/gdp/gdp build/lib/libgdp.so* DIR/)
# MAKE_COMPOSITE, BLEND_LAYERS: the generators to use where build/ has none. Inputs and outputs stay in
# $GDP_BENCH_DIR when set (about 200 MB; kept, so a rerun reuses the inputs), else in a folder of this
# run's own, removed at exit (two runs at once must not share one).
set -u
A=$1 B=$2
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
if [[ -n ${GDP_BENCH_DIR:-} ]]; then W=$GDP_BENCH_DIR
else W=$(mktemp -d /tmp/gdp-same-bits.XXXXXX); trap 'rm -rf "$W"' EXIT; fi
mkdir -p "$W/tmp"
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
make_composite=${MAKE_COMPOSITE:-$here/build/bench/make_composite}
[[ -x $make_composite ]] || { echo "same_bits.sh: no $make_composite (build bench/ or set MAKE_COMPOSITE)" >&2; exit 2; }
mk() { [[ -f $W/$3 ]] || "$make_composite" "$photo" "$1" "$2" "$W/$3" "$W/$4" "$5" > /dev/null; }
mk 1024 640 c.tif l.tif 256
mk 1024 256 n.tif nl.tif 128
mk 1024 512 e.tif el.tif 256
gdp() { local d=$1; shift; LD_LIBRARY_PATH=$d "$d/gdp" "$@"; }
same() { if cmp -s "$1" "$2"; then echo "same  $3"; else echo "DIFF  $3"; fi; }
planar=(-c "$W/c.tif" -l "$W/l.tif")
cyl=("${planar[@]}" --domain cylindrical)
sphere=(-c "$W/e.tif" -l "$W/el.tif" --sphere --pq-height 256)
narrow=(-c "$W/n.tif" -l "$W/nl.tif")
narrowcyl=("${narrow[@]}" --domain cylindrical)
run() {  # NAME GEOMETRY [FLAGS]: both builds, then cmp
  local name=$1 geo=$2 s
  shift 2
  local -n g=$geo
  for s in A B; do
    gdp "${!s}" stitch -q --depth float "${g[@]}" "$@" --temp "$W/tmp" -o "$W/$name.$s.tif" 2> "$W/$name.$s.err" ||
      echo "$s failed $name: $(tail -1 "$W/$name.$s.err")"
  done
  same "$W/$name.A.tif" "$W/$name.B.tif" "$name: $*"
}
for geo in planar cyl sphere; do
  run $geo-default $geo
  for b in 1 2 3 4 8; do run $geo-b$b $geo --bands $b; done
  run $geo-incore $geo --in-core
  run $geo-double $geo --double --bands 2
  run $geo-mem0 $geo --memory 0 --bands 3
  run $geo-v3 $geo --vcycles 3 --bands 2
  run $geo-v3one $geo --vcycles 3
done
for geo in narrow narrowcyl; do  # bands too narrow for the gathered level: merged stages
  for b in 8 7 4; do run $geo-merge$b $geo --bands $b --incore-bytes 256 --vcycles 2; done
  run $geo-merge8d $geo --bands 8 --incore-bytes 256 --double
done
ck() {  # NAME KILLER RESUMER SAVES GEOMETRY [FLAGS]: killed after SAVES saves, resumed, against A's plain run
  local name=$1 K=$2 R=$3 after=$4 geo=$5 note=
  shift 5
  local -n g=$geo
  rm -rf "$W/cp-$name" "$W/$name.r.tif"  # no earlier run's output to compare by mistake
  gdp "$A" stitch -q --depth float "${g[@]}" "$@" --temp "$W/tmp" -o "$W/$name.ref.tif"
  kill_resume() {
    GDP_CHECKPOINT_ROWS=8 GDP_CHECKPOINT_KILL_AFTER=$after gdp "$K" stitch -q --depth float "${g[@]}" "$@" \
      --temp "$W/tmp" -o "$W/$name.r.tif" --checkpoint "$W/cp-$name" 2> /dev/null
    GDP_CHECKPOINT_ROWS=8 gdp "$R" stitch -q --depth float "${g[@]}" "$@" --temp "$W/tmp" -o "$W/$name.r.tif" \
      --resume "$W/cp-$name" 2> "$W/$name.err"
  }
  # A resumer that refuses the killer's state for its version (docs/resume.md: another state layout)
  # cannot prove the bits across builds: the case runs again with the resumer as killer too.
  local ok=1
  kill_resume "$@" || ok=0
  if ((!ok)) && [[ $K != "$R" ]] && grep -q "saved by an older gdp" "$W/$name.err"; then
    note=" (refused: $(grep -o 'state version [0-9]*' "$W/$name.err"); killed by $R instead)"
    K=$R ok=1
    rm -rf "$W/cp-$name" "$W/$name.r.tif"
    kill_resume "$@" || ok=0
  fi
  ((ok)) || echo "resume failed $name: $(tail -1 "$W/$name.err")"
  same "$W/$name.ref.tif" "$W/$name.r.tif" "checkpoint $name: killed by $K after $after saves, resumed by $R: $*$note"
}
for after in 3 17 60; do
  ck p1-$after "$A" "$B" $after planar --vcycles 2
  ck p3-$after "$A" "$B" $after planar --vcycles 2 --bands 3
  ck c2-$after "$B" "$B" $after cyl --vcycles 2 --bands 2
  ck s2-$after "$A" "$B" $after sphere --vcycles 2 --bands 2
  ck m8-$after "$A" "$B" $after narrow --vcycles 2 --bands 8 --incore-bytes 256
  ck m7-$after "$B" "$B" $after narrowcyl --vcycles 2 --bands 7 --incore-bytes 256
done
mp() {  # NAME GEOMETRY [FLAGS]: both builds under mpirun -np 2
  local name=$1 geo=$2 s
  shift 2
  local -n g=$geo
  for s in A B; do
    LD_LIBRARY_PATH=${!s} mpirun --oversubscribe --bind-to none -np 2 "${!s}/gdp" stitch -q --depth float "${g[@]}" \
      "$@" --temp "$W/tmp" -o "$W/$name.$s.tif" 2> "$W/$name.$s.err" || echo "$s failed $name: $(tail -1 "$W/$name.$s.err")"
  done
  same "$W/$name.A.tif" "$W/$name.B.tif" "mpirun -np 2 $name: $*"
}
mp mpi-planar planar
mp mpi-planar-b2 planar --bands 2
mp mpi-cyl-b2 cyl --bands 2 --vcycles 2
mp mpi-sphere sphere
mp mpi-merge narrow --bands 4 --incore-bytes 256
same "$W/mpi-planar.B.tif" "$W/planar-b2.B.tif" "mpirun -np 2 vs --bands 2 (B)"
run planar-tolerance planar --tolerance 1e-4
blend_layers=${BLEND_LAYERS:-$here/build/bench/blend_layers}
[[ -f $W/layers/layer_05.tif ]] || { mkdir -p "$W/layers" && "$blend_layers" cut "$photo" "$W/layers" --size 1024x640 --grid 3x2 > /dev/null; }
cmd() {  # NAME NP COMMAND [ARGS]: both builds, under mpirun -np NP when NP > 1, then cmp
  local name=$1 np=$2 s pre=()
  shift 2
  ((np == 1)) || pre=(mpirun --oversubscribe --bind-to none -np "$np" -x LD_LIBRARY_PATH)
  for s in A B; do
    LD_LIBRARY_PATH=${!s} "${pre[@]}" "${!s}/gdp" "$@" -q --temp "$W/tmp" -o "$W/$name.$s.tif" 2> "$W/$name.$s.err" ||
      echo "$s failed $name: $(tail -1 "$W/$name.$s.err")"
  done
  same "$W/$name.A.tif" "$W/$name.B.tif" "$name: np $np $*"
}
layers=("$W"/layers/layer_0{0..5}.tif)
for np in 1 2; do
  cmd sharpen-np$np $np sharpen "$W/c.tif" --depth float
  cmd blend-np$np $np blend "${layers[@]}"
done
cmd sharpen-np2-b2 2 sharpen "$W/c.tif" --depth float --bands 2
cmd blend-np2-b2 2 blend "${layers[@]}" --bands 2
cmd blend-np2-graphcut 2 blend "${layers[@]}" --seams graphcut
