#!/usr/bin/env bash
# The one command that installs, builds and runs every test: scripts/test.sh
# Tests that need ../shared/data (real EuRoC data, detector models) skip with a message when it
# is absent; set ADUGS_SHARED_DATA=/path/to/shared/data to point elsewhere.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
start=$(date +%s)
bash scripts/setup.sh
cd build
ctest --output-on-failure -j"${ADUGS_JOBS:-2}"
echo "test.sh: build + tests took $(( $(date +%s) - start )) s" >&2
