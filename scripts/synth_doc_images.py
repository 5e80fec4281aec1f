#!/usr/bin/env python3
"""Renders the example frames of docs/synth.md with `pllvo synth` (standard library only).

    python3 scripts/synth_doc_images.py [--pllvo build/bin/pllvo] [--out docs/images/synth]

Each image comes from a preset rendered for a few seconds; frames are shrunk (2x2 box
filter) or cropped and joined side by side so the docs stay small.
"""
import argparse
import os
import shutil
import struct
import subprocess
import tempfile
import zlib


def read_png_gray(path):
    """8-bit grayscale, non-interlaced PNG (what OpenCV writes) -> (width, height, rows)."""
    data = open(path, "rb").read()
    assert data[:8] == b"\x89PNG\r\n\x1a\n", path
    pos, idat, width, height = 8, b"", 0, 0
    while pos < len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, color, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and color == 0 and interlace == 0, "expected 8-bit gray"
        elif kind == b"IDAT":
            idat += body
        pos += 12 + length
    raw = zlib.decompress(idat)
    rows, prev = [], bytearray(width)
    for y in range(height):
        f = raw[y * (width + 1)]
        line = bytearray(raw[y * (width + 1) + 1:(y + 1) * (width + 1)])
        for x in range(width):
            a = line[x - 1] if x else 0
            b = prev[x]
            c = prev[x - 1] if x else 0
            if f == 1:
                line[x] = (line[x] + a) & 255
            elif f == 2:
                line[x] = (line[x] + b) & 255
            elif f == 3:
                line[x] = (line[x] + (a + b) // 2) & 255
            elif f == 4:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
                line[x] = (line[x] + pred) & 255
        rows.append(line)
        prev = line
    return width, height, rows


def write_png_gray(path, rows):
    width, height = len(rows[0]), len(rows)
    raw = b"".join(b"\x00" + bytes(r) for r in rows)

    def chunk(kind, body):
        return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body) & 0xFFFFFFFF)

    png = b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
    png += chunk(b"IDAT", zlib.compress(raw, 9)) + chunk(b"IEND", b"")
    open(path, "wb").write(png)


def shrink(rows, factor):
    h, w = len(rows) // factor, len(rows[0]) // factor
    out = []
    for y in range(h):
        line = bytearray(w)
        for x in range(w):
            s = sum(rows[y * factor + dy][x * factor + dx] for dy in range(factor) for dx in range(factor))
            line[x] = (s + factor * factor // 2) // (factor * factor)
        out.append(line)
    return out


def crop(rows, x, y, w, h):
    return [bytearray(r[x:x + w]) for r in rows[y:y + h]]


def side_by_side(images, gap=4):
    h = len(images[0])
    return [bytearray(b"\xff" * gap).join(img[y] for img in images) for y in range(h)]


def frames(pllvo, work, preset, indices, duration=None, rate=20):
    """Frames `indices` of `preset`, rendered for `duration` s (default: up to the last one)."""
    duration = duration if duration is not None else max(indices) / rate
    out = os.path.join(work, f"{preset}_{duration:.3f}")
    if not os.path.exists(out):
        subprocess.run([pllvo, "synth", "--preset", preset, "--duration", f"{duration:.3f}", "--out", out],
                       check=True, stdout=subprocess.DEVNULL)
    names = sorted(os.listdir(os.path.join(out, "mav0", "cam0", "data")))
    return [read_png_gray(os.path.join(out, "mav0", "cam0", "data", names[i]))[2] for i in indices]


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--pllvo", default="build/bin/pllvo")
    ap.add_argument("--out", default="docs/images/synth")
    args = ap.parse_args()
    os.makedirs(args.out, exist_ok=True)
    work = tempfile.mkdtemp(prefix="pllvo_synth_docs_")
    try:
        save = lambda name, rows: write_png_gray(os.path.join(args.out, name), rows)
        one = lambda preset, i: frames(args.pllvo, work, preset, [i])[0]
        save("normal.png", shrink(one("medium_normal", 100), 2))
        save("lowlight.png", shrink(one("medium_lowlight", 100), 2))
        save("corridor.png", shrink(one("corridor_medium_normal", 200), 2))
        save("lowtexture.png", shrink(one("medium_lowtexture", 150), 2))
        save("flicker.png", side_by_side([shrink(f, 4) for f in frames(args.pllvo, work, "easy_flicker", [40, 41, 42, 43])]))
        # Motion blur: difficult flight after the lights went off (15 ms exposure, gain 4.5).
        save("blur.png", crop(frames(args.pllvo, work, "difficult_lightoff", [440], duration=30)[0], 0, 240, 376, 240))
        # Lights off at 15 s (frame 300) of the 30 s preset: before, just after, adapting, adapted.
        lightoff = frames(args.pllvo, work, "medium_lightoff", [296, 302, 330, 420], duration=30)
        save("lightoff.png", side_by_side([shrink(f, 4) for f in lightoff]))
    finally:
        shutil.rmtree(work)


if __name__ == "__main__":
    main()
