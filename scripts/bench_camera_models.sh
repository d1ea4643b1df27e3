#!/usr/bin/env bash
# One lens, five camera models: does the odometry do as well through each model as through
# radtan? (issue 28: ATE within 1.2x of the radtan run on the same trajectory.)
#
# The lens is EuRoC's cam0 (Kalibr's pinhole-radtan fit, ../shared/data). `adugs calib convert
# --model` refits it as double sphere (the closest DS, about 1 px RMS off, mostly in the corners,
# where radtan's polynomial and the sphere models part), and the DS lens as EUCM, MEI (omni) and
# Kannala-Brandt (equidistant), each within 0.01 px of it. So the five lenses see (nearly) the same
# image and any ATE difference is the model's code path, not a wider or narrower field of view.
# Per seed the same trajectory is rendered through each lens (`adugs sim --camera`), the
# sequence's calibration converted to the file a user of that model has (radtan: Kalibr, omni:
# VINS-Fusion MEI, equidistant: OpenVINS, ds and eucm: Basalt JSON) and run with
# `adugs run --calibration` on it. Finished runs are kept and skipped on a rerun.
#
# Usage: scripts/bench_camera_models.sh [--seeds "1 2 3 4 5 6 7 8"] [--duration 30] [--scene room]
#          [--out DIR] [--jobs N] [--adugs BIN]
# Prints per-seed ATE (SE3 RMSE, m) per model, the ratio to radtan per seed, their geometric mean
# and median, and each lens' refit error.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="$root/build/app/adugs"
out=/tmp/adugs_bench_camera_models
seeds="1 2 3 4 5 6 7 8"
duration=30 scene=room jobs=$(nproc)
while [ $# -gt 0 ]; do
  case "$1" in
    --seeds) seeds="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --scene) scene="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --adugs) adugs="$2"; shift 2 ;;
    *) echo "bench_camera_models: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
command -v parallel > /dev/null || { echo "bench_camera_models: GNU parallel missing (apt install parallel)" >&2; exit 2; }
[ -x "$adugs" ] || { echo "bench_camera_models: $adugs missing: run scripts/setup.sh" >&2; exit 2; }
euroc="${ADUGS_SHARED_DATA:-$root/../shared/data}/euroc_v101_micro/mav0"
[ -f "$euroc/cam0/sensor.yaml" ] || { echo "bench_camera_models: $euroc/cam0/sensor.yaml missing (../shared/data)" >&2; exit 2; }
models="radtan ds eucm omni equidistant"
mkdir -p "$out/lens"

# The lenses, with their refit errors.
lens_file() { echo "$out/lens/$1/camchain-imucam.yaml"; }
refit() {  # model, source files...
  local model="$1"; shift
  [ -f "$(lens_file "$model")" ] && return
  "$adugs" calib convert "$@" --to kalibr --model "$model" --max-refit-rms 5 --out "$out/lens/$model" \
    | grep -- '->' > "$out/lens/$model.refit"
}
mkdir -p "$out/lens/radtan"
[ -f "$(lens_file radtan)" ] || "$adugs" calib convert "$euroc/cam0/sensor.yaml" "$euroc/imu0/sensor.yaml" \
  --to kalibr --out "$out/lens/radtan" > /dev/null
echo "cam0: EuRoC's Kalibr radtan fit (the source)" > "$out/lens/radtan.refit"
refit ds "$euroc/cam0/sensor.yaml" "$euroc/imu0/sensor.yaml"
for m in eucm omni equidistant; do refit "$m" "$(lens_file ds)" "$out/lens/ds/imu.yaml"; done

tool_of() {
  case "$1" in
    radtan) echo kalibr ;; omni) echo vins ;; equidistant) echo openvins ;; *) echo basalt ;;
  esac
}
calibration_files() {  # folder written by calib convert --to tool
  case "$2" in
    kalibr) echo "$1/camchain-imucam.yaml $1/imu.yaml" ;;
    openvins) echo "$1/kalibr_imucam_chain.yaml $1/kalibr_imu_chain.yaml" ;;
    vins) echo "$1/config.yaml" ;;
    basalt) echo "$1/calib.json" ;;
  esac
}
one_run() {  # model seed
  local model="$1" seed="$2" dir="$out/runs/$1_s$2"
  [ -f "$dir/run/summary.yaml" ] && return 0
  rm -rf "$dir"; mkdir -p "$dir"
  "$adugs" sim --scene "$scene" --level none --seed "$seed" --duration "$duration" \
    --camera "$(lens_file "$model")" --out "$dir/seq" > "$dir/sim.log" 2>&1
  local tool; tool=$(tool_of "$model")
  "$adugs" calib convert "$dir/seq/mav0/cam0/sensor.yaml" "$dir/seq/mav0/imu0/sensor.yaml" --to "$tool" \
    --out "$dir/calib" > "$dir/convert.log" 2>&1
  # shellcheck disable=SC2046
  "$adugs" run "$dir/seq" --calibration $(calibration_files "$dir/calib" "$tool") --out "$dir/run.tmp" \
    > "$dir/run.log" 2>&1
  mv "$dir/run.tmp" "$dir/run"
  rm -rf "$dir/seq/mav0/cam0/data"  # the images: 0.3 GB per run
}
export -f one_run lens_file tool_of calibration_files
export adugs out scene duration
parallel --jobs "$jobs" --halt soon,fail=1 one_run {1} {2} ::: $models ::: $seeds

/usr/bin/python3 - "$out" "$models" "$seeds" <<'EOF'
import math, os, re, statistics, sys
out, models, seeds = sys.argv[1], sys.argv[2].split(), sys.argv[3].split()
def ate(model, seed):
    text = open(os.path.join(out, "runs", f"{model}_s{seed}", "run", "summary.yaml")).read()
    return float(re.search(r"^ate_se3_rmse_m: (\S+)", text, re.M).group(1))
table = {m: [ate(m, s) for s in seeds] for m in models}
print("| seed | " + " | ".join(models) + " |")
print("|---" * (len(models) + 1) + "|")
for i, s in enumerate(seeds):
    print(f"| {s} | " + " | ".join(f"{table[m][i]:.4f}" for m in models) + " |")
print("| median | " + " | ".join(f"{statistics.median(table[m]):.4f}" for m in models) + " |")
print()
print("| model | refit of | geometric mean of per-seed ratio to radtan | median ratio | worst seed ratio |")
print("|---|---|---|---|---|")
for m in models:
    ratios = [a / r for a, r in zip(table[m], table["radtan"])]
    gm = math.exp(sum(math.log(x) for x in ratios) / len(ratios))
    refit = open(os.path.join(out, "lens", m + ".refit")).read().splitlines()[0]
    print(f"| {m} | {refit} | {gm:.3f} | {statistics.median(ratios):.3f} | {max(ratios):.2f} |")
EOF
