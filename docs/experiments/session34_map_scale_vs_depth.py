#!/usr/bin/python3
"""Map scale against the rendered depth, keyframe by keyframe (session 34, docs/vo.md).

  git apply docs/experiments/session34_map_scale_log.patch   # logging only, PLLVO_DIAG
  pllvo synth --preset medium_lowlight --stereo --duration 10 --depth --out D   # same images + depth
  PLLVO_DIAG=1 pllvo run D --mono --single-thread --first 0 --out O 2> LOG
  /usr/bin/python3 docs/experiments/session34_map_scale_vs_depth.py LOG D FIRST_FRAME LAST_FRAME

Per keyframe: median z_est / z_true of the map points it sees before its BA (pre), of the points it
makes (new) and of its points after the BA (post), and new / pre. z_true is the depth image at the
feature's raw pixel (the working view of a monocular run has the calibration's K; the pixel is
distorted back with its radial-tangential model); points on a depth edge (>10 % over 3x3) are left
out. The camera constants below are the synthetic suite's cam0. numpy only (a 16-bit PNG reader).
"""
import sys, zlib, struct, os, numpy as np
log, seqdir = sys.argv[1], sys.argv[2]
fx, fy, cx, cy = 458.654, 457.296, 367.215, 248.375
k1, k2, p1, p2 = -0.28340811, 0.07395907, 0.00019359, 1.76187114e-05
def read_png16(path):
    data = open(path, 'rb').read(); pos = 8; idat = b''
    while pos < len(data):
        n, = struct.unpack('>I', data[pos:pos+4]); t = data[pos+4:pos+8]; c = data[pos+8:pos+8+n]; pos += 12 + n
        if t == b'IHDR': w, h, bd, ct = struct.unpack('>IIBB', c[:10])
        elif t == b'IDAT': idat += c
    raw = zlib.decompress(idat); bpp = 2; stride = w * bpp
    out = np.zeros((h, stride), np.uint8); prev = np.zeros(stride, np.int32); i = 0
    for y in range(h):
        f = raw[i]; line = np.frombuffer(raw[i+1:i+1+stride], np.uint8).astype(np.int32); i += 1 + stride
        if f == 0: cur = line
        elif f == 2: cur = (line + prev) & 255
        else:
            cur = np.zeros(stride, np.int32)
            for x in range(stride):
                a = cur[x-bpp] if x >= bpp else 0; b = prev[x]; cc = prev[x-bpp] if x >= bpp else 0
                if f == 1: p = a
                elif f == 3: p = (a + b) // 2
                else:
                    pa, pb, pc = abs(b - cc), abs(a - cc), abs(a + b - 2*cc)
                    p = a if pa <= pb and pa <= pc else (b if pb <= pc else cc)
                cur[x] = (line[x] + p) & 255
        out[y] = cur; prev = cur
    return (out[:, 0::2].astype(np.uint16) << 8 | out[:, 1::2]).astype(np.float64) / 1000.0
files = sorted(os.listdir(seqdir + '/mav0/cam0/depth'))
cache = {}
def depth(f):
    if f not in cache: cache[f] = read_png16(seqdir + '/mav0/cam0/depth/' + files[f])
    return cache[f]
def raw_px(u, v):
    x, y = (u - cx) / fx, (v - cy) / fy; r2 = x*x + y*y; rad = 1 + k1*r2 + k2*r2*r2
    xd = x*rad + 2*p1*x*y + p2*(r2 + 2*x*x); yd = y*rad + p1*(r2 + 2*y*y) + 2*p2*x*y
    return fx*xd + cx, fy*yd + cy
rec = {}
for l in open(log):
    if not l[:3] in ('NEW', 'OLD'): continue
    t, f, u, v, z = l.split(); f = int(f); u, v, z = float(u), float(v), float(z)
    rec.setdefault((t, f), []).append((u, v, z))
frames = sorted(set(f for _, f in rec))
lo, hi = int(sys.argv[3]), int(sys.argv[4])
print(" frame   pre(n)        new(n)        post(n)    new/pre")
for f in frames:
    if not lo <= f <= hi: continue
    D = depth(f); row = []
    med = {}
    for t in ('OLDPRE', 'NEWPT', 'OLDPOST'):
        r = []
        for u, v, z in rec.get((t, f), []):
            ru, rv = raw_px(u, v); iu, iv = int(round(ru)), int(round(rv))
            if not (1 <= iu < D.shape[1]-1 and 1 <= iv < D.shape[0]-1): continue
            nb = D[iv-1:iv+2, iu-1:iu+2]
            if nb.min() <= 0 or nb.max() > 1.1 * nb.min(): continue
            if z > 0: r.append(z / D[iv, iu])
        med[t] = np.median(r) if r else float('nan')
        row.append(f"{med[t]:6.3f}({len(r):3d})")
    print(f"{f:5d}  " + "  ".join(row) + f"   {med['NEWPT']/med['OLDPRE']:.3f}")
