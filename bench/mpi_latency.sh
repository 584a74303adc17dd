#!/usr/bin/env bash
# Latency hiding under MPI: the same 2-rank band solve with and without delayed message delivery.
# Usage: bench/mpi_latency.sh [WIDTH=8192] [HEIGHT=1024] [DELAY_US=1000] [BUILD=build] [FROM=receive]
# Makes a WIDTH x HEIGHT RGB float image from a real photo, runs `gdp sharpen --bands 1` on
# 2 ranks, plain and with bench/mpi_delay (LD_PRELOAD: every message reaches the receiver's
# probe DELAY_US later), and prints the solve times and the throughput ratio (one run each:
# compare within a run). FROM: count the delay from the receiver's first probe for a message
# ("receive": every receive waits it) or from the message's arrival ("arrival": a network's
# latency, which a message sent early enough hides); see bench/mpi_delay/mpi_delay.cc.
set -euo pipefail
width=${1:-8192}
height=${2:-1024}
delay=${3:-1000}
build=${4:-build}
from=${5:-receive}
here=$(cd "$(dirname "$0")/.." && pwd)
source "$here/bench/shared_data.sh"
photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
gdp="$here/$build/tools/gdp/gdp"
lib="$here/$build/bench/libgdp_mpi_delay.so"
work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-mpilat.XXXXXX")
trap 'rm -rf "$work"' EXIT
oiiotool "$photo" --resize "${width}x${height}" \
  -d float -o "$work/in.exr"
run() {  # $1: name, then extra mpirun arguments
  local name=$1
  shift
  mpirun --oversubscribe --allow-run-as-root -np 2 "$@" "$gdp" sharpen "$work/in.exr" -o "$work/out.exr" \
    --bands 1 -q --stats "$work/$name.json"
}
run plain
run delayed -x LD_PRELOAD="$lib" -x GDP_MPI_DELAY_US="$delay" -x GDP_MPI_DELAY_FROM="$from"
python3 - "$work/plain.json" "$work/delayed.json" "$delay" <<'PY'
import json, sys
p, d = (json.load(open(f)) for f in sys.argv[1:3])
for key in ("vcycles", "total"):
    a, b = p["seconds"][key], d["seconds"][key]
    print(f"{key}: plain {a:.2f} s, {sys.argv[3]} us per message {b:.2f} s, throughput ratio {a / b:.3f}")
PY
