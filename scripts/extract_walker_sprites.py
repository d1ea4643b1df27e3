#!/usr/bin/env python3
"""Cut sprites of real walking people (BGRA, exact binary alpha) from a static-camera video.

Usage: extract_walker_sprites.py VIDEO OUT_DIR

Made for OpenCV's vtest.avi (opencv-doc) and run at build time. Background subtraction against a
per-segment median background with shadow suppression, blob tracking, strict filters keeping only
sequences of one isolated person walking, then one sequence per person (the same people cross the
plaza many times). Writes OUT_DIR/walker_NN/frame_KK.png and OUT_DIR/walkers.yaml.
Deterministic: fixed parameters, no randomness, no threads in the decisions.
"""
import os
import shutil
import sys
import time

try:
    import cv2
    import numpy as np
except ImportError as e:  # CMake may have found a Python without OpenCV
    print(f"extract_walker_sprites: needs python3 with OpenCV and numpy ({e})", file=sys.stderr)
    sys.exit(2)

SEG = 130            # frames sharing one background (the scene changes slowly: tape in the wind)
BG_HALF = 150        # background = median of frames within +-BG_HALF of the segment's centre
BG_SAMPLES = 21
LO, HI = 20, 45      # colour difference of weak pixels, and of the seeds a blob must hold (hysteresis)
SHADOW_RATIO = (0.45, 0.97)  # a shadow darkens the ground by this factor ...
SHADOW_CHROMA = (12, 0.5)  # ... but keeps its chromaticity (max |normalised r,g,b| difference, x255),
                     # less so on saturated ground (grass under bluish skylight): 12 + 0.5 * saturation
MIN_H, ASPECT = 50, (1.8, 4.5)
MARGIN = 12          # isolation: no other foreground within the box grown by this many pixels
HEIGHT_TOL = 0.15
CYCLE, MIN_CYCLE = 12, 8
SAME_PERSON = 45     # appearance distance below which two sequences may show the same person


def frames(path):
    cap = cv2.VideoCapture(path)
    while cap.isOpened():
        ok, f = cap.read()
        if not ok:
            break
        yield f


def backgrounds(path):
    """Per segment of SEG frames, the per-pixel median of BG_SAMPLES frames around it."""
    kept, n = {}, 0
    for i, f in enumerate(frames(path)):
        if i % 4 == 0:  # keep a quarter of the frames in memory only
            kept[i] = f
        n = i + 1
    bgs = []
    for s in range(0, n, SEG):
        pool = [i for i in sorted(kept) if abs(i - s - SEG // 2) <= BG_HALF]
        pick = [pool[int(round(k))] for k in np.linspace(0, len(pool) - 1, min(BG_SAMPLES, len(pool)))]
        bgs.append(np.median(np.stack([kept[i] for i in pick]), axis=0).astype(np.uint8))
    return bgs, n


def segment(f, bg):
    """Foreground mask (uint8 0/1): moving objects, shadows removed, holes filled."""
    b, g, r = cv2.split(cv2.absdiff(f, bg))
    d = cv2.max(cv2.max(b, g), r)
    ys, xs = np.nonzero(d > LO)
    fp, bp = f[ys, xs].astype(np.float32) + 1, bg[ys, xs].astype(np.float32) + 1
    ratio = fp.sum(1) / bp.sum(1)
    fc, bc = fp / fp.sum(1, keepdims=True), bp / bp.sum(1, keepdims=True)
    chroma, sat = np.abs(fc - bc).max(1) * 255, np.abs(bc - 1 / 3).max(1) * 255
    lo, hi = SHADOW_RATIO
    keep = ~((ratio > lo) & (ratio < hi) & (chroma < SHADOW_CHROMA[0] + SHADOW_CHROMA[1] * sat))
    fg = np.zeros(d.shape, np.uint8)
    fg[ys[keep], xs[keep]] = 1
    fg = cv2.morphologyEx(fg, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))  # noise, thin tape
    # Hysteresis: a blob needs strongly different pixels; its weak pixels complete the outline.
    n, lab = cv2.connectedComponents(fg, connectivity=8)
    strong = np.zeros(n, bool)
    strong[np.unique(lab[(d > HI) & (fg > 0)])] = True
    strong[0] = False
    fg = strong[lab].astype(np.uint8)
    fg = cv2.morphologyEx(fg, cv2.MORPH_CLOSE, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5)))
    ff = np.pad(fg, 1)  # fill holes: background is what the zero region around the image reaches
    cv2.floodFill(ff, None, (0, 0), 2)
    return (ff[1:-1, 1:-1] != 2).astype(np.uint8)


