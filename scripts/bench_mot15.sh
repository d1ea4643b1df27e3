#!/usr/bin/env bash
# The tracker alone on MOTChallenge public detections, scored against the ground truth:
#   scripts/bench_mot15.sh MOT_DIR [--seqs "TUD-Campus TUD-Stadtmitte"] [--out DIR] [--ignore-rule zero-confidence|mot15]
#                          [-- adugs track options]
# MOT_DIR holds one folder per sequence with det/det.txt and gt/gt.txt (MOTChallenge layout; the
# MOT15 train split is what doc/results.md reports). Runs `adugs track --detections` per sequence,
# then one `adugs eval-mot` over all of them (per-sequence rows and OVERALL, CLEAR-MOT, identity
# and HOTA metrics), and keeps DIR/<seq>/tracks.txt, DIR/metrics.json and DIR/switches.csv.
# --ignore-rule mot15 scores as TrackEval's MOT15 setting (eval-mot's --ignore-rule).
# Measurement only: the data are not part of the repository and no test reads them.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
adugs="${ADUGS:-$root/build/app/adugs}"
[ $# -ge 1 ] || { echo "usage: $0 MOT_DIR [--seqs \"A B\"] [--out DIR] [--ignore-rule zero-confidence|mot15] [-- track options]" >&2; exit 2; }
mot="$1"; shift
seqs=""; out="out/bench_mot15"; ignore_rule="zero-confidence"
while [ $# -gt 0 ]; do
  case "$1" in
    --seqs) seqs="$2"; shift 2 ;;
    --out) out="$2"; shift 2 ;;
    --ignore-rule) ignore_rule="$2"; shift 2 ;;
    --) shift; break ;;
    *) echo "$0: unknown option $1 (track options go after --)" >&2; exit 2 ;;
  esac
done
[ -d "$mot" ] || { echo "$0: $mot: no such folder" >&2; exit 2; }
if [ -z "$seqs" ]; then
  for d in "$mot"/*/; do [ -f "$d/det/det.txt" ] && [ -f "$d/gt/gt.txt" ] && seqs="$seqs $(basename "$d")"; done
fi
[ -n "$seqs" ] || { echo "$0: no sequence with det/det.txt and gt/gt.txt under $mot" >&2; exit 2; }
mkdir -p "$out"
eval_args=()
for s in $seqs; do
  for f in det/det.txt gt/gt.txt; do
    [ -f "$mot/$s/$f" ] || { echo "$0: $mot/$s/$f: missing" >&2; exit 2; }
  done
  "$adugs" track --detections "$mot/$s/det/det.txt" --out "$out/$s" "$@" > /dev/null
  eval_args+=(--gt "$mot/$s/gt/gt.txt" --est "$out/$s/tracks.txt")
done
echo "adugs track options: ${*:-(defaults)}"
"$adugs" eval-mot "${eval_args[@]}" --ignore-rule "$ignore_rule" --json "$out/metrics.json" --switches "$out/switches.csv"
