#!/usr/bin/env python3
"""Generates the small trajectory pair used by tests/app/test_eval_reference.cpp.

gt_synthetic.csv   EuRoC ground-truth CSV (t [ns], p, q with w first), 10 Hz, 40 s, a drone-like
                   3-D flight (no real data is copied).
est_synthetic.txt  TUM (t [s], p, q with w last): the same flight seen in another world frame
                   (rotation, translation, scale 0.9), with position noise, a slow random-walk
                   drift, orientation noise, +-3 ms time jitter, 5 % of the poses dropped and
                   the first/last second missing.
Run with /usr/bin/python3 (numpy, scipy). Deterministic (fixed seed).
"""
import numpy as np
from scipy.spatial.transform import Rotation

rng = np.random.default_rng(20240611)
n = 400
t_ns = 1_700_000_000_000_000_000 + np.arange(n, dtype=np.int64) * 100_000_000
s = np.arange(n) * 0.1
p = np.stack([3.0 * np.sin(0.21 * s) + 0.5 * np.sin(0.9 * s),
              2.0 * np.sin(0.37 * s + 0.4) + 0.3 * np.cos(1.1 * s),
              1.2 + 0.4 * np.sin(0.5 * s)], axis=1)
vel = np.gradient(p, 0.1, axis=0)
yaw = np.arctan2(vel[:, 1], vel[:, 0])
R_W_B = Rotation.from_euler('zyx', np.stack([yaw, 0.05 * np.sin(0.8 * s), 0.04 * np.cos(0.6 * s)], axis=1))
q_xyzw = R_W_B.as_quat()

with open('gt_synthetic.csv', 'w') as f:
    f.write('#timestamp [ns],p_x [m],p_y [m],p_z [m],q_w [],q_x [],q_y [],q_z []\n')
    for k in range(n):
        x, y, z, w = q_xyzw[k]
        f.write('%d,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f,%.9f\n' % (t_ns[k], *p[k], w, x, y, z))

R_E_G = Rotation.from_euler('zyx', [-50.0, 6.0, 3.0], degrees=True)
t_E_G = np.array([-4.0, 2.5, 0.3])
scale = 0.9
drift = np.cumsum(rng.normal(0.0, 0.004, p.shape), axis=0)
p_noisy = p + rng.normal(0.0, 0.02, p.shape) + drift
p_est = scale * R_E_G.apply(p_noisy) + t_E_G
R_est = R_E_G * R_W_B * Rotation.from_rotvec(rng.normal(0.0, np.radians(0.4), p.shape))
q_est = R_est.as_quat()
t_est = t_ns + rng.integers(-3_000_000, 3_000_001, n)
keep = (rng.random(n) > 0.05) & (np.arange(n) >= 10) & (np.arange(n) < n - 10)

with open('est_synthetic.txt', 'w') as f:
    f.write('# timestamp[s] tx ty tz qx qy qz qw\n')
    for k in np.nonzero(keep)[0]:
        sec, ns = divmod(int(t_est[k]), 1_000_000_000)
        f.write('%d.%09d %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n' % (sec, ns, *p_est[k], *q_est[k]))