def blobs(f, fg, min_area=150):
    """Blobs of one frame: box, centroid, whether it passes as one clean person, image and mask crops."""
    n, lab, st, cen = cv2.connectedComponentsWithStats(fg, connectivity=8)
    H, W = fg.shape
    out = []
    for k in range(1, n):
        x, y, w, h, area = (int(v) for v in st[k])
        if area < min_area:
            continue
        # Isolation: no other foreground near the box (people, parts of people, tape, noise).
        X0, Y0, X1, Y1 = max(0, x - MARGIN), max(0, y - MARGIN), min(W, x + w + MARGIN), min(H, y + h + MARGIN)
        others = int(fg[Y0:Y1, X0:X1].sum()) - area
        clean = (x > 1 and y > 1 and x + w < W - 1 and y + h < H - 1 and h >= MIN_H and others <= 10
                 and ASPECT[0] <= h / w <= ASPECT[1] and 0.3 <= area / (w * h) <= 0.8)
        mask = (lab[y:y + h, x:x + w] == k).astype(np.uint8) * 255
        out.append(dict(box=(x, y, w, h), c=cen[k], clean=clean, img=f[y:y + h, x:x + w].copy(), mask=mask))
    return out


def iou(a, b):
    ix = max(0, min(a[0] + a[2], b[0] + b[2]) - max(a[0], b[0]))
    iy = max(0, min(a[1] + a[3], b[1] + b[3]) - max(a[1], b[1]))
    return ix * iy / float(a[2] * a[3] + b[2] * b[3] - ix * iy)


def track(per_frame):
    """Chains of blobs overlapping one-to-one in consecutive frames; merges and splits end chains,
    so every chain is one person (or one group) throughout."""
    tracks, prev_tracks = [], {}
    for t, cur in enumerate(per_frame):
        prev = per_frame[t - 1] if t else []
        ov = np.array([[iou(p['box'], c['box']) for c in cur] for p in prev]).reshape(len(prev), len(cur))
        cur_tracks = {}
        for j in range(len(cur)):
            i = np.nonzero(ov[:, j] > 0)[0]
            if len(i) == 1 and np.count_nonzero(ov[i[0]] > 0) == 1 and ov[i[0], j] > 0.3:
                cur_tracks[j] = prev_tracks[i[0]]
            else:
                cur_tracks[j] = []
                tracks.append(cur_tracks[j])
            cur_tracks[j].append((t, cur[j]))
        prev_tracks = cur_tracks
    return tracks


def best_window(tr):
    """Steadiest run of CYCLE (else >= MIN_CYCLE) clean frames of a walking (not standing) person."""
    for L in range(CYCLE, MIN_CYCLE - 1, -1):
        best = None
        for s in range(len(tr) - L + 1):
            win = tr[s:s + L]
            if not all(b['clean'] for _, b in win):
                continue
            h = np.array([b['box'][3] for _, b in win], float)
            dev = np.abs(h / np.median(h) - 1).max()
            move = np.linalg.norm(win[-1][1]['c'] - win[0][1]['c'])
            if dev <= HEIGHT_TOL and move >= 0.5 * np.median([b['box'][2] for _, b in win]):
                if best is None or dev < best[0]:
                    best = (dev, win)
        if best:
            return best[1]
    return None


