#!/usr/bin/python3
"""Rotation between nearby frames of a trajectory against the truth, stretch by stretch (session 34).

  /usr/bin/python3 docs/experiments/session34_relative_rotation.py RUN/trajectory.tum SEQ/mav0/state_groundtruth_estimate0/data.csv [W]

For frames i and i + W (default 5) of each stretch: the error of the relative rotation,
log(R_true_rel^T R_est_rel) (camera frames, so no alignment is needed; the synthetic suite's body
frame is cam0), its mean norm and its mean component along the true rotation axis (negative: the
turn estimated short). numpy only.
"""
import sys
import numpy as np


def rotation(x, y, z, w):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def so3_log(R):
    a = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    if a < 1e-9:
        return np.zeros(3)
    return a / (2 * np.sin(a)) * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]])


def main():
    est, truth = {}, {}
    for line in open(sys.argv[1]):
        if line.startswith("#") or not line.strip():
            continue
        v = [float(x) for x in line.split()]
        est[round(v[0], 3)] = rotation(*v[4:8])
    for line in open(sys.argv[2]):
        if line.startswith("#"):
            continue
        v = [float(x) for x in line.strip().split(",")]
        truth[round(v[0] * 1e-9, 3)] = rotation(v[5], v[6], v[7], v[4])
    w = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    ts = sorted(t for t in est if t in truth)
    for lo, hi in [(14, 34), (34, 46), (46, 56), (56, 100), (100, 140), (140, 200)]:
        along, norm = [], []
        for i in range(lo, min(hi, len(ts) - w)):
            R_est = est[ts[i]].T @ est[ts[i + w]]
            R_true = truth[ts[i]].T @ truth[ts[i + w]]
            axis = so3_log(R_true)
            err = so3_log(R_true.T @ R_est)
            norm.append(np.degrees(np.linalg.norm(err)))
            if np.linalg.norm(axis) > 1e-6:
                along.append(np.degrees(err @ axis / np.linalg.norm(axis)))
        if norm:
            print(f"frames {lo:3d}-{hi:3d}: {w}-frame relative rotation off by {np.mean(norm):.3f} deg on average, "
                  f"{np.mean(along):+.3f} deg along the true turn")


if __name__ == "__main__":
    main()
