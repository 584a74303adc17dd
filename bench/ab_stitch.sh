#!/usr/bin/env bash
# Two gdp builds on the same stitch, runs interleaved (A, B, A, B, ...): CPU seconds (user, sys),
# minor faults, peak RSS and wall per run, and whether their outputs are byte-identical.
#
#   bench/ab_stitch.sh OLD_BUILD NEW_BUILD [SIZE (8192)] [RUNS (3)] [-- extra gdp stitch flags]
#
# OLD_BUILD and NEW_BUILD are build folders (or copies of one: tools/gdp/gdp and lib/ beside it, or
# gdp and lib/ side by side). The input is the vs_dmg.sh composite: SIZE x SIZE PNG composite and
# labels cut by bench/make_composite from the blue-marble photo in ../shared/data (made once into
# ${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/SIZE when missing). The stitch is vs_dmg.sh's: 16-bit
# uncompressed TIFF out, --threads 2, scratch under --temp in the work folder (in memory within
# the default --memory budget). On a shared machine compare CPU seconds, not walls.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
me=$(basename "$0")
(($# >= 2)) || { sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2; }
old=$1 new=$2
shift 2
size=8192 runs=3
[[ $# -gt 0 && $1 != -- ]] && { size=$1; shift; }
[[ $# -gt 0 && $1 != -- ]] && { runs=$1; shift; }
[[ ${1:-} == -- ]] && shift
exe() {  # build folder -> gdp binary and the library folder beside it
  local d=$1
  if [[ -x $d/tools/gdp/gdp ]]; then echo "$d/tools/gdp/gdp $d/lib"; elif [[ -x $d/gdp ]]; then echo "$d/gdp $d/lib"; else
    echo "$me: no gdp binary in $d" >&2; exit 2; fi
}
read -r gdp_a lib_a < <(exe "$old")
read -r gdp_b lib_b < <(exe "$new")
d=${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/$size
if [[ ! -f $d/labels.png ]]; then
  source "$here/bench/shared_data.sh"
  photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
  mkdir -p "$d"
  "$here/build/bench/make_composite" "$photo" "$size" "$size" "$d/composite.png" "$d/labels.png" 1024 "$d/truth.tif"
fi
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-ab.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scratch"
run() {  # label, binary, library folder, run, extra flags...
  local label=$1 bin=$2 lib=$3 r=$4
  shift 4
  LD_LIBRARY_PATH=$lib python3 "$here/bench/measure_run.py" "$work/${label}_$r.json" -- "$bin" stitch \
    -c "$d/composite.png" -l "$d/labels.png" -o "$work/out_$label.tif" --depth 16 --compression none --threads 2 \
    --temp "$work/scratch" -q "$@"
}
for ((r = 1; r <= runs; ++r)); do
  run A "$gdp_a" "$lib_a" "$r" "$@"
  run B "$gdp_b" "$lib_b" "$r" "$@"
done
if cmp -s "$work/out_A.tif" "$work/out_B.tif"; then same="byte-identical"; else same="DIFFERENT"; fi
python3 - "$work" "$runs" "$size" "$same" <<'EOF'
import json, sys
work, runs, size, same = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4]
print(f"{size}x{size} stitch, A = old, B = new, interleaved; outputs {same}")
print("| run | build | CPU s | user s | sys s | minor faults | faults/Mpix | peak MB | wall s |")
print("|---|---|---|---|---|---|---|---|---|")
tot = {"A": [], "B": []}
mpix = int(size) ** 2 / 1e6
for r in range(1, runs + 1):
    for k in "AB":
        j = json.load(open(f"{work}/{k}_{r}.json"))
        cpu = j["user"] + j["sys"]
        tot[k].append((cpu, j["sys"]))
        print(f"| {r} | {k} | {cpu:.2f} | {j['user']:.2f} | {j['sys']:.2f} | {j['minor_faults']} | "
              f"{j['minor_faults'] / mpix:.0f} | {j['peak_rss_kb'] / 1024:.0f} | {j['wall']:.1f} |")
for k in "AB":
    c = sorted(x[0] for x in tot[k]); s = sorted(x[1] for x in tot[k])
    print(f"{k}: CPU median {c[len(c) // 2]:.2f} (min {c[0]:.2f}), sys median {s[len(s) // 2]:.2f}")
ca = sorted(x[0] for x in tot["A"]); cb = sorted(x[0] for x in tot["B"])
print(f"B/A CPU, medians: {cb[len(cb) // 2] / ca[len(ca) // 2]:.3f}x")
EOF
