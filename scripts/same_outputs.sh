#!/usr/bin/env bash
# Do two adugs builds give the same outputs? For refactors that must change no behaviour: runs
# both binaries on the same inputs and compares what they write byte for byte (trajectories,
# simulated sequences, tracks, calibration files; summary.yaml without its timing lines).
#   scripts/same_outputs.sh ADUGS_BEFORE ADUGS_AFTER [OUT_DIR]
# Inputs: the README demo's sequence (room/high seed 6, 30 s, --mask none and gt), a street/high
# sequence through the detector chain (YOLOX-nano + SORT + GrabCut, ../shared/models), a static
# handheld and an untuned courtyard sequence (60 s), the hybrid EuRoC V1_01 flight (its first
# 40 s; ../shared/data), `adugs track` on vtest.avi (opencv-doc) and `adugs calib intrinsics` on
# EuRoC's cam_april detections. The calibration is compared to 1e-9 relative: Ceres' threads make
# it differ in the last digits from one run of the same binary to the next. Exit 0 when everything
# is the same, 1 otherwise (lists what differs).
set -euo pipefail
[ $# -ge 2 ] || { sed -n '2,11p' "$0"; exit 2; }
before="$(realpath "$1")" after="$(realpath "$2")"
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
out="${3:-/tmp/adugs_same_outputs}"
shared="${ADUGS_SHARED_DATA:-$root/../shared/data}"
models="$(dirname "$shared")/models"
euroc="$shared/euroc_v101_micro"
vtest=/usr/share/doc/opencv-doc/examples/data/vtest.avi
rm -rf "$out" && mkdir -p "$out"

# name|adugs sim options
sims=(
  "room_high_s6|--scene room --level high --seed 6 --duration 30"
  "street_high_s3|--scene street --level high --seed 3 --duration 20 --people walkers"
  "street_handheld_s2|--scene street --motion handheld --level none --seed 2 --duration 60"
  "courtyard_glide_s1|--scene courtyard --motion glide --level none --seed 1 --duration 60"
  "hybrid_v101|--scene room --trajectory $euroc/groundtruth/V1_01_easy_vicon2gt.csv --imu $euroc/mav0/imu0/data.csv --calib $euroc/mav0/cam0/sensor.yaml --duration 40 --level none"
)
# name|sequence|adugs run options
runs=(
  "demo_unmasked|room_high_s6|--config $root/data/config/sim.yaml --mask none"
  "demo_masked|room_high_s6|--config $root/data/config/sim.yaml --mask gt"
  "street_chain|street_high_s3|--mask detector --detector-model $models/yolox_nano/yolox_nano.onnx"
  "street_handheld|street_handheld_s2|"
  "courtyard|courtyard_glide_s1|"
  "hybrid|hybrid_v101|"
)

jobs=()
for which in before after; do
  bin="$before"; [ "$which" = after ] && bin="$after"
  for s in "${sims[@]}"; do
    jobs+=("$bin sim ${s#*|} --out $out/$which/seq/${s%%|*} > $out/$which/sim_${s%%|*}.log 2>&1")
  done
done
mkdir -p "$out/before/seq" "$out/after/seq"
printf '%s\n' "${jobs[@]}" | parallel -j2 --halt now,fail=1

jobs=()
for which in before after; do
  bin="$before"; [ "$which" = after ] && bin="$after"
  for r in "${runs[@]}"; do
    IFS='|' read -r name seq opts <<< "$r"
    # Both binaries read the sequence `before` wrote (the sequences are compared separately).
    jobs+=("$bin run -q $out/before/seq/$seq $opts --out $out/$which/run/$name > $out/$which/run_$name.log 2>&1")
  done
  [ -f "$vtest" ] && jobs+=("$bin track $vtest --detector-model $models/yolox_nano/yolox_nano.onnx --segmenter grabcut --masks --out $out/$which/track > $out/$which/track.log 2>&1")
  jobs+=("$bin calib intrinsics --corners $shared/euroc_calib_aprilgrid/cam_april/cam0 --resolution 752x480 --out $out/$which/calib > $out/$which/calib.log 2>&1 || true")
done
printf '%s\n' "${jobs[@]}" | parallel -j2 --halt now,fail=1

status=0
compared=0
while IFS= read -r -d '' f; do
  rel="${f#$out/before/}"
  g="$out/after/$rel"
  case "$rel" in
    *.log|*.png|*.pdf|*.avi|*.mp4) continue ;;  # logs carry timings; pictures are drawn from the files compared here
  esac
  compared=$((compared + 1))
  if [ ! -f "$g" ]; then echo "missing after: $rel"; status=1; continue; fi
  timing='_ms|_s:|seconds|realtime|real_time|wall|latency|_median|_mean|config:'
  if [[ "$rel" == *summary.yaml || "$rel" == *record.yaml ]]; then
    if ! diff <(grep -vE "$timing" "$f") <(grep -vE "$timing" "$g") > /dev/null; then
      echo "differs: $rel"; status=1
    fi
  elif [[ "$rel" == calib/* ]]; then
    if ! /usr/bin/python3 - "$f" "$g" <<'PY'
import re, sys
number = re.compile(r"-?\d+\.?\d*(?:[eE][-+]?\d+)?")
a, b = (open(p).read().split("\n") for p in sys.argv[1:3])
same = len(a) == len(b)
for x, y in zip(a, b):
    if re.search(r"\d s[,)]", x):  # the report's timings
        continue
    nx, ny = number.findall(x), number.findall(y)
    same = same and number.sub("#", x) == number.sub("#", y) and len(nx) == len(ny) and all(
        abs(float(u) - float(v)) <= 1e-9 * max(1.0, abs(float(u))) for u, v in zip(nx, ny))
sys.exit(0 if same else 1)
PY
    then
      echo "differs: $rel"; status=1
    fi
  elif ! cmp -s "$f" "$g"; then
    echo "differs: $rel"; status=1
  fi
done < <(find "$out/before" -type f -print0)
echo "same_outputs: $compared files compared, $([ $status -eq 0 ] && echo 'all identical' || echo 'some differ')"
exit $status
