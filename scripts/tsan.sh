#!/usr/bin/env bash
# Builds `adugs` with ThreadSanitizer into build-tsan/ and runs the threaded pipeline
# (app/pipeline/) on a short generated dynamic sequence with ground-truth masks: a playback with
# the overlay view, then the live path (`adugs live --replay`) with an estimator slowed so that
# frames are dropped, the view, and a SIGINT half-way (about 3 minutes after the build). Any race
# report fails. Not part of CI (the extra build takes about 25 minutes on 2 cores). The
# detector chain is not covered: OpenCV dnn's TBB workers are not instrumented, so every read of a
# network output shows as a race and a 20-frame run takes over 5 minutes. Usage: scripts/tsan.sh
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
cmake -S . -B build-tsan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DADUGS_TSAN=ON \
  -DADUGS_BUILD_BENCHMARKS=OFF
cmake --build build-tsan -j"${ADUGS_JOBS:-2}" --target adugs
export TSAN_OPTIONS="halt_on_error=1 suppressions=$root/scripts/tsan.supp"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
build-tsan/app/adugs sim --scene room --level high --seed 7 --duration 10 --out "$work/seq" >/dev/null
build-tsan/app/adugs run "$work/seq" --mask gt --overlay "$work/run_gt/view.avi" --out "$work/run_gt"
printf 'pipeline:\n  test_estimator_delay_ms: 60\n' >"$work/slow.yaml"
build-tsan/app/adugs live --replay "$work/seq" --mask gt --no-window --config "$work/slow.yaml" \
  --overlay "$work/live/view.avi" --out "$work/live" &
live=$!
sleep 6
kill -INT "$live"
wait "$live"
grep -q "^end: stopped" "$work/live/summary.yaml"
echo "tsan: no data race reported" >&2
