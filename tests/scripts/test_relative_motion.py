#!/usr/bin/python3
"""scripts/relative_motion.py against a made-up run whose errors are known.

The truth turns 2 deg a frame about y and moves 0.1 along x; the estimate turns 2.5 deg a frame
(0.5 deg of heading error a step) and moves twice as far (a monocular scale of 2).
"""
import math
import os
import subprocess
import sys
import tempfile

SCRIPT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "scripts", "relative_motion.py")
FRAMES = 21


def quat_y(deg):
    """(w, x, y, z) of a rotation about y."""
    h = math.radians(deg) / 2
    return math.cos(h), 0.0, math.sin(h), 0.0


def write_layout(root):
    mav = os.path.join(root, "seq", "mav0")
    os.makedirs(os.path.join(mav, "cam0"))
    os.makedirs(os.path.join(mav, "state_groundtruth_estimate0"))
    run = os.path.join(root, "run")
    os.makedirs(run)
    ns = [1_000_000_000 + 50_000_000 * i for i in range(FRAMES)]
    with open(os.path.join(mav, "cam0", "data.csv"), "w") as f:
        f.write("#timestamp [ns],filename\n")
        f.writelines(f"{t},{t}.png\n" for t in ns)
    with open(os.path.join(mav, "state_groundtruth_estimate0", "data.csv"), "w") as f:
        f.write("#timestamp,p_x,p_y,p_z,q_w,q_x,q_y,q_z\n")
        for i, t in enumerate(ns):
            w, x, y, z = quat_y(2.0 * i)
            f.write(f"{t},{0.1 * i},0,0,{w},{x},{y},{z}\n")
    with open(os.path.join(run, "trajectory.tum"), "w") as f, open(os.path.join(run, "keyframes.tum"), "w") as k:
        for i, t in enumerate(ns):
            w, x, y, z = quat_y(2.5 * i)
            line = f"{t * 1e-9:.6f} {0.2 * i} 0 0 {x} {y} {z} {w}\n"
            f.write(line)
            if i % 5 == 0:
                k.write(line)
    return run, os.path.join(root, "seq")


def run(*args):
    r = subprocess.run([sys.executable, SCRIPT, *args], capture_output=True, text=True)
    return r.returncode, r.stdout, r.stderr


def rows(stdout):
    return [l.split() for l in stdout.splitlines() if l[:1] == " " or l[:1].isdigit()]


def main():
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    with tempfile.TemporaryDirectory() as root:
        run_dir, seq = write_layout(root)
        rc, out, err = run(run_dir, seq, "--steps", "--every", "10")
        check(rc == 0, f"--steps exit {rc}: {err}")
        steps = rows(out)
        check(len(steps) == 2, f"--steps: two windows of 10 frames expected, got {steps}")
        for r in steps:
            check(r[1] == "10", f"--steps: 10 steps a window, got {r}")
            check(abs(float(r[2]) - 0.50) < 0.011, f"--steps: rotation error 0.50 expected, got {r}")
            check(abs(float(r[3]) - 2.00) < 0.011, f"--steps: true rotation 2.00 expected, got {r}")

        rc, out, err = run(run_dir, seq, "--every", "10", "--from", "0")
        check(rc == 0, f"from 0: exit {rc}: {err}")
        since = rows(out)
        check([r[0] for r in since] == ["10", "20"], f"from 0: frames 10 and 20 expected, got {since}")
        for r in since:
            frames = int(r[0])
            check(abs(float(r[2]) - 0.5 * frames) < 0.011, f"from 0: rotation error {0.5 * frames} expected: {r}")
            check(abs(float(r[3]) - 2.0) < 0.001, f"from 0: distance ratio 2 expected: {r}")

        rc, out, err = run(run_dir, seq, "--every", "0")
        check(rc == 2 and "--every must be at least 1" in err, f"--every 0: exit {rc}, {err!r}")
        rc, out, err = run(run_dir, os.path.join(root, "missing"))
        check(rc != 0 and "no such file" in err, f"missing sequence: exit {rc}, {err!r}")

    for f in failures:
        print("FAIL:", f)
    print("relative_motion: %d checks failed" % len(failures) if failures else "relative_motion: all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
