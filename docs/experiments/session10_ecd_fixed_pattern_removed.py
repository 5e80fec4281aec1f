#!/usr/bin/python3
"""ECD slider_hdr_close: does removing the sensor's fixed pattern leave corners to follow?

Session 10 measurement (docs/vo.md). The fixed pattern is estimated offline (an upper bound for
any online estimate) as the mean over frames 60-148 of each frame's high-pass (frame minus its
Gaussian blur, sigma 3 px): the scene moves ~9.5 px per frame, so it averages out and the static
pattern stays. Each frame has it subtracted, then session 9's census runs (400 Shi-Tomasi
corners, three frames of pyramidal LK, 1 px forward-backward check, NCC >= 0.75): printed per start
frame: corners, survivors, survivors that moved > 10 px, their median motion; for the raw frames
and the cleaned ones. Needs python3-opencv (a one-off tool, not a project dependency).
Run: /usr/bin/python3 docs/experiments/session10_ecd_fixed_pattern_removed.py [ECD_FOLDER]
"""
import sys
import cv2
import numpy as np

D = (sys.argv[1] if len(sys.argv) > 1 else '../shared/data/ecd_slider_hdr_close_149') + '/images/'
raw = [cv2.imread(D + 'frame_%08d.png' % i, 0).astype(np.float32) for i in range(149)]
def high_pass(im): return im - cv2.GaussianBlur(im, (0, 0), 3)
pattern = np.mean([high_pass(raw[i]) for i in range(60, 149)], axis=0)

def frame(i, clean):
    im = raw[i] - pattern if clean else raw[i]
    return np.clip(cv2.GaussianBlur(im, (0, 0), 1.0), 0, 255).astype(np.uint8)

def ncc(a, pa, b, pb, s=21):
    A = cv2.getRectSubPix(a, (s, s), tuple(map(float, pa))).astype(np.float32)
    B = cv2.getRectSubPix(b, (s, s), tuple(map(float, pb))).astype(np.float32)
    A -= A.mean(); B -= B.mean(); d = np.sqrt((A * A).sum() * (B * B).sum())
    return (A * B).sum() / d if d > 0 else 0

def census(start, clean):
    ims = [frame(start + k, clean) for k in range(4)]
    pts = cv2.goodFeaturesToTrack(ims[0], 400, 0.001, 6, blockSize=5).reshape(-1, 2)
    alive = np.ones(len(pts), bool); cur = pts.copy()
    for k in range(3):
        p, st, _ = cv2.calcOpticalFlowPyrLK(ims[k], ims[k + 1], cur.reshape(-1, 1, 2), None, winSize=(21, 21), maxLevel=3)
        q, st2, _ = cv2.calcOpticalFlowPyrLK(ims[k + 1], ims[k], p, None, winSize=(21, 21), maxLevel=3)
        p = p.reshape(-1, 2); q = q.reshape(-1, 2)
        ok = (st.ravel() == 1) & (st2.ravel() == 1) & (np.linalg.norm(q - cur, axis=1) < 1)
        ok &= np.array([ok[i] and ncc(ims[k], cur[i], ims[k + 1], p[i]) > 0.75 for i in range(len(p))])
        alive &= ok; cur = p
    moved = alive & (np.linalg.norm(cur - pts, axis=1) > 10)
    return len(pts), alive.sum(), moved.sum()

print('start  raw: corners survivors moved   pattern removed: corners survivors moved')
for start in range(62, 146, 6):
    print(start, *census(start, False), ' ', *census(start, True))
