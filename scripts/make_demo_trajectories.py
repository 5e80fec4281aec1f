#!/usr/bin/python3
"""Writes the bundled demo pair examples/trajectories/{ref,est}.tum (pllvo's own synthetic data).

ref: a smooth 3-D figure-8 (about 26 m) at 20 Hz, heading along the direction of motion.
est: the same motion re-integrated with a small yaw bias and a 1 % scale error (drift), plus
noise, expressed in another world frame (rigid transform), with stamp jitter and a few drops.
Deterministic (fixed seed); pure Python, no dependencies. Run from the repository root:
    python3 scripts/make_demo_trajectories.py
"""
import math
import os
import random

N = 400
RATE = 20.0
T0 = 1700000000.0


def mat_mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def mat_vec(a, v):
    return [sum(a[i][k] * v[k] for k in range(3)) for i in range(3)]


def transpose(a):
    return [[a[j][i] for j in range(3)] for i in range(3)]


def axis_angle(axis, angle):
    n = math.sqrt(sum(c * c for c in axis))
    x, y, z = (c / n for c in axis)
    c, s, C = math.cos(angle), math.sin(angle), 1 - math.cos(angle)
    return [[c + x * x * C, x * y * C - z * s, x * z * C + y * s],
            [y * x * C + z * s, c + y * y * C, y * z * C - x * s],
            [z * x * C - y * s, z * y * C + x * s, c + z * z * C]]


def quaternion(r):
    """(qx, qy, qz, qw) of a rotation matrix (Shepperd's method)."""
    tr = r[0][0] + r[1][1] + r[2][2]
    if tr > 0:
        s = math.sqrt(tr + 1.0) * 2
        return ((r[2][1] - r[1][2]) / s, (r[0][2] - r[2][0]) / s, (r[1][0] - r[0][1]) / s, 0.25 * s)
    i = max(range(3), key=lambda k: r[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = math.sqrt(1.0 + r[i][i] - r[j][j] - r[k][k]) * 2
    q = [0.0, 0.0, 0.0]
    q[i] = 0.25 * s
    q[j] = (r[j][i] + r[i][j]) / s
    q[k] = (r[k][i] + r[i][k]) / s
    return (q[0], q[1], q[2], (r[k][j] - r[j][k]) / s)


def reference_pose(t):
    w = 2 * math.pi / (N / RATE)
    p = [3.0 * math.sin(w * t), 1.5 * math.sin(2 * w * t), 1.2 + 0.3 * math.sin(0.5 * w * t)]
    v = [3.0 * w * math.cos(w * t), 3.0 * w * math.cos(2 * w * t), 0.15 * w * math.cos(0.5 * w * t)]
    yaw = math.atan2(v[1], v[0])
    r = mat_mul(axis_angle([0, 0, 1], yaw), mat_mul(axis_angle([0, 1, 0], 0.1 * math.sin(w * t)),
                                                     axis_angle([1, 0, 0], 0.05 * math.cos(3 * w * t))))
    return r, p


def write(path, rows):
    with open(path, "w") as f:
        f.write("# timestamp tx ty tz qx qy qz qw\n")
        for stamp, r, p in rows:
            q = quaternion(r)
            f.write("%.6f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n" % ((stamp,) + tuple(p) + q))


def main():
    rng = random.Random(20240601)
    ref = [(T0 + i / RATE,) + reference_pose(i / RATE) for i in range(N)]

    # Estimate: integrate the true relative motions with a yaw bias and a scale error.
    G_r = mat_mul(axis_angle([0, 0, 1], math.radians(35)), axis_angle([1, 0.3, 0], math.radians(6)))
    G_t = [1.5, -2.0, 0.4]
    bias = axis_angle([0, 0, 1], math.radians(0.02))
    est = []
    r_est, p_est = ref[0][1], ref[0][2]
    for i, (stamp, r, p) in enumerate(ref):
        if i > 0:
            _, r_prev, p_prev = ref[i - 1]
            rel_r = mat_mul(transpose(r_prev), r)
            rel_p = mat_vec(transpose(r_prev), [a - b for a, b in zip(p, p_prev)])
            p_est = [a + b for a, b in zip(p_est, mat_vec(r_est, [1.01 * c for c in rel_p]))]
            r_est = mat_mul(mat_mul(r_est, rel_r), bias)
        if i > 0 and rng.random() < 0.03:
            continue  # a dropped frame
        noise_r = axis_angle([rng.gauss(0, 1) for _ in range(3)], math.radians(rng.gauss(0, 0.1)))
        r_noisy = mat_mul(r_est, noise_r)
        p_noisy = [c + rng.gauss(0, 0.005) for c in p_est]
        est.append((stamp + rng.uniform(-0.001, 0.001), mat_mul(G_r, r_noisy),
                    [a + b for a, b in zip(mat_vec(G_r, p_noisy), G_t)]))

    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "examples", "trajectories")
    os.makedirs(out, exist_ok=True)
    write(os.path.join(out, "ref.tum"), ref)
    write(os.path.join(out, "est.tum"), est)
    print("wrote %d reference and %d estimated poses to %s" % (len(ref), len(est), os.path.normpath(out)))


if __name__ == "__main__":
    main()
