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
