#!/usr/bin/env bash
# Checks data/config/d435i.yaml's tracker and estimator settings on D435i-like simulated data, as
# far as a simulator can stand in for the camera: handheld walks through the room scene (no moving
# objects), 30 Hz frames with auto-exposure gain changes, a 400 Hz IMU with the BMI055's datasheet
# noise densities, and a camera-IMU time offset of 5 ms that the config's online estimate must find.
# Compared with the same config without the online offset and with the simulator's and EuRoC's
# configs (tuned at 20 Hz). Every run is an independent `adugs` process under GNU parallel; finished
# runs are kept and skipped on a rerun. Prints a table (median and worst ATE over the seeds, the
# offset found, resets, speed) for doc/results.md.
#
# Usage: scripts/bench_d435i_config.sh [--out DIR] [--seeds "1 2 3 4"] [--duration 30]
#          [--time-offset 0.005] [--jobs N]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="$root/build/app/adugs"
out=/tmp/adugs_bench_d435i
seeds="1 2 3 4"
duration=30
offset=0.005
jobs=$(nproc)
while [ $# -gt 0 ]; do
  case "$1" in
    --out) out="$2"; shift 2 ;;
    --seeds) seeds="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --time-offset) offset="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    *) echo "bench_d435i_config: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
command -v parallel > /dev/null || { echo "bench_d435i_config: GNU parallel missing (apt install parallel)" >&2; exit 2; }
[ -x "$adugs" ] || { echo "bench_d435i_config: $adugs missing: run scripts/setup.sh" >&2; exit 2; }
mkdir -p "$out/seq" "$out/runs" "$out/configs"

# The simulated IMU: BMI055 datasheet densities (gyro 0.014 deg/s/sqrt(Hz), accel 150 ug/sqrt(Hz));
# random walks as EuRoC's ADIS16448 (the datasheet gives none).
cat > "$out/configs/bmi055_sensor.yaml" <<'EOF'
%YAML:1.0
sensor_type: imu
comment: BMI055-like (datasheet densities), for the D435i config check
T_BS:
  cols: 4
  rows: 4
  data: [1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 0.0, 1.0]
rate_hz: 400
gyroscope_noise_density: 2.4435e-04
gyroscope_random_walk: 1.9393e-05
accelerometer_noise_density: 1.4710e-03
accelerometer_random_walk: 3.0000e-3
EOF
cp "$root/data/config/d435i.yaml" "$out/configs/d435i.yaml"
sed 's/estimate_time_offset: true/estimate_time_offset: false/' "$root/data/config/d435i.yaml" > "$out/configs/d435i_no_td.yaml"
cp "$root/data/config/sim.yaml" "$out/configs/sim.yaml"
cp "$root/data/config/euroc.yaml" "$out/configs/euroc.yaml"
configs="d435i d435i_no_td sim euroc"

simulate() {  # seed
  local dir="$out/seq/s$1"
  [ -f "$dir/done" ] && return 0
  "$adugs" sim --scene room --motion handheld --level none --seed "$1" --duration "$duration" --rate 30 \
    --imu-rate 400 --imu-calib "$out/configs/bmi055_sensor.yaml" --time-offset "$offset" \
    --exposure-variation 0.2 --out "$dir" > "$dir.log" 2>&1 && touch "$dir/done"
}
run() {  # seed config
  local dir="$out/runs/s$1_$2"
  [ -f "$dir/summary.yaml" ] && return 0
  "$adugs" run -q "$out/seq/s$1" --config "$out/configs/$2.yaml" --out "$dir" > "$dir.log" 2>&1 || true
}
export -f simulate run
export adugs out duration offset
parallel -j "$jobs" simulate ::: $seeds
parallel -j "$jobs" run ::: $seeds ::: $configs

value() { grep -m1 "^$2:" "$1" 2>/dev/null | awk '{print $2}'; }
echo "| config | ATE median [m] | ATE worst [m] | td found [ms] (true $(awk "BEGIN{print $offset*1000}")) | resets | real-time factor median |"
echo "|---|---|---|---|---|---|"
for c in $configs; do
  ates="" tds="" resets=0 rts=""
  for s in $seeds; do
    f="$out/runs/s${s}_$c/summary.yaml"
    a=$(value "$f" ate_se3_rmse_m); ates="$ates ${a:-nan}"
    t=$(value "$f" time_offset_s); tds="$tds $(awk "BEGIN{printf \"%.2f\", ${t:-0}*1000}")"
    r=$(value "$f" resets); resets=$((resets + ${r:-0}))
    rt=$(value "$f" realtime_factor); rts="$rts ${rt:-nan}"
  done
  med() { tr ' ' '\n' | grep -v '^$' | sort -g | awk '{a[NR]=$1} END {print (NR%2 ? a[(NR+1)/2] : (a[NR/2]+a[NR/2+1])/2)}'; }
  worst=$(echo $ates | tr ' ' '\n' | sort -g | tail -1)
  echo "| $c | $(echo $ates | med) | $worst | $tds | $resets | $(echo $rts | med) |"
done
