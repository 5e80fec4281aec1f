#!/usr/bin/python3
"""Tracked steps and new points against the map's own scale, stretch by stretch (session 34).

  /usr/bin/python3 docs/experiments/session34_steps_vs_map.py RUN/trajectory.tum TRUTH_CSV MAP_SCALE_TXT [W]

MAP_SCALE_TXT is the output of session34_map_scale_vs_depth.py for the same run. Per stretch: the
median over i of |p_est(i + W) - p_est(i)| / |p_true(i + W) - p_true(i)| (default W = 5) divided by
the median map scale of its keyframes (1: the poses move as far as the map they are tracked in says),
and the new points' scale over the map's (weighted geometric mean over keyframes with >= 3). numpy only.
"""
import re
import sys
import numpy as np


def positions(path, sep, to_s):
    out = {}
    for line in open(path):
        if line.startswith("#") or not line.strip():
            continue
        v = line.strip().split(sep)
        out[round(float(v[0]) * to_s, 3)] = np.array([float(x) for x in v[1:4]])
    return out


def main():
    est = positions(sys.argv[1], None, 1.0)
    truth = positions(sys.argv[2], ",", 1e-9)
    w = int(sys.argv[4]) if len(sys.argv) > 4 else 5
    pre, new = {}, {}
    for line in open(sys.argv[3]):
        m = re.match(r"\s*(\d+)\s+([\d.]+)\(\s*\d+\)\s+([\d.na]+)\(\s*(\d+)\)", line)
        if m:
            pre[int(m[1])] = float(m[2])
            new[int(m[1])] = (float(m[3]), int(m[4]))
    ts = sorted(t for t in est if t in truth)
    for lo, hi in [(14, 34), (34, 46), (46, 56), (56, 100), (100, 140), (140, 200)]:
        chords = [np.linalg.norm(est[ts[i + w]] - est[ts[i]]) / np.linalg.norm(truth[ts[i + w]] - truth[ts[i]])
                  for i in range(lo, min(hi, len(ts) - w))]
        maps = [pre[k] for k in pre if lo <= k < hi]
        joined = [(new[k][0] / pre[k], new[k][1]) for k in new if lo <= k < hi and new[k][1] >= 3 and new[k][0] == new[k][0]]
        if not chords or not maps:
            continue
        weight = sum(n for _, n in joined)
        ratio = np.exp(sum(n * np.log(r) for r, n in joined) / weight) if weight else float("nan")
        print(f"frames {lo:3d}-{hi:3d}: map scale {min(maps):.2f}-{max(maps):.2f}, steps / map {np.median(chords) / np.median(maps):.3f}, "
              f"new points / map {ratio:.3f}")


if __name__ == "__main__":
    main()
