#!/usr/bin/python3
"""Score distribution of a detector's boxes against ground truth, to choose `adugs track --high-score`
for that detector (its confidence scale is its own; doc/tracking.md, "Choosing parameters").

Usage: detection_scores.py DET GT [DET GT ...] [--thresholds 0.5 0.6 0.7 0.8] [--gt-classes 0]
                          [--min-visibility 0.5]
  DET: MOTChallenge det.txt (frame, -1, left, top, w, h, score, ...), e.g. `adugs track --write-detections`
  GT:  MOTChallenge gt.txt of the same frames (rows with confidence 0 are left out; --gt-classes and
       --min-visibility keep the rows of those classes (column 8) and visibility (column 9), e.g. the
       simulator's people that are more than half visible: --gt-classes 0 --min-visibility 0.5)
Per pair: box count, score quantiles, and for the true detections (matched one-to-one to an object
with IoU >= 0.5 in their frame, greedily by IoU) and the false ones: count, median score and the
fraction of true detections below each threshold (those would start no track at that --high-score);
recall: objects found / objects kept in GT (detections on objects not kept count as neither).
Measurement help only (numpy); no test reads it.
"""
import argparse
import sys

import numpy as np


def read_mot(path, min_columns):
    try:
        rows = np.loadtxt(path, delimiter=",", ndmin=2)
    except (OSError, ValueError) as e:
        sys.exit(f"{path}: {e}")
    if rows.size == 0 or rows.shape[1] < min_columns:
        sys.exit(f"{path}: expected at least {min_columns} comma-separated columns per row")
    return rows


def iou_matrix(a, b):
    """IoU of boxes (left, top, w, h): a[i] against b[j]."""
    x0 = np.maximum(a[:, None, 0], b[None, :, 0])
    y0 = np.maximum(a[:, None, 1], b[None, :, 1])
    x1 = np.minimum(a[:, None, 0] + a[:, None, 2], b[None, :, 0] + b[None, :, 2])
    y1 = np.minimum(a[:, None, 1] + a[:, None, 3], b[None, :, 1] + b[None, :, 3])
    inter = np.clip(x1 - x0, 0, None) * np.clip(y1 - y0, 0, None)
    union = a[:, None, 2] * a[:, None, 3] + b[None, :, 2] * b[None, :, 3] - inter
    return np.where(union > 0, inter / np.where(union > 0, union, 1), 0)


def match_detections(det, gt):
    """Per detection: the index of the ground-truth row it matches (IoU >= 0.5, one-to-one, greedy by
    IoU, in its frame), or -1."""
    matched = np.full(len(det), -1)
    for frame in np.unique(det[:, 0]):
        di = np.flatnonzero(det[:, 0] == frame)
        gi = np.flatnonzero(gt[:, 0] == frame)
        if len(gi) == 0:
            continue
        iou = iou_matrix(det[di, 2:6], gt[gi, 2:6])
        while iou.size and iou.max() >= 0.5:
            d, g = np.unravel_index(np.argmax(iou), iou.shape)
            matched[di[d]] = gi[g]
            iou[d, :] = 0
            iou[:, g] = 0
    return matched


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("files", nargs="+", help="DET GT pairs")
    p.add_argument("--thresholds", nargs="+", type=float, default=[0.5, 0.6, 0.7, 0.8])
    p.add_argument("--gt-classes", nargs="+", type=float, help="keep ground truth of these classes (column 8)")
    p.add_argument("--min-visibility", type=float, help="keep ground truth at least this visible (column 9)")
    a = p.parse_args()
    if len(a.files) % 2:
        sys.exit("give DET GT pairs")
    print("det file: boxes, score min / p5 / p25 / p50 / p75 / p95 / max | true: count, median, fraction below "
          + " / ".join(f"{t:g}" for t in a.thresholds) + " | false: count, median | recall")
    for det_path, gt_path in zip(a.files[0::2], a.files[1::2]):
        det = read_mot(det_path, 7)
        gt = read_mot(gt_path, 7)
        gt = gt[gt[:, 6] != 0]
        skipped = np.zeros(len(gt), bool)
        if a.gt_classes is not None:
            skipped |= ~np.isin(gt[:, 7], a.gt_classes) if gt.shape[1] > 7 else True
        if a.min_visibility is not None:
            skipped |= gt[:, 8] < a.min_visibility if gt.shape[1] > 8 else True
        # Detections matched to objects left out count as neither true nor false.
        matched = match_detections(det, gt)
        det = det[(matched < 0) | ~skipped[matched]]
        matched = matched[(matched < 0) | ~skipped[matched]]
        is_true = matched >= 0
        kept = int(np.sum(~skipped))
        score = det[:, 6]
        q = np.percentile(score, [0, 5, 25, 50, 75, 95, 100])
        t, f = score[is_true], score[~is_true]
        below = " / ".join(f"{np.mean(t < th):.2f}" for th in a.thresholds) if len(t) else "-"
        print(f"{det_path}: {len(score)}, " + " / ".join(f"{x:.2f}" for x in q)
              + f" | {len(t)}, {np.median(t) if len(t) else float('nan'):.2f}, {below}"
              + f" | {len(f)}, {np.median(f) if len(f) else float('nan'):.2f}"
              + f" | {len(t) / kept if kept else float('nan'):.3f} of {kept}")


if __name__ == "__main__":
    main()
