#!/usr/bin/env bash
# Where mpirun -np 2's extra CPU goes (issue 17): perf record (cpu-clock, DWARF call graphs) of the
# plain one-band stitch and of each rank under mpirun (every gdp thread: workers, gdp-decode,
# gdp-encode), each sample charged to its innermost gdp,
# MPI or loader function (callees included), and the two runs compared by function, in ms of CPU.
#
#   bench/mpi_rank_profile.sh [SIZE=8192] [BUILD=build] [TOP=30]
#
# GDP=/dir/gdp profiles that binary instead (a folder as bench/same_bits.sh takes: set LD_LIBRARY_PATH
# to it too); BUILD still gives bench/make_composite.
#
# Needs perf. Makes a SIZE x SIZE composite (uncompressed TIFF) with bench/make_composite in a
# scratch folder removed on exit. Prints the functions whose CPU differs most (mpirun - plain, both
# ranks summed, then the third as many that fell most; mpirun's own process is not recorded: /usr/bin/time around mpirun shows it) and the
# totals. Samples are 1 ms; on a loaded machine compare the MPI functions (ColumnGather, MpiHub,
# mpi::, mca_btl_vader_get_cma: CMA, the pull of a message over 4 KB), not the kernels.
set -euo pipefail
size=${1:-8192}
build=${2:-build}
top=${3:-30}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
stitch_bench_setup rank-profile "$build"
gdp=${GDP:-$gdp}
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
"$here/$build/bench/make_composite" "$photo" "$size" "$size" "$work/c.tif" "$work/l.tif" > /dev/null
stitch=(stitch -c "$work/c.tif" -l "$work/l.tif" --compression none -q)
record=(perf record --call-graph dwarf,8192 -F 1000 -e cpu-clock -q)
"${record[@]}" -o "$work/plain.data" "$gdp" "${stitch[@]}" -o "$work/plain.tif" 2> /dev/null
cat > "$work/rank.sh" << EOF
#!/bin/sh
exec ${record[*]} -o "$work/rank\$OMPI_COMM_WORLD_RANK.data" "\$@" 2> /dev/null
EOF
chmod +x "$work/rank.sh"
mpirun --oversubscribe --bind-to none -np 2 "$work/rank.sh" "$gdp" "${stitch[@]}" -o "$work/mpi.tif"
charge() {  # samples of command gdp per innermost gdp / MPI / loader frame
  for f in "$@"; do perf script -i "$f" -F comm,ip,sym 2> /dev/null; done | awk 'BEGIN { RS = "" } $1 ~ /^gdp/ {
    n = split($0, L, "\n"); key = "(other)"
    for (i = 2; i <= n; i++) {
      s = L[i]; sub(/^[ \t]*[0-9a-f]+ /, "", s)
      if (s ~ /^gdp::|^PMPI|^MPI_|^ompi_|^opal_|^mca_|^_dl_|^dl_main/) {
        gsub(/\(anonymous namespace\)/, "anon", s); sub(/\(.*$/, "", s); gsub(/ /, "_", s); key = substr(s, 1, 80); break
      }
    }
    c[key]++
  } END { for (k in c) print k, c[k] }' | sort
}
join -a1 -a2 -e 0 -o 0,1.2,2.2 <(charge "$work/plain.data") <(charge "$work/rank0.data" "$work/rank1.data") |
  awk -v top="$top" '{ d = $3 - $2; a += $2; b += $3; print d, $2, $3, $1 | "sort -rn | head -" top
      print d, $2, $3, $1 | "sort -n | head -" int(top / 3) " | sort -rn" }
    END { close("sort -rn | head -" top); print "..."; close("sort -n | head -" int(top / 3) " | sort -rn")
      printf "total: plain %d ms, ranks %d ms (%.2fx)\n", a, b, b / a }' |
  awk 'BEGIN { print "mpirun-plain  plain  ranks  function (ms of CPU)" } { print }'
