#!/usr/bin/env bash
# A Table III-like sweep on a many-core machine: stitch throughput (Mpix/s) against the number of bands, from a pack of bench/device/pack.sh.
# Usage: bench/device/scaling.sh PACK OUTDIR        (docs/scaling.md: the command for a lent machine)
# Makes the inputs itself (PACK/bin/make_composite from the packed photo, uncompressed TIFF, one
# generator per size in parallel), then per size of the sweep runs `gdp stitch` with each band
# count, one worker per band (--threads = bands + 2: the two codec threads), scratch in memory
# (--memory, default 64G: all of it fits), under measure_run.py (wall, user+sys CPU, peak RSS) and
# `timeout`, and checks every banded output against the one-band output with PACK/bin/image_diff
# (tolerance: 2e-4 of the value range for float outputs, what docs/how-bands-work.md states for
# images wider than 512 columns; one step more for integer outputs). Then, while the time budget allows (estimated from the sweep's walls),
# one run with every scratch store in files (--memory 0; checked against the same bands' in-memory
# run, where the same bits are expected) and the gigapixel runs. GDP_SCALING_OWN_GLIBC=1
# runs the programs on the packed glibc even where the machine's would do. OUTDIR receives
# scaling.md and scaling.json after every run (so a cut-off run still leaves its table) and log.txt.
# Settings (environment):
#   GDP_SCALING_SIZES="16384"       square sizes of the band sweep
#   GDP_SCALING_BANDS="1 2 4 8 16"  band counts (the first is the reference of the speedups and checks)
#   GDP_SCALING_GIGA=32768          size of the large runs ("" for none)
#   GDP_SCALING_GIGA_BANDS="1 16"   their band counts (checked against the first)
#   GDP_SCALING_DISK="16384:16"     SIZE:BANDS of the run with scratch in files ("" for none)
#   GDP_SCALING_MEMORY=64G          --memory of the other runs
#   GDP_SCALING_DEPTH=float         output samples of the sweep; GDP_SCALING_GIGA_DEPTH=8 of the large runs
#   GDP_SCALING_BUDGET=450          seconds for the whole script; optional runs that would pass it are skipped
#   GDP_SCALING_TIMEOUT=300         seconds for one run at most
#   GDP_SCALING_THREADS=""          --threads of every run ("": bands + 2, one worker per band)
#   TMPDIR=/tmp                     where inputs, outputs and scratch go (a tmpfs takes the disk out)
set -euo pipefail
[[ $# -eq 2 ]] || { echo "usage: $0 PACK OUTDIR" >&2; exit 2; }
here=$(cd "$(dirname "$0")/../.." && pwd)
pack=$(cd "$1" && pwd)
mkdir -p "$2"
out=$(cd "$2" && pwd)
# The packed programs run with the pack's libraries (only they: python3 and the tools keep the
# machine's), on the machine's glibc when it is at least the pack's, else on the packed one.
need=$(sed 's/GLIBC_//' "$pack/GLIBC")
have=$(getconf GNU_LIBC_VERSION 2>/dev/null | awk '{print $2}') || true
if [[ -z ${GDP_SCALING_OWN_GLIBC:-} && $(printf '%s\n%s\n' "$need" "${have:-0}" | sort -V | head -1) == "$need" ]]; then
  launch=(env "LD_LIBRARY_PATH=$pack/lib")
else
  launch=("$pack/glibc/ld-linux-x86-64.so.2" --library-path "$pack/lib:$pack/glibc")
fi
sizes=${GDP_SCALING_SIZES-16384}
bands=${GDP_SCALING_BANDS-1 2 4 8 16}
giga=${GDP_SCALING_GIGA-32768}
giga_bands=${GDP_SCALING_GIGA_BANDS-1 16}
disk=${GDP_SCALING_DISK-16384:16}
memory=${GDP_SCALING_MEMORY-64G}
depth=${GDP_SCALING_DEPTH-float}
giga_depth=${GDP_SCALING_GIGA_DEPTH-8}
budget=${GDP_SCALING_BUDGET-450}
run_limit=${GDP_SCALING_TIMEOUT-300}
threads=${GDP_SCALING_THREADS-}
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-scaling.XXXXXX")
trap 'rm -rf "$work"' EXIT
runs=$out/runs.jsonl
: > "$runs"
exec > >(tee "$out/log.txt") 2>&1
t0=$SECONDS
say() { printf '[%4ds] %s\n' $((SECONDS - t0)) "$*"; }
say "glibc here ${have:-unknown}, the pack needs $need: running the programs as ${launch[*]} PROGRAM"
table() { python3 "$here/bench/device/scaling_table.py" "$runs" "$out/machine.json" "$out" || say "table failed"; }

python3 - "$out/machine.json" "$pack" "$memory" "$budget" "${threads:-bands + 2}" <<'PY'
import json, os, platform, shutil, sys
cpu = next((l.split(":", 1)[1].strip() for l in open("/proc/cpuinfo") if l.startswith("model name")), "?")
mem = next(int(l.split()[1]) for l in open("/proc/meminfo") if l.startswith("MemTotal")) / 2**20
tmp = shutil.disk_usage(os.environ.get("TMPDIR", "/tmp"))
try:
    quota = open("/sys/fs/cgroup/cpu.max").read().strip()  # "max 100000" or "QUOTA PERIOD"
except OSError:
    quota = None
m = dict(cpu=cpu, cores=len(os.sched_getaffinity(0)), cpus_online=os.cpu_count(), cgroup_cpu_max=quota, memory_gib=round(mem, 1), tmp_free_gib=round(tmp.free / 2**30, 1),
         glibc=" ".join(platform.libc_ver()), kernel=platform.release(),
         pack_needs=open(f"{sys.argv[2]}/GLIBC").read().strip(), memory_option=sys.argv[3], budget_s=int(sys.argv[4]), threads=sys.argv[5],
         scratch_dir=os.environ.get("TMPDIR", "/tmp"))
json.dump(m, open(sys.argv[1], "w"), indent=1)
print("machine:", json.dumps(m))
PY

# Inputs: one make_composite per size, in parallel (each is one thread).
declare -A made
for s in $sizes ${giga}; do
  [[ -n ${made[$s]:-} ]] && continue
  "${launch[@]}" "$pack/bin/make_composite" "$pack/data/earth-blue-marble.jpg" "$s" "$s" "$work/c$s.tif" "$work/l$s.tif" $((s / 16)) &
  made[$s]=$!
done
say "making inputs for sizes: ${!made[*]}"
for s in "${!made[@]}"; do wait "${made[$s]}" || say "make_composite $s FAILED: its runs will fail"; done
say "inputs made: $(du -sh "$work" | cut -f1)"

declare -A wall  # "SIZE:BANDS" -> wall seconds of the in-memory run
# run NAME SIZE BANDS MEMORY DEPTH REF: one stitch, measured; REF names the run it is checked against.
run() {
  local name=$1 s=$2 b=$3 mem=$4 dep=$5 ref=$6 rc=0 limit t=${threads:-$(($3 + 2))}
  limit=$((budget - (SECONDS - t0) + 30))
  ((limit > run_limit)) && limit=$run_limit
  ((limit < 10)) && limit=10
  say "run $name: ${s}x$s, --bands $b --threads $t --memory $mem, depth $dep (limit ${limit}s)"
  python3 "$here/bench/measure_run.py" "$work/$name.time.json" -- timeout "$limit" "${launch[@]}" "$pack/bin/gdp" stitch \
    -c "$work/c$s.tif" -l "$work/l$s.tif" -o "$work/$name.tif" --compression none --depth "$dep" -q \
    --bands "$b" --threads "$t" --memory "$mem" --temp "$work" --stats "$work/$name.stats.json" || rc=$?
  if ((rc == 0)) && [[ -n $ref && $ref != "$name" && -f $work/$ref.tif ]]; then
    "${launch[@]}" "$pack/bin/image_diff" "$work/$ref.tif" "$work/$name.tif" > "$work/$name.diff.json" ||
      say "image_diff failed (exit $?)"
    [[ -s $work/$name.diff.json ]] && say "against $ref: $(cat "$work/$name.diff.json")"
  fi
  [[ $name == "$ref" || $name == "$keep" ]] || rm -f "$work/$name.tif"  # only references stay
  python3 - "$runs" "$name" "$s" "$b" "$mem" "$dep" "$ref" "$rc" "$work/$name" <<'PY'
import json, sys
runs, name, size, bands, memory, depth, ref, rc, base = sys.argv[1:]
def load(path):
    try:
        return json.load(open(path))
    except (OSError, ValueError):
        return None
run = dict(name=name, size=int(size), bands=int(bands), memory=memory, depth=depth, ref=ref, rc=int(rc),
           time=load(base + ".time.json"), stats=load(base + ".stats.json"), diff=load(base + ".diff.json"))
open(runs, "a").write(json.dumps(run) + "\n")
PY
  if ((rc == 0)); then
    [[ $mem == 0 ]] || wall[$s:$b]=$(python3 -c "import json,sys; print(json.load(open(sys.argv[1]))['wall'])" "$work/$name.time.json")
    say "run $name done: $(python3 -c "import json,sys; t=json.load(open(sys.argv[1])); print(f\"{t['wall']:.1f} s wall, {t['user']+t['sys']:.1f} CPU-s, peak {t['peak_rss_kb']/1024:.0f} MB\")" "$work/$name.time.json")"
  else
    say "run $name FAILED (exit $rc; 124: over its ${limit}s limit)"
  fi
  table
}
# fits S B FACTOR: whether a run of S x S with B bands, estimated from the nearest measured run
# (same bands, else the one-band run) scaled by the pixel count and FACTOR, ends inside the budget.
fits() {
  local s=$1 b=$2 f=$3 est
  est=$(python3 - "$s" "$b" "$f" "$((budget - (SECONDS - t0)))" "${!wall[@]}" "${wall[@]}" <<'PY'
import sys
s, b, f, left = int(sys.argv[1]), int(sys.argv[2]), float(sys.argv[3]), float(sys.argv[4])
n = (len(sys.argv) - 5) // 2
walls = {tuple(map(int, k.split(":"))): float(v) for k, v in zip(sys.argv[5:5 + n], sys.argv[5 + n:])}
cands = [(k, v) for k, v in walls.items() if k[1] == b] or [(k, v) for k, v in walls.items() if k[1] == 1]
if not cands:
    print(-1); sys.exit()
(ks, kb), v = max(cands)
print(int(v * (s / ks) ** 2 * f) if int(v * (s / ks) ** 2 * f) < left else -1)
PY
)
  if ((est < 0)); then say "skipped ${s}x$s --bands $b: over the time left"; return 1; fi
  say "estimate for ${s}x$s --bands $b: ${est}s"
}

keep=""  # the sweep run the files run is checked against (the same bits are expected)
[[ -z $disk ]] || keep=s${disk%:*}-b${disk#*:}
for s in $sizes; do
  ref=""
  for b in $bands; do
    name=s$s-b$b
    run "$name" "$s" "$b" "$memory" "$depth" "${ref:-$name}"
    ref=${ref:-$name}
  done
done
if [[ -n $disk ]]; then
  s=${disk%:*} b=${disk#*:}
  if [[ -f $work/c$s.tif ]] && fits "$s" "$b" 1.5; then run "$keep-files" "$s" "$b" 0 "$depth" "$keep"; fi
fi
rm -f "$work"/s*-b*.tif
if [[ -n $giga ]]; then
  ref=""
  for b in $giga_bands; do
    name=s$giga-b$b
    fits "$giga" "$b" 1.2 || continue
    run "$name" "$giga" "$b" "$memory" "$giga_depth" "${ref:-$name}"
    ref=${ref:-$name}
  done
  rm -f "$work/$ref.tif"
fi
say "done; $out/scaling.md:"
cat "$out/scaling.md"
