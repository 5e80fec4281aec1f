#!/usr/bin/env python3
"""Runs pllvo over a dataset folder frame by frame and plots the trajectory against the ground truth.

    PYTHONPATH=build/python python3 examples/python/run_and_plot.py ../shared/data/kitti_06_stereo51/sequences/06 out.png

The estimate is aligned to the ground truth (Umeyama: SE(3) for stereo, Sim(3) for mono) over the frames both have,
and drawn in the plane of largest motion with equal axis scales.
"""
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt
import numpy as np

import pllvo


def umeyama(source, target, with_scale):
    """s, R, t minimising |target - (s R source + t)|^2 (rows are points)."""
    mu_s, mu_t = source.mean(0), target.mean(0)
    cov = (target - mu_t).T @ (source - mu_s) / len(source)
    u, d, vt = np.linalg.svd(cov)
    flip = np.diag([1.0, 1.0, np.sign(np.linalg.det(u @ vt))])
    rotation = u @ flip @ vt
    scale = np.trace(np.diag(d) @ flip) / ((source - mu_s) ** 2).sum(1).mean() if with_scale else 1.0
    return scale, rotation, mu_t - scale * rotation @ mu_s


def main(dataset_folder, png):
    dataset = pllvo.Dataset(dataset_folder)
    odometry = pllvo.Odometry(dataset.calibration)
    for i in range(len(dataset)):
        result = odometry.track(*dataset.frame(i))
        print(f"{result.timestamp:.3f} {result.state:12s} points {result.tracked_points:4d} lines {result.tracked_lines:3d}")
    odometry.finish()
    stamps, poses = odometry.trajectory()
    gt_stamps, gt_poses = dataset.ground_truth()
    estimate = poses[:, :3, 3]
    fig, ax = plt.subplots(figsize=(6, 6))
    if len(gt_stamps):
        nearest = np.abs(gt_stamps[None, :] - stamps[:, None]).argmin(1)
        truth = gt_poses[nearest, :3, 3]
        s, R, t = umeyama(estimate, truth, with_scale=not odometry.stereo)
        estimate = (s * (R @ estimate.T)).T + t
        ate = np.sqrt(((estimate - truth) ** 2).sum(1).mean())
        axes = np.argsort(np.ptp(truth, 0))[::-1][:2]
        ax.plot(truth[:, axes[0]], truth[:, axes[1]], "k-", label="ground truth")
        ax.set_title(f"ATE {ate:.3f} m over {len(stamps)} frames")
    else:
        axes = np.argsort(np.ptp(estimate, 0))[::-1][:2]
    ax.plot(estimate[:, axes[0]], estimate[:, axes[1]], "r-", label="pllvo")
    ax.set_xlabel("xyz"[axes[0]] + " [m]")
    ax.set_ylabel("xyz"[axes[1]] + " [m]")
    ax.set_aspect("equal", adjustable="datalim")
    ax.legend()
    fig.savefig(png, dpi=120)
    print(f"tracked {len(stamps)} of {len(dataset)} frames; plot: {png}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit("usage: run_and_plot.py DATASET OUT.png")
    main(sys.argv[1], sys.argv[2])
