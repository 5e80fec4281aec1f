"""Keypoint lists -> SuperPoint's 65-class cell labels, and pixel masks -> cell masks.

A cell's label is the position (dy * 8 + dx) of one of its keypoints, or 64 (dustbin) when it has none.
When several keypoints fall into one cell, one of them is drawn at random, as in SuperPoint.
"""
import numpy as np

CELL = 8
DUSTBIN = CELL * CELL


def cell_labels(points, height, width, rng):
    """points [N,2] xy float (pixel centres at integers) -> int64 [H/8, W/8] labels in 0..64."""
    hc, wc = height // CELL, width // CELL
    labels = np.full(hc * wc, DUSTBIN, np.int64)
    pixels = np.round(np.asarray(points, np.float64).reshape(-1, 2)).astype(np.int64)
    keep = (pixels[:, 0] >= 0) & (pixels[:, 0] < wc * CELL) & (pixels[:, 1] >= 0) & (pixels[:, 1] < hc * CELL)
    pixels = pixels[keep]
    if len(pixels) == 0:
        return labels.reshape(hc, wc)
    pixels = pixels[rng.permutation(len(pixels))]
    cells = (pixels[:, 1] // CELL) * wc + pixels[:, 0] // CELL
    cells, first = np.unique(cells, return_index=True)
    chosen = pixels[first]
    labels[cells] = (chosen[:, 1] % CELL) * CELL + chosen[:, 0] % CELL
    return labels.reshape(hc, wc)


def cell_mask(pixel_mask):
    """bool [H,W] -> bool [H/8, W/8]: a cell counts only when all of its pixels are valid."""
    h, w = pixel_mask.shape
    hc, wc = h // CELL, w // CELL
    return pixel_mask[:hc * CELL, :wc * CELL].reshape(hc, CELL, wc, CELL).all(axis=(1, 3))
