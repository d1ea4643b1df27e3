#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, AddressSanitizer + UndefinedBehaviorSanitizer) in build-fuzz
# and runs each one for a bounded time.
#   scripts/fuzz.sh [fuzz_csv|fuzz_yaml|fuzz_onnx|fuzz_device|fuzz_image ...]
#   FUZZ_SECONDS  seconds per target (default 60)      FUZZ_JOBS  build jobs (default 2)
#   FUZZ_BUILD_DIR (default <repo>/build-fuzz; a build already configured with -DADUGS_FUZZ=ON, such
#   as scripts/sanitize.sh's build-asan, is used as it is: CI runs the targets from there)
# Fails (exit 1) if a target crashes, throws anything but InputError, trips a sanitizer, leaks or
# times out. The reproducer is written to $FUZZ_BUILD_DIR/fuzz-artifacts/ and the log to
# $FUZZ_BUILD_DIR/fuzz-<target>.log; replay with: $FUZZ_BUILD_DIR/tests/fuzz/<target> <file>
# Inputs found along the way accumulate in $FUZZ_BUILD_DIR/fuzz-corpus/ (the checked-in seeds in
# tests/fuzz/corpus/ are only read).
set -euo pipefail

repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${FUZZ_BUILD_DIR:-$repo/build-fuzz}"
seconds="${FUZZ_SECONDS:-60}"
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(fuzz_csv fuzz_yaml fuzz_onnx fuzz_device fuzz_image)

mkdir -p "$build"
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$repo}"
# RelWithDebInfo has -g, for which ccache hashes the working directory unless told not to.
export CCACHE_NOHASHDIR=1
if ! grep -qx "ADUGS_FUZZ:BOOL=ON" "$build/CMakeCache.txt" 2>/dev/null; then
  CC=clang CXX=clang++ cmake -S "$repo" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    -DADUGS_FUZZ=ON -DADUGS_BUILD_TESTS=OFF -DADUGS_BUILD_BENCHMARKS=OFF >"$build/configure.log" 2>&1 ||
    { cat "$build/configure.log"; exit 1; }
fi
cmake --build "$build" -j "${FUZZ_JOBS:-2}" --target "${targets[@]}"

export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:${ASAN_OPTIONS:-}"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:${UBSAN_OPTIONS:-}"
mkdir -p "$build/fuzz-artifacts"
status=0
for target in "${targets[@]}"; do
  kind="${target#fuzz_}"
  work="$build/fuzz-corpus/$kind"
  log="$build/fuzz-$target.log"
  mkdir -p "$work"
  args=(-max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -max_len=4096 -print_final_stats=1
        -artifact_prefix="$build/fuzz-artifacts/$target-")
  [ -f "$repo/tests/fuzz/$kind.dict" ] && args+=(-dict="$repo/tests/fuzz/$kind.dict")
  # Any single allocation above this is a bug for images: the harness skips headers of more than
  # 4 Mpixels, so a bigger one can only come from a length field believed (a PNG chunk's, once).
  [ "$kind" = image ] && args+=(-malloc_limit_mb=256)
  echo "== $target: ${seconds}s"
  rc=0
  # Seeds: the checked-in corpus, and real files of the project read only (libFuzzer writes to the
  # first folder alone): the run configs and the datasets' Kalibr files for YAML, the evaluation
  # reference trajectories for CSV.
  seeds=("$repo/tests/fuzz/corpus/$kind")
  case "$kind" in
    yaml) seeds+=("$repo/data/config" "$repo"/data/config/presets/*/)
          # Other tools' calibration files when exported (scripts/export_third_party_calibrations.sh).
          if [ -n "${ADUGS_THIRD_PARTY_CALIB:-}" ]; then
            while IFS= read -r d; do seeds+=("$d"); done < <(find "$ADUGS_THIRD_PARTY_CALIB" -type d)
          fi ;;
    csv) seeds+=("$repo/tests/data/reference") ;;
    # Real PNGs and JPEGs of every kind opencv-doc has (grey+alpha, RGBA, palette, RGB; JPEG colour
    # and grey), the small ones: copied into the build folder (the samples folder holds videos too).
    image) sample_dir=/usr/share/doc/opencv-doc/examples/data
           mkdir -p "$build/fuzz-seeds-image"
           for f in mask.png templ.png tmpl.png imageTextN.png pic5.png blox.jpg HappyFish.jpg LinuxLogo.jpg left01.jpg; do
             [ -f "$sample_dir/$f" ] && cp "$sample_dir/$f" "$build/fuzz-seeds-image/"
           done
           seeds+=("$build/fuzz-seeds-image") ;;
  esac
  "$build/tests/fuzz/$target" "${args[@]}" "$work" "${seeds[@]}" >"$log" 2>&1 || rc=$?
  grep -E "stat::number_of_executed_units|stat::peak_rss_mb" "$log" || true
  grep -E "^#[0-9]+ +DONE" "$log" || true
  if [ "$rc" -ne 0 ]; then
    echo "FAIL: $target exited with $rc; log: $log"
    grep -E "BUG:|ERROR:|SUMMARY:|runtime error|Test unit written|deadly signal|timeout" "$log" | head -20 || true
    status=1
  else
    echo "ok: $target"
  fi
done
exit "$status"
