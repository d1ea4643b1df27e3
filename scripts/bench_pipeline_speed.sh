#!/usr/bin/env bash
# Speed of `adugs run --mask detector` (the detector -> SORT -> GrabCut chain) with one adugs
# binary, or two (e.g. before and after a pipeline change), on the simulated room with walkers (the
# sequence of doc/results.md "Speed of the whole adugs run --mask detector"). The two binaries run
# alternately, --repeats times per chain, so a machine whose load changes hurts both alike; the
# table gives medians [min-max] of the wall time, of the CPU time (user + system) per second of
# sequence (load-independent: below 2 a 2-core machine could keep up if the stages overlapped
# perfectly) and the per-stage medians from summary.yaml. With
# --live, the AFTER binary also runs `adugs live --replay` on the same sequence: the fraction of
# frames the live pipeline keeps at sensor pace and the latency.
#
# Usage: scripts/bench_pipeline_speed.sh [--before OLD/adugs] --after NEW/adugs [--repeats 3]
#        [--duration 20] [--work DIR] [--models DIR] [--live]
# Needs the shared models (yolo-fastest-1.1_coco, yolox_nano) at ../shared/models or --models.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
before="" after="" repeats=3 duration=20 work="" live=0
models="${ADUGS_SHARED_MODELS:-$root/../shared/models}"
while [ $# -gt 0 ]; do
  case "$1" in
    --before) before="$2"; shift 2 ;;
    --after) after="$2"; shift 2 ;;
    --repeats) repeats="$2"; shift 2 ;;
    --duration) duration="$2"; shift 2 ;;
    --work) work="$2"; shift 2 ;;
    --models) models="$2"; shift 2 ;;
    --live) live=1; shift ;;
    *) echo "bench_pipeline_speed: unknown option $1" >&2; exit 2 ;;
  esac
done
[ -x "$after" ] || { echo "bench_pipeline_speed: give the adugs binary to measure with --after" >&2; exit 2; }
[ -z "$before" ] || [ -x "$before" ] || { echo "bench_pipeline_speed: --before $before is not an executable" >&2; exit 2; }
yf="$models/yolo-fastest-1.1_coco/yolo-fastest-1.1-xl.weights"
yx="$models/yolox_nano/yolox_nano.onnx"
for m in "$yf" "$yx"; do [ -f "$m" ] || { echo "bench_pipeline_speed: missing model $m" >&2; exit 2; }; done
work="${work:-$(mktemp -d)}"
mkdir -p "$work"
seq="$work/room_high_walkers_s3"
if [ ! -f "$seq/mav0/sim.yaml" ]; then
  "$after" sim --scene room --level high --seed 3 --duration "$duration" --people walkers --out "$seq" >/dev/null
fi
printf 'dynamic:\n  segment_every: 3\n' >"$work/seg3.yaml"

# name | options
chains=(
  "yolo-fastest-xl every frame, GrabCut every frame|--mask detector --detector-model $yf"
  "yolo-fastest-xl every frame, GrabCut every 3rd|--mask detector --detector-model $yf --config $work/seg3.yaml"
  "yolox-nano every 3rd frame, GrabCut every frame|--mask detector --detector-model $yx --detect-every 3"
)

summary_value() {  # FILE KEY
  sed -n "s/^ *$2: \([^ #]*\).*/\1/p" "$1" | head -1
}

