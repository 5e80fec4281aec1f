#!/usr/bin/python3
"""A run's frames re-expressed through their keyframes' final poses (ORB-SLAM's trajectory convention).

  /usr/bin/python3 docs/experiments/session36_keyframe_composed_trajectory.py RUN OUT.tum

RUN is a `pllvo run --out` folder. Each frame of RUN/trajectory.tum (its pose as tracked) becomes
T_kf_final * T_kf_tracked^-1 * T_frame_tracked, with kf the latest keyframe at or before the frame
(RUN/keyframes.tum holds the keyframes' poses after every later window BA; the keyframe's tracked
pose is its frame's line in trajectory.tum). Frames before the first keyframe stay as they are.
Compare both files with `pllvo eval FILE SEQ/mav0/state_groundtruth_estimate0/data.csv --metric ape
--align sim3` (docs/vo.md, session 36). Needs numpy.
"""
import sys

import numpy as np


def to_matrix(row):
    x, y, z, w = row[4:8] / np.linalg.norm(row[4:8])
    T = np.eye(4)
    T[:3, :3] = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                 [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                 [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    T[:3, 3] = row[1:4]
    return T


def to_quaternion(R):
    w = np.sqrt(max(0.0, 1 + np.trace(R))) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return x, y, z, w


def main():
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    frames = np.loadtxt(sys.argv[1] + "/trajectory.tum", ndmin=2)
    keyframes = np.loadtxt(sys.argv[1] + "/keyframes.tum", ndmin=2)
    tracked = {round(r[0], 6): to_matrix(r) for r in frames}
    with open(sys.argv[2], "w") as out:
        for r in frames:
            k = np.searchsorted(keyframes[:, 0], r[0] + 1e-7) - 1
            T = to_matrix(r)
            if k >= 0 and round(keyframes[k, 0], 6) in tracked:
                T = to_matrix(keyframes[k]) @ np.linalg.inv(tracked[round(keyframes[k, 0], 6)]) @ T
            out.write("%.9f %.9f %.9f %.9f %.9f %.9f %.9f %.9f\n" % (r[0], *T[:3, 3], *to_quaternion(T[:3, :3])))


if __name__ == "__main__":
    main()
