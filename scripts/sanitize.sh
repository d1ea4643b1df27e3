#!/usr/bin/env bash
# Builds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer into build-asan/ and
# runs them. Any sanitizer report fails the run. The same build holds the libFuzzer targets
# (clang, -DADUGS_FUZZ=ON): scripts/fuzz.sh then runs them from build-asan without a build of its
# own (CI compiled the code three times before, 2026-12: one build less).
# It is a unity build (CMAKE_UNITY_BUILD: groups of 8 files compiled as one): the headers of
# Eigen, Ceres, OpenCV and ViSP are parsed once per group, not once per file. From nothing on
# 2 cores it takes ~17 min, where the per-file gcc build took ~48 and the fuzz build ~10 more.
# The price: helpers in anonymous namespaces of files that share a group must not share a name
# (a clash is a compile error here, not in the Release build: rename it or share it).
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"
# -g1: line tables only, enough for file:line in sanitizer reports; full -g debug info of the
# Eigen/Ceres-heavy code made this build much slower.
# ccache keys on paths relative to the checkout, so a fresh clone elsewhere reuses objects.
export CCACHE_BASEDIR="${CCACHE_BASEDIR:-$root}"
# With -g, ccache also hashes the working directory unless told not to: without this a clone in
# another folder (CI's) rebuilt everything (48 min on 2 cores) whatever the cache held.
export CCACHE_NOHASHDIR=1
CC=clang CXX=clang++ cmake -S . -B build-asan -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DADUGS_SANITIZE=ON -DADUGS_FUZZ=ON -DCMAKE_UNITY_BUILD=ON \
  -DADUGS_BUILD_BENCHMARKS=OFF -DCMAKE_CXX_FLAGS_RELWITHDEBINFO="-O2 -g1 -DNDEBUG"
cmake --build build-asan -j"${ADUGS_JOBS:-2}"
# One OpenMP thread: this clang build loads two OpenMP runtimes (clang's libomp for our code,
# gcc's libgomp through Ceres and ViSP), and with both, Eigen's parallel products came out wrong
# (2026-12-02: the marginalisation's eigenvectors far from orthonormal, J^T J = 2 H in
# WindowSolver.InformationFormPriorEqualsTheResidualForm; right with one thread and in the gcc
# Release build, which has libgomp only).
export OMP_NUM_THREADS=1
export ASAN_OPTIONS="detect_leaks=1:abort_on_error=1:strict_string_checks=1"
export UBSAN_OPTIONS="print_stacktrace=1:halt_on_error=1"
# Leaks inside third-party libraries (OpenCV's and ViSP's static singletons) are not ours.
export LSAN_OPTIONS="suppressions=$root/scripts/lsan.supp:print_suppressions=0"
cd build-asan
# The long accuracy and end-to-end runs run in the Release stage only: the list, with what
# each took under the sanitizers and which shorter tests keep their code paths covered here, is
# scripts/sanitize_release_only.txt. SANITIZE_ALL=1 runs every test.
mapfile -t release_only < <(grep -v '^#' "$root/scripts/sanitize_release_only.txt" | awk 'NF {print $1}')
exclude="^($(IFS='|'; echo "${release_only[*]}"))\$"
if [ "${SANITIZE_ALL:-0}" = 1 ]; then exclude='^$'; fi
ctest --output-on-failure -j"${ADUGS_JOBS:-2}" -E "$exclude"
