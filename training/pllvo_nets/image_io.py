"""Reading the 8-bit grayscale PNG fixtures without PIL (OpenCV's bindings when present)."""
import numpy as np


def read_png(path):
    """8-bit grayscale PNG -> uint8 [H, W]: OpenCV when its Python bindings are installed,
    else a small decoder (the fixtures are non-interlaced grayscale; slower, same pixels)."""
    try:
        import cv2

        return cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    except ImportError:
        pass
    import struct
    import zlib

    data = open(path, "rb").read()
    pos, chunks, width, height = 8, [], 0, 0
    while pos < len(data):
        (length,) = struct.unpack(">I", data[pos : pos + 4])
        kind = data[pos + 4 : pos + 8]
        body = data[pos + 8 : pos + 8 + length]
        if kind == b"IHDR":
            width, height, depth, colour, _, _, interlace = struct.unpack(">IIBBBBB", body)
            assert depth == 8 and colour == 0 and interlace == 0, "8-bit grayscale PNG expected"
        elif kind == b"IDAT":
            chunks.append(body)
        pos += 12 + length
    raw = np.frombuffer(zlib.decompress(b"".join(chunks)), dtype=np.uint8).reshape(height, width + 1)
    out = np.zeros((height, width), dtype=np.int32)
    prev = np.zeros(width, dtype=np.int32)
    for y in range(height):
        f, line = raw[y, 0], raw[y, 1:].astype(np.int32)
        if f in (0, 1, 2):  # None, Sub, Up: vectorised
            row = (np.cumsum(line) if f == 1 else line + (prev if f == 2 else 0)) & 0xFF
            out[y], prev = row, row
            continue
        row = np.zeros(width, dtype=np.int32)
        for x in range(width):
            a = row[x - 1] if x else 0
            b = prev[x]
            c = prev[x - 1] if x else 0
            if f == 0:
                pred = 0
            elif f == 1:
                pred = a
            elif f == 2:
                pred = b
            elif f == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            row[x] = (line[x] + pred) & 0xFF
        out[y], prev = row, row
    return out.astype(np.uint8)
