#!/usr/bin/env python3
"""Re-derives the HOTA figures that tests/app/test_cmd_eval_mot.cpp (HotaReproducesTrackEvalOnTud)
checks, from py-motmetrics' TUD-Campus and TUD-Stadtmitte files in ../shared/data/mot_reference,
with numpy and scipy alone, as TrackEval's metrics/hota.py computes them (IoU of xywh boxes,
alphas 0.05..0.95, the global alignment score, Hungarian matching per frame, the sequence
combination weighted by HOTA_TP; MOT15 preprocessing: confidence-0 ground truth dropped, which
these files do not have).

  /usr/bin/python3 tests/data/reference/derive_hota_reference.py ../shared/data/mot_reference \
      > tests/data/reference/hota_tud_reference.txt

The test reads hota_tud_reference.txt: re-running this script must reproduce it (run outside CI).
One line per sequence and one `overall`: HOTA DetA AssA LocA DetRe DetPr AssRe AssPr.
"""
import os
import sys

import numpy as np
from scipy.optimize import linear_sum_assignment

ALPHAS = np.arange(0.05, 0.99, 0.05)
EPS = np.finfo("float").eps


def read_mot(path, is_gt):
    rows = np.loadtxt(path, delimiter=",", ndmin=2)
    if is_gt:
        rows = rows[rows[:, 6] != 0]
    frames = {}
    for r in rows:
        frames.setdefault(int(r[0]), []).append((int(r[1]), r[2:6]))
    return frames


def ious(a, b):  # xywh boxes, rows of a against rows of b
    if len(a) == 0 or len(b) == 0:
        return np.zeros((len(a), len(b)))
    a = np.array(a, dtype=float)
    b = np.array(b, dtype=float)
    a2, b2 = a[:, :2] + a[:, 2:], b[:, :2] + b[:, 2:]
    lo = np.maximum(a[:, None, :2], b[None, :, :2])
    hi = np.minimum(a2[:, None], b2[None])
    inter = np.prod(np.clip(hi - lo, 0, None), axis=2)
    union = (a[:, 2] * a[:, 3])[:, None] + (b[:, 2] * b[:, 3])[None] - inter
    return inter / np.maximum(union, EPS)


def sequence(gt_path, est_path):
    gt, est = read_mot(gt_path, True), read_mot(est_path, False)
    gt_ids = sorted({i for f in gt.values() for i, _ in f})
    est_ids = sorted({i for f in est.values() for i, _ in f})
    gmap = {v: k for k, v in enumerate(gt_ids)}
    emap = {v: k for k, v in enumerate(est_ids)}
    steps = []
    for t in sorted(set(gt) | set(est)):
        g = gt.get(t, [])
        e = est.get(t, [])
        steps.append((np.array([gmap[i] for i, _ in g], dtype=int), np.array([emap[i] for i, _ in e], dtype=int),
                      ious([b for _, b in g], [b for _, b in e])))
    potential = np.zeros((len(gt_ids), len(est_ids)))
    gt_count = np.zeros((len(gt_ids), 1))
    est_count = np.zeros((1, len(est_ids)))
    for g, e, sim in steps:
        denom = sim.sum(0)[None, :] + sim.sum(1)[:, None] - sim
        sim_iou = np.zeros_like(sim)
        mask = denom > 0 + EPS
        sim_iou[mask] = sim[mask] / denom[mask]
        potential[g[:, None], e[None, :]] += sim_iou
        gt_count[g] += 1
        est_count[0, e] += 1
    alignment = potential / (gt_count + est_count - potential)
    n = len(ALPHAS)
    tp, fn, fp, loca = np.zeros(n), np.zeros(n), np.zeros(n), np.zeros(n)
    matches = [np.zeros_like(potential) for _ in ALPHAS]
    for g, e, sim in steps:
        if len(g) == 0:
            fp += len(e)
            continue
        if len(e) == 0:
            fn += len(g)
            continue
        rows, cols = linear_sum_assignment(-(alignment[g[:, None], e[None, :]] * sim))
        for a, alpha in enumerate(ALPHAS):
            ok = sim[rows, cols] >= alpha - EPS
            r, c = rows[ok], cols[ok]
            tp[a] += len(r)
            fn[a] += len(g) - len(r)
            fp[a] += len(e) - len(r)
            if len(r):
                loca[a] += sim[r, c].sum()
                matches[a][g[r], e[c]] += 1
    assa, assre, asspr = np.zeros(n), np.zeros(n), np.zeros(n)
    for a in range(n):
        m = matches[a]
        assa[a] = (m * (m / np.maximum(1, gt_count + est_count - m))).sum() / max(1, tp[a])
        assre[a] = (m * (m / np.maximum(1, gt_count))).sum() / max(1, tp[a])
        asspr[a] = (m * (m / np.maximum(1, est_count))).sum() / max(1, tp[a])
    loca = np.maximum(1e-10, loca) / np.maximum(1e-10, tp)
    return dict(tp=tp, fn=fn, fp=fp, assa=assa, assre=assre, asspr=asspr, loca=loca)


def final(r):
    deta = r["tp"] / np.maximum(1, r["tp"] + r["fn"] + r["fp"])
    detre = r["tp"] / np.maximum(1, r["tp"] + r["fn"])
    detpr = r["tp"] / np.maximum(1, r["tp"] + r["fp"])
    hota = np.sqrt(deta * r["assa"])
    return [x.mean() for x in (hota, deta, r["assa"], r["loca"], detre, detpr, r["assre"], r["asspr"])]


def combine(results):
    tp = sum(r["tp"] for r in results)
    out = dict(tp=tp, fn=sum(r["fn"] for r in results), fp=sum(r["fp"] for r in results))
    for k in ("assa", "assre", "asspr"):
        out[k] = sum(r[k] * r["tp"] for r in results) / np.maximum(1, tp)
    out["loca"] = np.maximum(1e-10, sum(r["loca"] * r["tp"] for r in results)) / np.maximum(1e-10, tp)
    return out


def main():
    ref = sys.argv[1] if len(sys.argv) > 1 else "../shared/data/mot_reference"
    print("# sequence HOTA DetA AssA LocA DetRe DetPr AssRe AssPr (TrackEval's hota.py, re-derived)")
    results = []
    for seq in ("TUD-Campus", "TUD-Stadtmitte"):
        r = sequence(os.path.join(ref, seq, "gt.txt"), os.path.join(ref, seq, "test.txt"))
        results.append(r)
        print(seq + "/test.txt", " ".join(f"{v:.9f}" for v in final(r)))
    print("overall", " ".join(f"{v:.9f}" for v in final(combine(results))))


if __name__ == "__main__":
    main()
