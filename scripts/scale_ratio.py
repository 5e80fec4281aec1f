#!/usr/bin/python3
"""Scale drift of a trajectory: estimated / true distance travelled over consecutive windows of frames.

  /usr/bin/python3 scripts/scale_ratio.py RUN/trajectory.tum SEQ/mav0/state_groundtruth_estimate0/data.csv [--window 10]

The estimate is pllvo's trajectory.tum (timestamps in seconds), the truth a EuRoC ground-truth csv (ns);
poses are paired by timestamp (to the millisecond). A monocular run has an arbitrary scale, so read the
ratios against each other: a constant row is a constant scale, a falling one is scale drift. Standard
library only.
"""
import argparse
import math
import sys


def read_positions(path, separator, seconds_per_unit, layout):
    """{time in s (to the ms): (x, y, z)} from a file whose lines start with time, x, y, z."""
    poses = {}
    with open(path) as f:
        for n, line in enumerate(f, 1):
            if line.startswith("#") or not line.strip():
                continue
            v = line.strip().split(separator)
            if len(v) < 4:
                sys.exit(f"scale_ratio: error: {path}:{n}: expected '{layout}'")
            poses[round(float(v[0]) * seconds_per_unit, 3)] = tuple(float(x) for x in v[1:4])
    return poses


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("estimate")
    p.add_argument("truth")
    p.add_argument("--window", type=int, default=10, help="frames per window")
    args = p.parse_args()
    est = read_positions(args.estimate, None, 1.0, "time x y z ...")
    gt = read_positions(args.truth, ",", 1e-9, "ns,x,y,z,...")
    times = sorted(t for t in est if t in gt)
    if len(times) <= args.window:
        sys.exit("scale_ratio: error: fewer paired poses than one window")
    ratios = []
    for i in range(0, len(times) - args.window, args.window):
        a, b = times[i], times[i + args.window]
        true = math.dist(gt[a], gt[b])
        ratios.append(f"{math.dist(est[a], est[b]) / true:.2f}" if true > 1e-6 else "-")
    print(" ".join(ratios))


if __name__ == "__main__":
    main()
