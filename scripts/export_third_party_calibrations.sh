#!/usr/bin/env bash
# Exports the calibration files that ship with OpenVINS, VINS-Fusion, VINS-Mono and Basalt from
# git snapshots of their repositories into OUT, for tests/data/test_third_party_calibrations.cpp
# (which reads them from $ADUGS_THIRD_PARTY_CALIB and skips, with this hint, without them).
# Nothing of theirs enters this repository.
#   scripts/export_third_party_calibrations.sh OUT open_vins.git VINS-Fusion.git VINS-Mono.git basalt.git
# Each argument after OUT is a git dir (bare or not) or a clone; its name picks what is exported.
set -euo pipefail
out="$1"; shift
mkdir -p "$out"
for repo in "$@"; do
  git_dir="$repo"; [ -d "$repo/.git" ] && git_dir="$repo/.git"
  case "$repo" in
    *open_vins*) name=open_vins; paths=(config) ;;
    *VINS-Fusion*) name=VINS-Fusion; paths=(config) ;;
    *VINS-Mono*) name=VINS-Mono; paths=(config) ;;
    *basalt*) name=basalt; paths=(data) ;;
    *) echo "export_third_party_calibrations: do not know which files of $repo to take" >&2; exit 2 ;;
  esac
  mkdir -p "$out/$name"
  git --git-dir="$git_dir" archive HEAD "${paths[@]}" | tar -x -C "$out/$name"
  echo "$name: $(git --git-dir="$git_dir" rev-parse HEAD) -> $out/$name"
done
