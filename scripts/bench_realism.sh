#!/usr/bin/env bash
# What a real camera adds, against OpenVINS on the same images (issue 29, "Realism"): hybrid
# flights (the real V1_01 IMU and ground truth of ../shared/data, images rendered along the true
# trajectory) with one effect at a time and all together:
#   clean        no lens distortion, pixel noise 1 grey level (the table's reference)
#   distortion   EuRoC's radial-tangential lens (the renders go through it; both systems undistort)
#   blur         motion blur from the true motion over a 10 ms exposure (5 renders averaged)
#   noise        pixel noise 3 grey levels
#   exposure     auto-exposure steps: gain 1 +- 0.2 (two sines, 6.3 s and 1.9 s)
#   vignetting   30 % less light in the farthest corner
#   all          every effect above at once
# Each flight is start:length:seed (seconds of the V1_01 flight, cut from the real files; the seed
# draws the pixel noise). OpenVINS' stock EuRoC config initialises from standstill, which V1_01
# has only at its start: flights that start later leave it uninitialised, so the default flights
# start at 0 and differ in length and seed. Each sequence goes through ../shared/tools/openvins/compare.sh (ATE over the same poses, CPU,
# memory), and the table gives per flight and effect OpenVINS' ATE, adugs' ATE and their ratio,
# then per effect the geometric mean of the ratios. Finished runs are kept and skipped on a rerun.
#
# Usage: scripts/bench_realism.sh [--flights "0:40:1 0:40:2 0:80:1"] [--effects "clean distortion ..."]
#          [--out DIR] [--adugs BIN] [--label L] [--adugs-options "--config C.yaml ..."]
# --adugs-options are passed to `adugs run`; with --label L its results go to DIR/compare_L, so an
# estimator option is measured on the same rendered sequences (rendered once per DIR).
# Needs OpenVINS built (../shared/tools/openvins/README.md) and ../shared/data.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="$root/build/app/adugs"
adugs_options="" label=""
out=/tmp/adugs_bench_realism
flights="0:40:1 0:40:2 0:80:1"
effects="clean distortion blur noise exposure vignetting all"
while [ $# -gt 0 ]; do
  case "$1" in
    --flights) flights="$2"; shift 2 ;;
    --effects) effects="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --adugs) adugs="$2"; shift 2 ;;
    --adugs-options) adugs_options="$2"; shift 2 ;;
    --label) label="$2"; shift 2 ;;
    *) echo "bench_realism: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
shared="${ADUGS_SHARED_DATA:-$root/../shared/data}"
compare="$(dirname "$shared")/tools/openvins/compare.sh"
euroc="$shared/euroc_v101_micro"
[ -x "$adugs" ] || { echo "bench_realism: $adugs missing: run scripts/setup.sh" >&2; exit 2; }
[ -f "$compare" ] || { echo "bench_realism: $compare missing (../shared/tools/openvins)" >&2; exit 2; }
[ -f "$euroc/groundtruth/V1_01_easy_vicon2gt.csv" ] || { echo "bench_realism: $euroc missing (../shared/data)" >&2; exit 2; }
mkdir -p "$out/input"

# The lens without distortion, for the effects that are not about it.
undistorted="$out/input/cam0_undistorted/sensor.yaml"
mkdir -p "$(dirname "$undistorted")"
sed 's/^distortion_coefficients:.*/distortion_coefficients: [0.0, 0.0, 0.0, 0.0]/' "$euroc/mav0/cam0/sensor.yaml" > "$undistorted"
cp "$euroc/mav0/imu0/sensor.yaml" "$out/input/imu_sensor.yaml"

# A window of the flight: the ground truth and IMU rows from `start` seconds on.
cut_flight() {  # start_s -> prints the folder with trajectory.csv and imu.csv
  local start="$1" dir="$out/input/from_$1"
  if [ ! -f "$dir/imu.csv" ]; then
    mkdir -p "$dir"
    local t0
    t0=$(awk -F, 'NR == 2 {print $1}' "$euroc/groundtruth/V1_01_easy_vicon2gt.csv")
    local from=$((t0 + start * 1000000000))
    awk -F, -v from="$from" 'NR == 1 || $1 + 0 >= from' "$euroc/groundtruth/V1_01_easy_vicon2gt.csv" > "$dir/trajectory.csv"
    awk -F, -v from="$from" 'NR == 1 || $1 + 0 >= from' "$euroc/mav0/imu0/data.csv" > "$dir/imu.csv"
  fi
  echo "$dir"
}

