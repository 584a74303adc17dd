# Sourced by the benchmark scripts: `shared_data REL` prints the path of a real image in the
# project's shared data folder (../shared/data beside the repository, or $GDP_SHARED_DATA), or
# names the missing file in one line and exits 2. The tests never need it (tests/data).
shared_data() {
  local dir=${GDP_SHARED_DATA:-$(cd "$(dirname "${BASH_SOURCE[0]}")/../.." && pwd)/shared/data}
  if [[ ! -f $dir/$1 ]]; then
    echo "$(basename "$0"): missing $dir/$1 (the shared data folder beside the repository; set GDP_SHARED_DATA to use another)" >&2
    exit 2
  fi
  printf '%s\n' "$dir/$1"
}

# `stitch_bench_setup NAME BUILD` sets what the stitch benchmarks share: $photo (the real photo
# their composites are cut from), $gdp (the binary of build folder BUILD under $here) and $work
# (a new scratch folder gdp-NAME.* removed on exit).
stitch_bench_setup() {
  photo=$(shared_data equirect/three-globe-npm/earth-blue-marble.jpg)
  gdp="$here/$2/tools/gdp/gdp"
  work=$(mktemp -d "${TMPDIR:-/tmp}/gdp-$1.XXXXXX")
  trap 'rm -rf "$work"' EXIT
}
