"""Synthetic shapes with exact corner labels (SuperPoint section 4, "Synthetic Shapes").

Each image holds one kind of primitive on a smooth random background: line segments, a polygon,
several polygons, ellipses (distractors: no corners), a star, a checkerboard, stripes, a cube, or pure
noise (no corners). Labels are the unambiguous corners: segment ends, polygon vertices, star centre
and tips, checkerboard / stripe grid points, visible cube vertices. Shapes of one image never overlap,
so no unlabelled junction appears. Rendering is done at twice the output size with anti-aliasing and
reduced by area averaging; labels are carried through the same reduction exactly.
"""
import math

import cv2
import numpy as np

KINDS = ("lines", "polygon", "multiple_polygons", "ellipses", "star", "checkerboard", "stripes", "cube", "noise")
_SHIFT = 4                      # cv2 sub-pixel bits for polygon / line coordinates
_MIN_CONTRAST = 0.25            # minimum grey-level gap between a shape and what surrounds it


def _background(rng, h, w):
    """Smooth random background: a base level, a low-frequency field and heavily blurred blobs."""
    grid = rng.uniform(0, 1, (int(rng.integers(2, 6)), int(rng.integers(2, 6)))).astype(np.float32)
    field = cv2.resize(grid, (w, h), interpolation=cv2.INTER_CUBIC)
    bg = rng.uniform(0, 1) * (1 - 0.5) + 0.5 * field * rng.uniform(0, 1)
    blobs = np.zeros((h, w), np.float32)
    for _ in range(int(rng.integers(0, 12))):
        centre = (int(rng.integers(0, w)), int(rng.integers(0, h)))
        cv2.circle(blobs, centre, int(rng.integers(4, max(5, min(h, w) // 4))), float(rng.uniform(-0.3, 0.3)), -1)
    blobs = cv2.GaussianBlur(blobs, (0, 0), min(h, w) / 12)
    return np.clip(bg + blobs, 0, 1).astype(np.float32)


def _contrasting(rng, *levels, gap=_MIN_CONTRAST):
    """A grey level at least `gap` away from each of `levels` (else the level farthest from them all)."""
    for _ in range(50):
        value = rng.uniform(0, 1)
        if all(abs(value - level) >= gap for level in levels):
            return float(value)
    candidates = np.linspace(0, 1, 21)
    return float(candidates[np.argmax([min(abs(c - level) for level in levels) for c in candidates])])


def _region_level(image, points):
    x0, y0 = np.floor(points.min(axis=0)).astype(int)
    x1, y1 = np.ceil(points.max(axis=0)).astype(int)
    h, w = image.shape
    patch = image[max(y0, 0):min(y1, h - 1) + 1, max(x0, 0):min(x1, w - 1) + 1]
    return float(patch.mean()) if patch.size else float(image.mean())


def _fixed(points):
    return np.round(np.asarray(points) * (1 << _SHIFT)).astype(np.int32)


def _fill_polygon(image, points, level):
    cv2.fillPoly(image, [_fixed(points)], level, cv2.LINE_AA, _SHIFT)


def _draw_segment(image, a, b, level, thickness):
    cv2.line(image, tuple(int(v) for v in _fixed(a)), tuple(int(v) for v in _fixed(b)), level, thickness,
             cv2.LINE_AA, _SHIFT)


def _segments_cross(p1, p2, q1, q2):
    def orient(a, b, c):
        return np.sign((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]))
    return orient(p1, p2, q1) != orient(p1, p2, q2) and orient(q1, q2, p1) != orient(q1, q2, p2)


def _far_from(point, others, distance):
    return all(np.hypot(*(point - o)) >= distance for o in others)


def _random_polygon(rng, centre, radius, min_vertices=3, max_vertices=8):
    """Vertices around `centre` whose corners are all clearly bent (interior angle away from 180 deg)."""
    for _ in range(100):
        n = int(rng.integers(min_vertices, max_vertices + 1))
        angles = np.sort(rng.uniform(0, 2 * math.pi, n))
        if np.min(np.diff(np.append(angles, angles[0] + 2 * math.pi))) < 0.3:
            continue
        radii = radius * rng.uniform(0.5, 1.0, n)
        points = centre + np.stack([radii * np.cos(angles), radii * np.sin(angles)], axis=1)
        edges = np.roll(points, -1, axis=0) - points
        if np.min(np.linalg.norm(edges, axis=1)) < 0.25 * radius:
            continue
        previous = np.roll(edges, 1, axis=0)
        cosines = -np.sum(previous * edges, axis=1) / (np.linalg.norm(previous, axis=1) * np.linalg.norm(edges, axis=1))
        if np.all(cosines > math.cos(math.radians(155))):
            return points
    return None


def _lines(rng, image):
    h, w = image.shape
    size = min(h, w)
    placed, corners = [], []
    for _ in range(int(rng.integers(1, 6))):
        for _ in range(30):
            a = rng.uniform([0, 0], [w - 1, h - 1])
            b = rng.uniform([0, 0], [w - 1, h - 1])
            if np.hypot(*(a - b)) < 0.15 * size or not _far_from(a, corners, 0.08 * size) \
                    or not _far_from(b, corners, 0.08 * size):
                continue
            if any(_segments_cross(a, b, p, q) for p, q in placed):
                continue
            level = _contrasting(rng, _region_level(image, np.stack([a, b])))
            _draw_segment(image, a, b, level, int(rng.integers(1, max(2, int(0.02 * size)) + 1)))
            placed.append((a, b))
            corners += [a, b]
            break
    return corners


def _polygon(rng, image, count):
    h, w = image.shape
    size = min(h, w)
    discs, corners = [], []
    for _ in range(count):
        for _ in range(30):
            radius = rng.uniform(0.1, 0.4 if count == 1 else 0.25) * size
            centre = rng.uniform([radius, radius], [w - 1 - radius, h - 1 - radius])
            if any(np.hypot(*(centre - c)) < radius + r + 0.03 * size for c, r in discs):
                continue
            points = _random_polygon(rng, centre, radius)
            if points is None:
                continue
            _fill_polygon(image, points, _contrasting(rng, _region_level(image, points)))
            discs.append((centre, radius))
            corners += list(points)
            break
    return corners


def _ellipses(rng, image):
    h, w = image.shape
    size = min(h, w)
    discs = []
    for _ in range(int(rng.integers(1, 10))):
        axes = rng.uniform(0.04, 0.25, 2) * size
        radius = float(axes.max())
        centre = rng.uniform([radius, radius], [w - 1 - radius, h - 1 - radius])
        if any(np.hypot(*(centre - c)) < radius + r for c, r in discs):
            continue
        level = _contrasting(rng, _region_level(image, np.stack([centre - radius, centre + radius])))
        cv2.ellipse(image, tuple(int(v) for v in _fixed(centre)), tuple(int(v) for v in _fixed(axes)),
                    float(rng.uniform(0, 180)), 0, 360, level, -1, cv2.LINE_AA, _SHIFT)
        discs.append((centre, radius))
    return []


def _star(rng, image):
    h, w = image.shape
    size = min(h, w)
    radius = rng.uniform(0.15, 0.45) * size
    centre = rng.uniform([radius, radius], [w - 1 - radius, h - 1 - radius])
    for _ in range(50):
        n = int(rng.integers(3, 8))
        angles = np.sort(rng.uniform(0, 2 * math.pi, n))
        if np.min(np.diff(np.append(angles, angles[0] + 2 * math.pi))) > 0.5:
            break
    else:
        return []
    tips = centre + (radius * rng.uniform(0.5, 1.0, n))[:, None] * np.stack([np.cos(angles), np.sin(angles)], 1)
    level = _contrasting(rng, _region_level(image, np.vstack([tips, centre])))
    thickness = int(rng.integers(1, max(2, int(0.02 * size)) + 1))
    for tip in tips:
        _draw_segment(image, centre, tip, level, thickness)
    return [centre] + list(tips)


def _perspective_quad(rng, h, w, aspect):
    """Four corners of a rectangle of the given aspect seen in random perspective, inside the image."""
    size = min(h, w)
    half = np.array([aspect, 1.0]) / max(aspect, 1.0) * rng.uniform(0.25, 0.48) * size
    centre = rng.uniform(half, [w - 1 - half[0], h - 1 - half[1]])
    quad = centre + np.array([[-1, -1], [1, -1], [1, 1], [-1, 1]]) * half
    quad += rng.uniform(-0.25, 0.25, (4, 2)) * half
    angle = rng.uniform(-math.pi, math.pi)
    c, s = math.cos(angle), math.sin(angle)
    return centre + (quad - centre) @ np.array([[c, s], [-s, c]])


def _grid(rng, image, rows, cols):
    """A rows x cols board of alternating dark / bright cells in perspective; corners at all grid points."""
    h, w = image.shape
    quad = _perspective_quad(rng, h, w, cols / rows)
    unit = np.array([[0, 0], [cols, 0], [cols, rows], [0, rows]], np.float32)
    H = cv2.getPerspectiveTransform(unit, quad.astype(np.float32))
    gx, gy = np.meshgrid(np.arange(cols + 1), np.arange(rows + 1))
    grid = cv2.perspectiveTransform(np.stack([gx, gy], -1).reshape(-1, 1, 2).astype(np.float64), H).reshape(rows + 1, cols + 1, 2)
    background = _region_level(image, quad)
    dark = _contrasting(rng, background)
    bright = _contrasting(rng, background, dark)
    for i in range(rows):
        for j in range(cols):
            cell = np.array([grid[i, j], grid[i, j + 1], grid[i + 1, j + 1], grid[i + 1, j]])
            _fill_polygon(image, cell, dark if (i + j) % 2 else bright)
    return list(grid.reshape(-1, 2))


def _cube(rng, image):
    """A cube in perspective; visible faces shaded differently; labels at the vertices of visible faces."""
    h, w = image.shape
    size = min(h, w)
    vertices = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], np.float64)
    vertices *= rng.uniform(0.5, 1.5, 3)
    faces = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    rotation, _ = cv2.Rodrigues(rng.normal(0, 1, 3))
    camera = vertices @ rotation.T + [0, 0, rng.uniform(4, 9)]
    projected = camera[:, :2] / camera[:, 2:3]
    extent = (projected.max(axis=0) - projected.min(axis=0)).max()
    projected = (projected - projected.min(axis=0)) * rng.uniform(0.3, 0.7) * size / extent
    projected += rng.uniform([0, 0], np.maximum([w - 1, h - 1] - projected.max(axis=0), 1e-3))
    visible = []
    for face in faces:
        quad = camera[list(face)]
        normal = np.cross(quad[1] - quad[0], quad[3] - quad[0])
        if np.dot(normal, quad.mean(axis=0) - camera.mean(axis=0)) < 0:
            normal = -normal
        if np.dot(normal, quad.mean(axis=0)) < -1e-3 * np.linalg.norm(normal) * np.linalg.norm(quad.mean(axis=0)):
            visible.append(face)
    background = _region_level(image, projected)
    shades = []
    for face in visible:
        shade = _contrasting(rng, background, *shades, gap=0.15)
        for _ in range(20):
            if abs(shade - background) >= _MIN_CONTRAST:
                break
            shade = _contrasting(rng, background, *shades, gap=0.15)
        shades.append(shade)
        _fill_polygon(image, projected[list(face)], shade)
    return list(projected[sorted({v for face in visible for v in face})])


def render(rng, height, width, kind=None):
    """One synthetic image: (float32 [height,width] in [0,1], float32 [N,2] corner xy in that image)."""
    kind = kind or KINDS[int(rng.integers(len(KINDS)))]
    h2, w2 = 2 * height, 2 * width
    canvas = _background(rng, h2, w2)
    if kind == "lines":
        corners = _lines(rng, canvas)
    elif kind == "polygon":
        corners = _polygon(rng, canvas, 1)
    elif kind == "multiple_polygons":
        corners = _polygon(rng, canvas, int(rng.integers(2, 5)))
    elif kind == "ellipses":
        corners = _ellipses(rng, canvas)
    elif kind == "star":
        corners = _star(rng, canvas)
    elif kind == "checkerboard":
        corners = _grid(rng, canvas, int(rng.integers(2, 7)), int(rng.integers(2, 7)))
    elif kind == "stripes":
        corners = _grid(rng, canvas, 1, int(rng.integers(3, 10)))
    elif kind == "cube":
        corners = _cube(rng, canvas)
    elif kind == "noise":
        canvas = np.clip(canvas + rng.normal(0, rng.uniform(0.05, 0.3), canvas.shape), 0, 1).astype(np.float32)
        corners = []
    else:
        raise ValueError(f"unknown synthetic shape kind {kind!r}")
    image = cv2.resize(canvas, (width, height), interpolation=cv2.INTER_AREA)
    points = (np.asarray(corners, np.float64).reshape(-1, 2) + 0.5) / 2.0 - 0.5
    keep = (points[:, 0] >= 0) & (points[:, 0] <= width - 1) & (points[:, 1] >= 0) & (points[:, 1] <= height - 1)
    return image.astype(np.float32), points[keep].astype(np.float32)
