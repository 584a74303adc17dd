#!/usr/bin/env bash
# Two gdp builds, A (old) and B (new), run interleaved (A, B, A, B, ...) on the same input: CPU
# seconds (user + sys), peak RSS, wall and --stats phases per run, whether their outputs are the
# same bytes (cmp), and B/A of the median CPU. On a shared machine compare CPU seconds, not walls.
#
#   bench/ab.sh MODE OLD NEW [SIZE] [RUNS] [-- extra gdp flags]
#
# MODE (SIZE default 8192 in all):
#   stitch      gdp stitch on vs_dmg.sh's SIZE x SIZE PNG composite and labels (made once into
#               ${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/SIZE by bench/make_composite), 16-bit
#               uncompressed TIFF out, --threads 2. RUNS default 3. Measured by bench/measure_run.py.
#   blend       gdp blend on bench/blend_vs_enblend.sh's layers (GRID, default 4x4, made once into
#               ${GDP_BENCH_DIR:-/tmp/gdp-blend-bench} by bench/blend_layers), then each build's
#               critical path on 2 idle cores (bench/critical_path.py, where perf is installed).
#               RUNS default 2. Measured by bench/measure_run.py.
#   input-pass  gdp stitch's input pass (issue 17): a composite of uncompressed TIFFs (decoding is
#               cheap), --bands 1 then 2 each run; each thread's CPU (bench/thread_cpu.py) and the
#               --stats input pass (seconds.rhs, and its decoding thread's and readers' CPU where
#               the binary reports them). RUNS default 2. MAKE_COMPOSITE: the generator to use
#               where build/ has none.
# OLD and NEW: build folders (tools/gdp/gdp and lib/), folders holding copies of gdp and libgdp
# (so that a rebuild cannot change them mid-run: mkdir -p DIR && cp build/tools/gdp/gdp
# build/lib/libgdp.so.* DIR/), or gdp binaries. The inputs are cut from the blue-marble photo in
# ../shared/data (exit 2 when it is missing); scratch goes to a folder removed on exit.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
me=$(basename "$0")
usage() { sed -n '2,/^set -e/p' "$0" | sed '$d; s/^# \{0,1\}//' >&2; exit 2; }
(($# >= 3)) || usage
mode=$1 old=$2 new=$3
shift 3
case $mode in stitch) runs=3 ;; blend | input-pass) runs=2 ;; *) usage ;; esac
size=8192
[[ $# -gt 0 && $1 != -- ]] && { size=$1; shift; }
[[ $# -gt 0 && $1 != -- ]] && { runs=$1; shift; }
[[ ${1:-} == -- ]] && shift
exe() {  # build folder, folder of copies or binary -> the gdp binary and the library folder for it
  local d=$1
  if [[ -f $d && -x $d ]]; then echo "$(realpath "$d") $(realpath "$(dirname "$d")")"
  elif [[ -x $d/tools/gdp/gdp ]]; then echo "$(realpath "$d/tools/gdp/gdp") $(realpath "$d/lib")"
  elif [[ -x $d/gdp && -d $d/lib ]]; then echo "$(realpath "$d/gdp") $(realpath "$d/lib")"
  elif [[ -x $d/gdp ]]; then echo "$(realpath "$d/gdp") $(realpath "$d")"
  else echo "$me: no gdp binary in $d" >&2; exit 2; fi
}
read -r gdp_A lib_A < <(exe "$old")
read -r gdp_B lib_B < <(exe "$new")
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-ab.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/scratch"
measure=measure_run.py variants=("")
case $mode in
  stitch)
    d=${GDP_BENCH_DIR:-/tmp/gdp-vs-dmg}/$size
    if [[ ! -f $d/labels.png ]]; then
      mkdir -p "$d"
      "$here/build/bench/make_composite" "$photo" "$size" "$size" "$d/composite.png" "$d/labels.png" 1024 "$d/truth.tif"
    fi
    args=(stitch -c "$d/composite.png" -l "$d/labels.png" --depth 16 --compression none --threads 2) ;;
  blend)
    grid=${GRID:-4x4}
    d=${GDP_BENCH_DIR:-/tmp/gdp-blend-bench}/${size}_${grid}_v0.3
    mkdir -p "$d"
    [[ -f $d/original.tif ]] || "$here/build/bench/blend_layers" cut "$photo" "$d" --size "${size}x${size}" \
      --grid "$grid" --overlap 0.2 --offset 40 --vignette 0.3 --seed 7
    args=(blend) variants=("-- $(echo "$d"/layer_*.tif)") ;;
  input-pass)
    "${MAKE_COMPOSITE:-$here/build/bench/make_composite}" "$photo" "$size" "$size" "$work/composite.tif" \
      "$work/labels.tif" $((size / 16))
    args=(stitch -c "$work/composite.tif" -l "$work/labels.tif" --compression none)
    measure=thread_cpu.py variants=("--bands 1" "--bands 2") ;;
esac
for ((r = 1; r <= runs; ++r)); do
  for v in "${!variants[@]}"; do
    for side in A B; do
      bin=gdp_$side lib=lib_$side
      read -ra flags <<< "${variants[$v]}"
      # The variant's flags go last: blend's layers follow its "--".
      LD_LIBRARY_PATH=${!lib} python3 "$here/bench/$measure" "$work/${side}_${v}_$r.json" -- "${!bin}" \
        "${args[@]}" -q --temp "$work/scratch" --stats "$work/${side}_${v}_$r.stats.json" \
        -o "$work/out_${side}_$v.tif" "$@" "${flags[@]}"
    done
  done
done
same=()
for v in "${!variants[@]}"; do
  cmp -s "$work/out_A_$v.tif" "$work/out_B_$v.tif" && same+=("byte-identical") || same+=("DIFFERENT")
done
python3 - "$work" "$mode" "$size" "$runs" "${#variants[@]}" "${variants[@]/#-- */}" -- "${same[@]}" <<'EOF'
import json, sys
work, mode, size, runs, n = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4]), int(sys.argv[5])
names, same = sys.argv[6:6 + n], sys.argv[7 + n:]
mpix = size * size / 1e6
print(f"{size}x{size} {mode}, A = old, B = new, interleaved")
print("| run | variant | build | CPU s | user s | sys s | peak MB | wall s | phases (--stats seconds) |")
print("|---|---|---|---|---|---|---|---|---|")
cpu = {}
for r in range(1, runs + 1):
    for v in range(n):
        for k in "AB":
            j = json.load(open(f"{work}/{k}_{v}_{r}.json"))
            stats = json.load(open(f"{work}/{k}_{v}_{r}.stats.json"))
            s = {**stats["seconds"], **{p: t for p, t in stats.items() if p.startswith("seconds_") and p != "seconds_total"}}
            c = j["cpu"] if "cpu" in j else j["user"] + j["sys"]
            cpu.setdefault((v, k), []).append(c)
            phases = ", ".join(f"{p} {t:.2f}" for p, t in s.items() if isinstance(t, (int, float)))
            if "main" in j:  # thread_cpu.py: the main thread and the busiest others
                phases += (f"; main thread {j['main']:.2f} CPU-s ({1e3 * j['main'] / mpix:.1f} ns/px), others "
                           + ", ".join(f"{t:.2f}" for t in j["threads"][:4]))
            user, sys_s = (f"{j['user']:.2f}", f"{j['sys']:.2f}") if "user" in j else ("-", "-")
            peak = f"{j['peak_rss_kb'] / 1024:.0f}" if "peak_rss_kb" in j else "-"
            print(f"| {r} | {names[v] or '-'} | {k} | {c:.2f} | {user} | {sys_s} | {peak} | {j['wall']:.1f} | {phases} |")
for v in range(n):
    a, b = sorted(cpu[(v, "A")]), sorted(cpu[(v, "B")])
    print(f"{names[v] or mode}: outputs {same[v]}; CPU medians A {a[len(a) // 2]:.2f}, B {b[len(b) // 2]:.2f}: "
          f"B/A {b[len(b) // 2] / a[len(a) // 2]:.3f}x")
EOF
if [[ $mode == blend ]]; then
  command -v perf > /dev/null || { echo "critical path: skipped (no perf)"; exit 0; }
  for side in A B; do
    bin=gdp_$side lib=lib_$side
    echo "critical path, $side (load $(cut -d' ' -f1 /proc/loadavg)):"
    python3 "$here/bench/critical_path.py" -- env LD_LIBRARY_PATH="${!lib}" "${!bin}" blend -q -o "$work/cp.tif" \
      --temp "$work/scratch" "$@" -- "$d"/layer_*.tif
  done
fi
