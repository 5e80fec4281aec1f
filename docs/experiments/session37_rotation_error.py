"""Per-frame rotation error of a monocular run on a synthetic sequence (session 37).

  /usr/bin/python3 docs/experiments/session37_rotation_error.py RUN/trajectory.tum SEQ_FOLDER [FIRST [EVERY]]

Prints, per frame, the angle (deg) between the estimated and the true orientation after aligning
the first frames (the synthetic T_BS is the identity), the step's rotation error
log(R_true_step^T R_est_step) and the true step rotation (rotation vectors, deg).
"""
import sys

import numpy as np


def quat_matrix(w, x, y, z):
    n = np.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def angle_deg(R):
    return np.degrees(np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1)))


def log_deg(R):
    a = np.arccos(np.clip((np.trace(R) - 1) / 2, -1, 1))
    if a < 1e-9:
        return np.zeros(3)
    return np.degrees(a / (2 * np.sin(a)) * np.array([R[2, 1] - R[1, 2], R[0, 2] - R[2, 0], R[1, 0] - R[0, 1]]))


def main():
    est = np.loadtxt(sys.argv[1])
    gt = np.loadtxt(f"{sys.argv[2]}/mav0/state_groundtruth_estimate0/data.csv", delimiter=",", comments="#")
    first = int(sys.argv[3]) if len(sys.argv) > 3 else 0
    every = int(sys.argv[4]) if len(sys.argv) > 4 else 1
    t_gt = gt[:, 0] * 1e-9
    R_est = [quat_matrix(r[7], r[4], r[5], r[6]) for r in est]  # TUM: qx qy qz qw
    R_gt = [quat_matrix(*gt[np.argmin(abs(t_gt - t)), 4:8]) for t in est[:, 0]]  # EuRoC: qw qx qy qz
    align = R_gt[0] @ R_est[0].T
    for i in range(len(est)):
        if i < first or i % every:
            continue
        step_err = step_true = np.zeros(3)
        if i > 0:
            step_est, step_true_R = R_est[i - 1].T @ R_est[i], R_gt[i - 1].T @ R_gt[i]
            step_err, step_true = log_deg(step_true_R.T @ step_est), log_deg(step_true_R)
        print(f"{i} {angle_deg(R_gt[i].T @ align @ R_est[i]):.2f} step_err {np.round(step_err, 2)} "
              f"true_step {np.round(step_true, 2)}")


if __name__ == "__main__":
    main()
