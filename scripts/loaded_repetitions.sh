#!/usr/bin/env bash
# Runs the Release suite and the sanitizer suite N times in a row while stress-ng keeps every
# core busy: a test that depends on timing or on a free machine fails here, not in a user's CI.
# Usage: scripts/loaded_repetitions.sh [N=3] [LOG_DIR=loaded-runs]
# Needs build/ (scripts/test.sh) and build-asan/ (scripts/sanitize.sh) built; stress-ng from Debian.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
repetitions="${1:-3}"
log_dir="$(realpath -m "${2:-loaded-runs}")"
mkdir -p "$log_dir"
command -v stress-ng >/dev/null || { echo "loaded_repetitions: stress-ng is missing (apt-get install stress-ng)" >&2; exit 2; }
for need in build/CTestTestfile.cmake build-asan/CTestTestfile.cmake; do
  [ -f "$need" ] || { echo "loaded_repetitions: $need is missing: build both suites first" >&2; exit 2; }
done
load_workers="${LOAD_WORKERS:-$(nproc)}"
stress-ng --cpu "$load_workers" --timeout 0 --quiet &
stress_pid=$!
trap 'kill "$stress_pid" 2>/dev/null || true; wait "$stress_pid" 2>/dev/null || true' EXIT
echo "loaded_repetitions: stress-ng --cpu $load_workers beside the suites; logs in $log_dir" >&2
failed=0
summary="$log_dir/summary.txt"
: > "$summary"
for i in $(seq 1 "$repetitions"); do
  for suite in release sanitizer; do
    log="$log_dir/${suite}_$i.log"
    start=$(date +%s)
    if [ "$suite" = release ]; then
      status=0; (cd build && ctest --output-on-failure -j"${ADUGS_JOBS:-2}") > "$log" 2>&1 || status=$?
    else
      status=0; bash scripts/sanitize.sh > "$log" 2>&1 || status=$?
    fi
    result=$(grep -E "tests passed|tests failed" "$log" | tail -1 || true)
    line="repetition $i $suite: exit $status, $(( $(date +%s) - start )) s, ${result:-no ctest summary}"
    echo "$line" | tee -a "$summary" >&2
    [ "$status" = 0 ] || failed=$((failed + 1))
  done
done
echo "loaded_repetitions: $failed of $((2 * repetitions)) suite runs failed" | tee -a "$summary" >&2
[ "$failed" = 0 ]
