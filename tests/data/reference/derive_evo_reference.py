#!/usr/bin/env python3
"""Re-derives the reference figures of tests/app/test_eval_reference.cpp from the checked-in pair
(gt_synthetic.csv, est_synthetic.txt) with numpy alone, as the `evo` tool computes them
(sync.associate_trajectories with max_diff 0.01 s, geometry.umeyama_alignment,
trajectory.align_trajectory with --correct_scale / --n_to_align, APE of translation_part and
rotation_angle_deg) and, for posyaw, as OpenVINS' ov_eval AlignUtils does (yaw-only Umeyama).

  /usr/bin/python3 tests/data/reference/derive_evo_reference.py > tests/data/reference/evo_reference.txt

The test reads evo_reference.txt: re-running this script must reproduce it (run outside CI; it is
independent of the project's code). One line per case: mode, frames aligned on (-1 = all),
scale, then rmse mean median std min max of the translation error [m] and of the rotation error
[deg].
"""
import os

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))


def quat_to_rot(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def read_gt():  # EuRoC CSV: t [ns], p, q (w first)
    rows = np.loadtxt(os.path.join(HERE, "gt_synthetic.csv"), delimiter=",", comments="#")
    t = rows[:, 0] * 1e-9
    return t, rows[:, 1:4], [quat_to_rot(*r[4:8]) for r in rows]


def read_est():  # TUM: t [s], p, q (w last)
    rows = np.loadtxt(os.path.join(HERE, "est_synthetic.txt"), comments="#")
    return rows[:, 0], rows[:, 1:4], [quat_to_rot(r[7], r[4], r[5], r[6]) for r in rows]


def associate(t_ref, t_est, max_diff=0.01):
    """evo's sync.associate_trajectories: the shorter trajectory's stamps each matched to the
    nearest stamp of the longer one when within max_diff."""
    est_shorter = len(t_est) <= len(t_ref)
    short, long_ = (t_est, t_ref) if est_shorter else (t_ref, t_est)
    pairs = []
    for i, s in enumerate(short):
        d = np.abs(long_ - s)
        j = int(np.argmin(d))
        if d[j] <= max_diff:
            pairs.append((j, i) if est_shorter else (i, j))  # (ref index, est index)
    return pairs


def umeyama(x, y, with_scale):
    """evo's geometry.umeyama_alignment: R, t, c minimising ||y - (c R x + t)||, x and y 3 x n."""
    n = x.shape[1]
    mx, my = x.mean(axis=1), y.mean(axis=1)
    sigma_x = 1.0 / n * np.linalg.norm(x - mx[:, None]) ** 2
    cov = 1.0 / n * (y - my[:, None]) @ (x - mx[:, None]).T
    u, d, v = np.linalg.svd(cov)
    s = np.eye(3)
    if np.linalg.det(u) * np.linalg.det(v) < 0.0:
        s[2, 2] = -1
    r = u @ s @ v
    c = 1 / sigma_x * np.trace(np.diag(d) @ s) if with_scale else 1.0
    t = my - c * r @ mx
    return r, t, c


def yaw_only(x, y):
    """ov_eval AlignUtils::align_umeyama with yaw_only (known scale 1): the rotation about z that
    best maps the centred x onto the centred y."""
    mx, my = x.mean(axis=1), y.mean(axis=1)
    c = (y - my[:, None]) @ (x - mx[:, None]).T  # sum of y_i x_i^T
    theta = np.arctan2(c[1, 0] - c[0, 1], c[0, 0] + c[1, 1])
    r = np.array([[np.cos(theta), -np.sin(theta), 0], [np.sin(theta), np.cos(theta), 0], [0, 0, 1]])
    return r, my - r @ mx, 1.0


def stats(e):
    return [np.sqrt(np.mean(e ** 2)), np.mean(e), np.median(e), np.std(e), np.min(e), np.max(e)]


def case(mode, frames):
    t_ref, p_ref, r_ref = read_gt()
    t_est, p_est, r_est = read_est()
    pairs = associate(t_ref, t_est)
    ref_p = np.array([p_ref[i] for i, _ in pairs]).T
    est_p = np.array([p_est[j] for _, j in pairs]).T
    ref_r = [r_ref[i] for i, _ in pairs]
    est_r = [r_est[j] for _, j in pairs]
    n = len(pairs) if frames < 0 else frames
    if mode == "none":
        r, t, c = np.eye(3), np.zeros(3), 1.0
    elif mode == "posyaw":
        r, t, c = yaw_only(est_p[:, :n], ref_p[:, :n])
    else:
        r, t, c = umeyama(est_p[:, :n], ref_p[:, :n], mode == "sim3")
    aligned = c * r @ est_p + t[:, None]
    trans = np.linalg.norm(aligned - ref_p, axis=0)
    rot = []
    for rr, re in zip(ref_r, est_r):
        rel = rr.T @ (r @ re)
        rot.append(np.degrees(np.arccos(np.clip((np.trace(rel) - 1) / 2, -1.0, 1.0))))
    return len(pairs), c, stats(trans), stats(np.array(rot))


def main():
    print("# mode frames scale trans(rmse mean median std min max) rot(rmse mean median std min max) pairs")
    for mode, frames in [("se3", -1), ("sim3", -1), ("posyaw", -1), ("none", -1), ("se3", 50)]:
        pairs, scale, trans, rot = case(mode, frames)
        print(mode, frames, repr(float(scale)), " ".join(repr(float(v)) for v in trans + rot), pairs)


if __name__ == "__main__":
    main()
