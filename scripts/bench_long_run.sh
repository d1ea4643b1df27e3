#!/usr/bin/env bash
# A long run's memory and per-frame cost over time (issue 29: "a 30-minute simulated run: memory
# and per-frame time flat"). Generates a simulated sequence (room, level none, default 1800 s) once,
# runs `adugs run` on it and samples the process every few seconds: resident memory (VmRSS), CPU
# time (utime + stime of every thread) and the sequence time reached (from the run's progress
# line). Prints, per tenth of the sequence, peak memory and CPU per sequence second, and writes
# the samples to OUT/samples.csv. A 60 s run of the same sequence gives the reference peak.
#
# Usage: scripts/bench_long_run.sh [--duration S] [--seed N] [--out DIR] [--adugs BIN]
#          [--interval S] [-- adugs run options]
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="$root/build/app/adugs"
out=/tmp/adugs_bench_long_run
duration=1800 seed=7 interval=5
while [ $# -gt 0 ]; do
  case "$1" in
    --duration) duration="$2"; shift 2 ;;
    --seed) seed="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --adugs) adugs="$2"; shift 2 ;;
    --interval) interval="$2"; shift 2 ;;
    --) shift; break ;;
    *) echo "bench_long_run: unknown option $1 (see the header of $0)" >&2; exit 2 ;;
  esac
done
[ -x "$adugs" ] || { echo "bench_long_run: $adugs missing: run scripts/setup.sh" >&2; exit 2; }
seq="$out/seq_${duration}s_seed$seed"
mkdir -p "$out"
if [ ! -f "$seq/.complete" ]; then
  echo "bench_long_run: generating $seq (room, level none, $duration s)" >&2
  rm -rf "$seq"
  "$adugs" sim --scene room --level none --seed "$seed" --duration "$duration" --out "$seq" \
    > "$out/sim.log" 2>&1
  touch "$seq/.complete"
fi

# run LABEL DURATION: one adugs run, sampled; prints the samples file.
run() {
  local play="$2" dir="$out/run_$1"
  shift 2
  rm -rf "$dir"
  mkdir -p "$dir"
  "$adugs" run "$seq" --duration "$play" --out "$dir" "$@" 2> "$dir/progress.log" > /dev/null &
  local pid=$! tick
  tick=$(getconf CLK_TCK)
  echo "wall_s,sequence_s,rss_mb,cpu_s" > "$dir/samples.csv"
  local t0=$SECONDS
  while kill -0 "$pid" 2> /dev/null; do
    if [ -r "/proc/$pid/status" ]; then
      local rss cpu seq_s
      rss=$(awk '/^VmRSS/ {print $2 / 1024}' "/proc/$pid/status" 2> /dev/null || echo "")
      cpu=$(awk -v t="$tick" '{print ($14 + $15) / t}' "/proc/$pid/stat" 2> /dev/null || echo "")
      seq_s=$(tr '\r' '\n' < "$dir/progress.log" | awk '/^run: [0-9.]+ s \|/ {s = $2} END {print s + 0}')
      [ -n "$rss" ] && [ -n "$cpu" ] && echo "$((SECONDS - t0)),$seq_s,$rss,$cpu" >> "$dir/samples.csv"
    fi
    sleep "$interval"
  done
  wait "$pid" || { echo "bench_long_run: adugs run failed, see $dir/progress.log" >&2; exit 1; }
  echo "$dir/samples.csv"
}
short=$(run short 60 "$@")
long=$(run long 0 "$@")

/usr/bin/python3 - "$short" "$long" "$duration" <<'EOF'
import csv, sys
def load(p):
    return [{k: float(v) for k, v in r.items()} for r in csv.DictReader(open(p))]
short, long, duration = load(sys.argv[1]), load(sys.argv[2]), float(sys.argv[3])
peak_short = max(r["rss_mb"] for r in short)
peak_long = max(r["rss_mb"] for r in long)
print(f"peak memory: 60 s run {peak_short:.0f} MB, {duration:.0f} s run {peak_long:.0f} MB "
      f"({peak_long / peak_short:.2f}x)")
print("| part of the sequence | sequence s | peak RSS in it | CPU per sequence second |")
print("|---|---|---|---|")
for k in range(10):
    lo, hi = duration * k / 10, duration * (k + 1) / 10
    rows = [r for r in long if lo <= r["sequence_s"] <= hi and r["sequence_s"] > 0]
    if len(rows) < 2:
        print(f"| {k + 1}/10 | {lo:.0f}-{hi:.0f} | - | (too few samples) |")
        continue
    d_seq = rows[-1]["sequence_s"] - rows[0]["sequence_s"]
    d_cpu = rows[-1]["cpu_s"] - rows[0]["cpu_s"]
    rate = f"{d_cpu / d_seq:.3f} s" if d_seq > 0 else "-"
    print(f"| {k + 1}/10 | {lo:.0f}-{hi:.0f} | {max(r['rss_mb'] for r in rows):.0f} MB | {rate} |")
EOF
