#!/usr/bin/env bash
# Accuracy and speed of `adugs run` over the simulator's sequence sets, one labelled configuration
# at a time, so that variations (options, builds) are compared on the same files:
#   static    16 x 60 s, no moving objects: street/room x glide/handheld x seeds 1 2 3 5
#             (the sequences the defaults were tuned on)
#   hybrid    the real EuRoC V1_01 flight (145 s, real IMU) with the room rendered along it
#   dynamic   room/high and street/high, seeds 3-11, 30 s, each with --mask none and --mask gt
#   untuned   sequences no option was tuned on: the courtyard scene (far walls, low texture) glide
#             and handheld seeds 1 2 3 5, room/street handheld with seeds 21 22, 60 s; the hybrid
#             V1_01 flight through the courtyard
# Every run is an independent `adugs` process under GNU parallel; finished runs are kept and
# skipped on a rerun (a killed benchmark resumes). Sequences are generated once into OUT/seq.
#
# Usage: scripts/bench_vio.sh --label NAME [--config YAML] [--sets "static hybrid dynamic untuned"]
#          [--adugs BIN] [--sim-adugs BIN] [--out DIR] [--jobs N] [--repeat K]
#        scripts/bench_vio.sh --report "LABEL1 LABEL2 ..." [--sets ...] [--out DIR]
# --repeat K runs each sequence K times (timing spread; the output is deterministic).
# The report (scripts/bench_vio_report.py) prints per-sequence ATE, % of distance travelled,
# real-time factor and back-end median for each label side by side, with means, medians, spread.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="$root/build/app/adugs"
sim_adugs=""
out=/tmp/adugs_bench_vio
sets="static hybrid dynamic untuned"
label="" config="" report="" jobs=$(nproc) repeat=1
while [ $# -gt 0 ]; do
  case "$1" in
    --label) label="$2"; shift 2 ;;
    --config) config="$2"; shift 2 ;;
    --sets) sets="$2"; shift 2 ;;
    --adugs) adugs="$2"; shift 2 ;;
    --sim-adugs) sim_adugs="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --jobs) jobs="$2"; shift 2 ;;
    --repeat) repeat="$2"; shift 2 ;;
    --report) report="$2"; shift 2 ;;
    *) echo "bench_vio: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
[ -n "$report" ] || [ -n "$label" ] || { echo "bench_vio: --label NAME is required" >&2; exit 2; }
[ -z "$config" ] || [ -f "$config" ] || { echo "bench_vio: config $config missing" >&2; exit 2; }
command -v parallel > /dev/null || { echo "bench_vio: GNU parallel missing (apt install parallel)" >&2; exit 2; }
[ -x "$adugs" ] || { echo "bench_vio: $adugs missing: run scripts/setup.sh" >&2; exit 2; }
sim_adugs="${sim_adugs:-$adugs}"
euroc="${ADUGS_SHARED_DATA:-$root/../shared/data}/euroc_v101_micro"

# name: adugs sim options; mask modes per sequence
sequences() {
  local hybrid="--trajectory $euroc/groundtruth/V1_01_easy_vicon2gt.csv --imu $euroc/mav0/imu0/data.csv --calib $euroc/mav0/cam0/sensor.yaml --duration 0 --level none"
  for set in $sets; do
    case $set in
      static)
        for sc in street room; do for mo in glide handheld; do for s in 1 2 3 5; do
          echo "static ${sc}_${mo}_s$s none|--scene $sc --motion $mo --level none --seed $s --duration 60"
        done; done; done ;;
      hybrid) echo "hybrid hybrid_room_v101 none|--scene room $hybrid" ;;
      dynamic)
        for sc in room street; do for s in 3 4 5 6 7 8 9 10 11; do
          echo "dynamic ${sc}_high_s$s none,gt|--scene $sc --level high --seed $s --duration 30"
        done; done ;;
      untuned)
        for mo in glide handheld; do for s in 1 2 3 5; do
          echo "untuned courtyard_${mo}_s$s none|--scene courtyard --motion $mo --level none --seed $s --duration 60"
        done; done
        for sc in room street; do for s in 21 22; do
          echo "untuned ${sc}_handheld_s$s none|--scene $sc --motion handheld --level none --seed $s --duration 60"
        done; done
        echo "untuned hybrid_courtyard_v101 none|--scene courtyard $hybrid" ;;
      *) echo "bench_vio: unknown set $set" >&2; exit 2 ;;
    esac
  done
}

mkdir -p "$out"
manifest="$(mktemp)"  # "set name masks|sim options" per line; the report reads it too
trap 'rm -f "$manifest"' EXIT
sequences > "$manifest"
if [ -n "$report" ]; then
  /usr/bin/python3 "$root/scripts/bench_vio_report.py" "$out" --manifest "$manifest" --labels "$report"
  exit 0
fi
mkdir -p "$out/seq" "$out/runs/$label"
[ -n "$config" ] && cp "$config" "$out/runs/$label/config.yaml"

sim_one() {  # name options...
  local name="$1"; shift
  local dir="$out/seq/$name"
  [ -f "$dir/.done" ] && return 0
  "$sim_adugs" sim "$@" --out "$dir" > "$dir.log" 2>&1 && touch "$dir/.done"
}
run_one() {  # run-name sequence-name options...
  local name="$1" seq="$2"; shift 2
  local dir="$out/runs/$label/$name"
  [ -f "$dir/summary.yaml" ] && return 0
  rm -rf "$dir"; mkdir -p "$dir"
  # A failed run (divergence, bad input) is recorded and does not stop the others.
  "$adugs" run -q "$out/seq/$seq" "$@" --out "$dir" > "$dir/log.txt" 2>&1 || echo "exit $?" > "$dir/failed"
}
export -f sim_one run_one
export out adugs sim_adugs label

: > "$out/sim_$label.txt"; : > "$out/runs_$label.txt"
while IFS='|' read -r head sim_opts; do
  read -r set name masks <<< "$head"
  echo "sim_one $name $sim_opts" >> "$out/sim_$label.txt"
  for mask in ${masks//,/ }; do
    for k in $(seq 1 "$repeat"); do
      run_name="$name"; [ "$mask" != none ] && run_name="${name}_mask_$mask"
      [ "$repeat" -gt 1 ] && run_name="${run_name}_r$k"
      echo "run_one $run_name $name --mask $mask ${config:+--config $out/runs/$label/config.yaml}" >> "$out/runs_$label.txt"
    done
  done
done < "$manifest"
echo "bench_vio: $(wc -l < "$out/sim_$label.txt") sequences (generated once), $(wc -l < "$out/runs_$label.txt") runs of '$label' on $jobs jobs" >&2
SHELL=/bin/bash parallel --will-cite -j "$jobs" --halt soon,fail=1 < "$out/sim_$label.txt"
SHELL=/bin/bash parallel --will-cite -j "$jobs" --joblog "$out/joblog_$label" < "$out/runs_$label.txt"
/usr/bin/python3 "$root/scripts/bench_vio_report.py" "$out" --manifest "$manifest" --labels "$label"