def appearance(win, bands=4):
    """Median colour of the person in horizontal bands, head to feet (Lab; lightness halved: it
    varies most with the lighting across the plaza). Median over the frames."""
    per = []
    for _, b in win:
        lab = cv2.cvtColor(b['img'], cv2.COLOR_BGR2Lab).astype(np.float32) * (0.5, 1, 1)
        h, m = lab.shape[0], b['mask'] > 0
        per.append([np.median(lab[k * h // bands:(k + 1) * h // bands][m[k * h // bands:(k + 1) * h // bands]], 0)
                    for k in range(bands)])
    return np.median(per, axis=0)


def one_per_person(cands):
    """Group sequences showing the same person: average-linkage clustering on appearance (distance of
    the most different body band, so hair or trousers alone tell people apart), where sequences whose
    tracks coexist in time are never joined: they are two people."""
    n = len(cands)
    app = [appearance(c['win']) for c in cands]
    dist = np.array([[np.abs(app[i] - app[j]).sum(1).max() for j in range(n)] for i in range(n)])
    apart = np.array([[a['span'][0] <= b['span'][1] and b['span'][0] <= a['span'][1] for b in cands] for a in cands])
    groups = [[i] for i in range(n)]
    while True:
        best = None
        for a in range(len(groups)):
            for b in range(a + 1, len(groups)):
                ix = np.ix_(groups[a], groups[b])
                d = dist[ix].mean()
                if not apart[ix].any() and d < SAME_PERSON and (best is None or d < best[0]):
                    best = (d, a, b)
        if best is None:
            break
        groups[best[1]] += groups.pop(best[2])
    # Per person: the longest, then sideways (what the simulator shows most), then tallest sequence.
    key = lambda c: (-len(c['win']), direction(c['win']) not in ('left', 'right'), -height(c['win']), c['win'][0][0])
    return sorted((min((cands[i] for i in g), key=key) for g in groups), key=lambda c: c['win'][0][0])


def height(win):
    return int(np.median([b['box'][3] for _, b in win]))


def direction(win):
    (x0, y0), (x1, y1) = win[0][1]['c'], win[-1][1]['c']
    if abs(x1 - x0) >= abs(y1 - y0):
        return 'right' if x1 > x0 else 'left'
    return 'towards' if y1 > y0 else 'away'  # elevated camera: coming closer moves down the image


def main(argv):
    if len(argv) != 3:
        print(__doc__, file=sys.stderr)
        return 2
    video, out = argv[1], argv[2]
    t0 = time.time()
    if not cv2.VideoCapture(video).isOpened():
        print(f"extract_walker_sprites: cannot open video {video}", file=sys.stderr)
        return 2
    bgs, n = backgrounds(video)
    per_frame = [blobs(f, segment(f, bgs[i // SEG])) for i, f in enumerate(frames(video))]
    cands = []
    for tr in track(per_frame):
        win = best_window(tr)
        if win:
            cands.append(dict(win=win, span=(tr[0][0], tr[-1][0])))
    walkers = one_per_person(cands)
    if len(walkers) < 4:
        print(f"extract_walker_sprites: only {len(walkers)} clean walkers in {video} (need 4)", file=sys.stderr)
        return 2
    os.makedirs(out, exist_ok=True)
    for d in os.listdir(out):  # sprites of an earlier run must not outlive it
        if d.startswith("walker_") and os.path.isdir(os.path.join(out, d)):
            shutil.rmtree(os.path.join(out, d))
    lines = ["# generated by scripts/extract_walker_sprites.py from vtest.avi: do not edit",
             f"source: {video}", "walkers:"]
    for k, c in enumerate(walkers):
        name = f"walker_{k:02d}"
        os.makedirs(os.path.join(out, name), exist_ok=True)
        for j, (_, b) in enumerate(c['win']):
            bgra = np.dstack([b['img'], b['mask']])
            bgra[b['mask'] == 0, :3] = 0  # no background colour hidden under alpha 0
            cv2.imwrite(os.path.join(out, name, f"frame_{j:02d}.png"), bgra, [cv2.IMWRITE_PNG_COMPRESSION, 6])
        lines += [f"  - name: {name}", f"    frames: {len(c['win'])}", f"    first_video_frame: {c['win'][0][0]}",
                  f"    height_px: {height(c['win'])}        # median silhouette height",
                  f"    direction: {direction(c['win'])}"]
    with open(os.path.join(out, "walkers.yaml"), "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print(f"extract_walker_sprites: {len(walkers)} walkers ({len(cands)} clean sequences) from {n} frames "
          f"written to {out} in {time.time() - t0:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
