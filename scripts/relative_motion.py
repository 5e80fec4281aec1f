#!/usr/bin/python3
"""How far a run's motion strays from the truth, measured from one frame: the monocular start's quality.

  /usr/bin/python3 scripts/relative_motion.py RUN SEQ [--from F] [--to F] [--every N] [--start | --steps]

RUN is a `pllvo run --out` folder (trajectory.tum, keyframes.tum), SEQ the EuRoC-layout sequence it
ran on (mav0/cam0/data.csv gives the frame numbers, mav0/state_groundtruth_estimate0/data.csv the
truth; cam0 is the body frame, as in `pllvo synth` sequences). The first line judges the start:
the first two keyframes (a monocular start's reference and second view), the error of the second's
translation direction and rotation relative to the first. Then, every N frames from --from
(default: the first keyframe), the motion since --from: the error of its direction and rotation,
and the estimated over the true distance (a monocular run's scale is arbitrary: read the column
against itself; a falling column is the scale shrinking). With --steps, the frame-to-frame motion
instead, summed up per N frames: the mean error of each step's rotation against the true step's
rotation (the drift of the heading, which no alignment hides), and the median error of each step's
translation direction. Standard library only.
"""
import argparse
import math
import os
import sys


def quat_matrix(w, x, y, z):
    n = math.sqrt(w * w + x * x + y * y + z * z)
    w, x, y, z = w / n, x / n, y / n, z / n
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
            [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
            [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]


def transpose(m):
    return [list(r) for r in zip(*m)]


def mul(a, b):
    return [[sum(a[i][k] * b[k][j] for k in range(3)) for j in range(3)] for i in range(3)]


def apply(m, v):
    return [sum(m[i][k] * v[k] for k in range(3)) for i in range(3)]


def angle_of(m):
    """Rotation angle (deg) of a rotation matrix."""
    return math.degrees(math.acos(max(-1.0, min(1.0, (m[0][0] + m[1][1] + m[2][2] - 1) / 2))))


def angle_between(a, b):
    na, nb = math.hypot(*a), math.hypot(*b)
    if na < 1e-12 or nb < 1e-12:
        return float("nan")
    return math.degrees(math.acos(max(-1.0, min(1.0, sum(x * y for x, y in zip(a, b)) / (na * nb)))))


def read_poses(path, parse, layout):
    """{time in s (to the ms): (R, t)} from the lines of a file, each parsed by `parse` (None: malformed)."""
    poses = {}
    with open(path) as f:
        for n, line in enumerate(f, 1):
            if line.startswith("#") or not line.strip():
                continue
            try:
                pose = parse(line)
            except ValueError:
                pose = None
            if pose is None:
                sys.exit(f"relative_motion: error: {path}:{n}: expected '{layout}'")
            poses[pose[0]] = pose[1:]
    return poses


def parse_tum(line):
    """t x y z qx qy qz qw (seconds)."""
    v = line.split()
    if len(v) != 8:
        return None
    v = [float(x) for x in v]
    return round(v[0], 3), quat_matrix(v[7], v[4], v[5], v[6]), v[1:4]


def parse_euroc(line):
    """ns,px,py,pz,qw,qx,qy,qz,... (EuRoC ground truth)."""
    v = line.strip().split(",")
    if len(v) < 8:
        return None
    v = [float(x) for x in v[:8]]
    return round(v[0] * 1e-9, 3), quat_matrix(*v[4:8]), v[1:4]


def relative(a, b):
    """Motion from pose a to pose b in a's frame: (rotation, translation)."""
    Ra_t = transpose(a[0])
    return mul(Ra_t, b[0]), apply(Ra_t, [y - x for x, y in zip(a[1], b[1])])


def compare(est, gt, t0, t1):
    """Direction error (deg), rotation error (deg), estimated / true distance, true rotation (deg)."""
    Re, te = relative(est[t0], est[t1])
    Rg, tg = relative(gt[t0], gt[t1])
    true_distance = math.hypot(*tg)
    ratio = math.hypot(*te) / true_distance if true_distance > 1e-9 else float("nan")
    return angle_between(te, tg), angle_of(mul(transpose(Re), Rg)), ratio, angle_of(Rg)


def print_steps(est, gt, frame_times, first, last, every):
    """Per window of `every` frames: mean step rotation error and true step rotation, median direction error."""
    print("frames     steps  rotation_err_deg  true_rotation_deg  median_direction_err_deg")
    for lo in range(first + 1, last + 1, every):
        end = min(lo + every, last + 1)
        rot_err, true_rot, dir_err = [], [], []
        for f in range(lo, end):
            a, b = frame_times[f - 1], frame_times[f]
            if not all(t in est and t in gt for t in (a, b)):
                continue
            d, r, _, rot = compare(est, gt, a, b)
            rot_err.append(r)
            true_rot.append(rot)
            dir_err.append(d)
        if not rot_err:
            print(f"{lo:4d}-{end - 1:<4d}  0  (not tracked)")
            continue
        n = len(rot_err)
        print(f"{lo:4d}-{end - 1:<4d} {n:4d}  {sum(rot_err) / n:16.2f}  {sum(true_rot) / n:17.2f}  "
              f"{sorted(dir_err)[n // 2]:24.1f}")


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("run")
    p.add_argument("sequence")
    p.add_argument("--from", dest="first", type=int, help="frame to measure from (default: the first keyframe)")
    p.add_argument("--to", dest="last", type=int, help="last frame (default: the last estimated)")
    p.add_argument("--every", type=int, default=10, help="frames between printed lines")
    what = p.add_mutually_exclusive_group()
    what.add_argument("--start", action="store_true", help="print the start's line only")
    what.add_argument("--steps", action="store_true", help="frame-to-frame errors per --every frames")
    args = p.parse_args()
    if args.every < 1:
        p.error("--every must be at least 1")
    mav = args.sequence.rstrip("/") + "/mav0"
    run = args.run.rstrip("/")
    for path in (mav + "/cam0/data.csv", mav + "/state_groundtruth_estimate0/data.csv", run + "/trajectory.tum",
                 run + "/keyframes.tum"):
        if not os.path.isfile(path):
            sys.exit(f"relative_motion: error: {path}: no such file")
    with open(mav + "/cam0/data.csv") as f:
        frame_times = [round(int(l.split(",")[0]) * 1e-9, 3) for l in f if l.strip() and not l.startswith("#")]
    frame_of = {t: i for i, t in enumerate(frame_times)}
    est = read_poses(run + "/trajectory.tum", parse_tum, "t x y z qx qy qz qw")
    gt = read_poses(mav + "/state_groundtruth_estimate0/data.csv", parse_euroc, "ns,px,py,pz,qw,qx,qy,qz,...")
    keyframes = sorted(read_poses(run + "/keyframes.tum", parse_tum, "t x y z qx qy qz qw"))
    if len(keyframes) < 2:
        sys.exit("relative_motion: error: fewer than two keyframes")
    k0, k1 = keyframes[0], keyframes[1]
    if all(t in est and t in gt for t in (k0, k1)):
        d, r, _, rot = compare(est, gt, k0, k1)
        print(f"start: frames {frame_of.get(k0, '?')} -> {frame_of.get(k1, '?')}: direction {d:.1f} deg off, "
              f"rotation {r:.2f} deg off (true rotation {rot:.1f} deg)")
    if args.start:
        return
    first = args.first if args.first is not None else frame_of.get(k0, 0)
    if not 0 <= first < len(frame_times) or frame_times[first] not in est:
        sys.exit(f"relative_motion: error: frame {first} has no estimated pose")
    last_tracked = max(f for f, t in enumerate(frame_times) if t in est)
    last = min(args.last, len(frame_times) - 1) if args.last is not None else last_tracked
    if args.steps:
        print_steps(est, gt, frame_times, first, last, args.every)
        return
    t0 = frame_times[first]
    print("frame  direction_err_deg  rotation_err_deg  distance_ratio  true_rotation_deg")
    for f in range(first + args.every, last + 1, args.every):
        t = frame_times[f]
        if t not in est or t not in gt:
            print(f"{f:5d}  (not tracked)")
            continue
        d, r, ratio, rot = compare(est, gt, t0, t)
        print(f"{f:5d}  {d:17.1f}  {r:16.2f}  {ratio:14.3f}  {rot:17.1f}")


if __name__ == "__main__":
    main()