effect_options() {
  case "$1" in
    clean|distortion) echo "" ;;
    blur) echo "--blur-samples 5 --exposure-ms 10" ;;
    noise) echo "--pixel-noise 3" ;;
    exposure) echo "--exposure-variation 0.2" ;;
    vignetting) echo "--vignetting 0.3" ;;
    all) echo "--blur-samples 5 --exposure-ms 10 --pixel-noise 3 --exposure-variation 0.2 --vignetting 0.3" ;;
    *) echo "bench_realism: unknown effect $1" >&2; exit 2 ;;
  esac
}

for flight in $flights; do
  IFS=: read -r start length seed <<< "$flight"
  seed="${seed:-1}" name="${start}_${length}_s${seed}"
  input="$(cut_flight "$start")"
  for effect in $effects; do
    seq="$out/seq/${name}_$effect" result="$out/compare${label:+_$label}/${name}_$effect"
    [ -f "$result/compare.json" ] && continue
    calib="$undistorted" undistorted_flag="--undistorted"
    case "$effect" in distortion|all) calib="$euroc/mav0/cam0/sensor.yaml" undistorted_flag="" ;; esac
    echo "bench_realism: flight ${start}+${length} s seed $seed, $effect" >&2
    if [ ! -f "$seq/rendered" ]; then
      rm -rf "$seq"
      # shellcheck disable=SC2046
      "$adugs" sim --trajectory "$input/trajectory.csv" --imu "$input/imu.csv" --calib "$calib" \
        --imu-calib "$out/input/imu_sensor.yaml" --duration "$length" --seed "$seed" --level none \
        $(effect_options "$effect") --out "$seq" > "$out/sim_${name}_$effect.log" 2>&1
      touch "$seq/rendered"
    fi
    mkdir -p "$(dirname "$result")"
    # shellcheck disable=SC2086
    OUT="$result" bash "$compare" "$seq" "$adugs" $undistorted_flag -- $adugs_options > "$result.log" 2>&1 ||
      { echo "bench_realism: compare failed, see $result.log" >&2; continue; }
  done
done

/usr/bin/python3 - "$out" "$flights" "$effects" "$label" <<'EOF'
import json, math, os, sys
out, flights, effects, run_label = sys.argv[1], sys.argv[2].split(), sys.argv[3].split(), sys.argv[4]
print("| flight | effect | OpenVINS ATE | adugs ATE | adugs / OpenVINS | CPU adugs / OpenVINS |")
print("|---|---|---|---|---|---|")
ratios = {e: [] for e in effects}
for f in flights:
    start, length, seed = (f.split(":") + ["1"])[:3]
    label = f"{start}+{length} s, seed {seed}"
    for e in effects:
        p = os.path.join(out, "compare_" + run_label if run_label else "compare", f"{start}_{length}_s{seed}_{e}", "compare.json")
        if not os.path.exists(p):
            print(f"| {label} | {e} | - | - | (no result) | |")
            continue
        c = json.load(open(p))
        r = c["ratio_adugs_over_openvins"]
        ratios[e].append(r["ate_m"])
        print(f"| {label} | {e} | {c['openvins']['ate_m']:.4f} m | {c['adugs']['ate_m']:.4f} m | "
              f"{r['ate_m']:.2f}x | {r['cpu_s']:.2f}x |")
print()
print("| effect | flights | geometric mean of adugs / OpenVINS ATE |")
print("|---|---|---|")
for e in effects:
    v = ratios[e]
    gm = math.exp(sum(math.log(x) for x in v) / len(v)) if v else float("nan")
    print(f"| {e} | {len(v)} | {gm:.2f}x |")
EOF