results="$work/results.tsv"
: >"$results"
for c in "${!chains[@]}"; do
  opts="${chains[$c]#*|}"
  for r in $(seq 1 "$repeats"); do
    for which in before after; do
      bin="$before"; [ "$which" = after ] && bin="$after"
      [ -n "$bin" ] || continue
      out="$work/run_${c}_${which}_$r"
      rm -rf "$out"
      mkdir -p "$out"
      # shellcheck disable=SC2086
      /usr/bin/time -f "%U %S" -o "$out.cpu" "$bin" run -q "$seq" $opts --out "$out" >/dev/null
      s="$out/summary.yaml"
      recall=$(sed -n 's/.*recall: \([0-9.]*\).*/\1/p' "$s")
      cpu=$(awk '{print $1 + $2}' "$out.cpu")
      printf '%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\t%s\n' "$c" "$which" "$(summary_value "$s" wall_s)" \
        "$(summary_value "$s" realtime_factor)" "$(summary_value "$s" dynamic_mask_median)" \
        "$(summary_value "$s" frontend_median)" "$(summary_value "$s" backend_median)" \
        "$(summary_value "$s" ate_se3_rmse_m)" "${recall:-}" "$cpu" "$(summary_value "$s" sequence_s)" >>"$results"
      echo "bench_pipeline_speed: chain $c, $which, repeat $r: $(summary_value "$s" wall_s) s" >&2
    done
  done
done
if [ "$live" = 1 ]; then
  for c in "${!chains[@]}"; do
    opts="${chains[$c]#*|}"
    for r in $(seq 1 "$repeats"); do
      out="$work/live_${c}_$r"
      rm -rf "$out"
      # shellcheck disable=SC2086
      "$after" live -q --no-window --replay "$seq" --replay-frame-loss 0 $opts --out "$out" >/dev/null
      s="$out/summary.yaml"
      printf 'live\t%s\t%s\t%s\t%s\t%s\n' "$c" "$(summary_value "$s" frames)" "$(summary_value "$s" frames_acquired)" \
        "$(summary_value "$s" latency_median)" "$(summary_value "$s" ate_se3_rmse_m)" >>"$results"
      echo "bench_pipeline_speed: live chain $c, repeat $r done" >&2
    done
  done
fi

/usr/bin/python3 - "$results" "$duration" "$repeats" "${chains[@]%%|*}" <<'EOF'
import statistics, sys
path, duration, repeats, names = sys.argv[1], float(sys.argv[2]), sys.argv[3], sys.argv[4:]
rows = [line.rstrip("\n").split("\t") for line in open(path)]
def cell(values, fmt="%.1f"):
    v = sorted(float(x) for x in values if x not in ("", None))
    if not v:
        return "-"
    return (fmt % statistics.median(v)) + " [" + (fmt % v[0]) + "-" + (fmt % v[-1]) + "]"
print(f"Room, high level, walkers, seed 3, {duration:g} s; medians [min-max] over {repeats} runs each.\n")
print("| chain | binary | wall [s] | real-time factor | CPU s per sequence s | mask stage [ms] | KLT front-end [ms] | back-end [ms] | ATE [m] | mask recall |")
print("|---|---|---|---|---|---|---|---|---|---|")
for c, name in enumerate(names):
    for which in ("before", "after"):
        sel = [r for r in rows if r[0] == str(c) and r[1] == which]
        if not sel:
            continue
        col = lambda i: [r[i] for r in sel]
        cpu = [float(r[9]) / float(r[10]) for r in sel if len(r) > 10 and r[9] and r[10]]
        print(f"| {name} | {which} | {cell(col(2))} | {cell(col(3), '%.2f')}x | {cell(cpu, '%.2f')} | {cell(col(4))} | "
              f"{cell(col(5))} | {cell(col(6))} | {cell(col(7), '%.3f')} | {cell(col(8), '%.3f')} |")
live = [r for r in rows if r[0] == "live"]
if live:
    print("\n`adugs live --replay` (after), sensor pace:\n")
    print("| chain | frames kept of acquired | latency [ms] | ATE [m] |")
    print("|---|---|---|---|")
    for c, name in enumerate(names):
        sel = [r for r in live if r[1] == str(c)]
        if sel:
            kept = [float(r[2]) / float(r[3]) for r in sel if r[3] not in ("", "0")]
            print(f"| {name} | {cell([100 * k for k in kept], '%.0f')} % | {cell([r[4] for r in sel], '%.0f')} | "
                  f"{cell([r[5] for r in sel], '%.3f')} |")
EOF
