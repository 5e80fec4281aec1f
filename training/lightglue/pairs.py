"""Training and evaluation pairs for LightGlue, each with its exact dense correspondence.

A pair is (image0, image1, warp01, warp10): warpAB [H,W,2] gives, for every pixel of image A, where that
scene point is in image B (NaN where it is not visible there). Ground-truth matches of any keypoints
follow from it (losses.py), so both kinds of pair look the same to the training loop:

* homography pairs (LightGlue's pre-training): a crop of a real image and a copy warped by a random
  homography, each with its own photometric change (brightness, contrast, gamma, noise, blur, darkening);
* synthetic pairs: two frames of a `pllvo synth --depth` sequence (packed by training/make_data_pack.py)
  a few frames apart; the depth and the true poses give the correspondence, and a depth test against
  the other frame's depth marks occluded points as unmatchable. The lighting is the sequence's own
  (low light, flicker, exposure jumps), which is where PLL-VO must be strong.
"""
import json
from pathlib import Path

import cv2
import numpy as np

from superpoint import data_sources, photometric
from superpoint.homographies import sample_homography, warp_image


def homography_warp(H, height, width):
    """[H,W,2] pixel -> pixel under H (NaN outside the target image)."""
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    points = np.stack([xs, ys, np.ones_like(xs)], -1) @ H.T
    mapped = points[..., :2] / points[..., 2:3]
    outside = ((mapped[..., 0] < 0) | (mapped[..., 0] > width - 1) | (mapped[..., 1] < 0) | (mapped[..., 1] > height - 1))
    mapped[outside] = np.nan
    return mapped.astype(np.float32)


class HomographyPairs:
    def __init__(self, data_config, height, width, homography, photometric_params, seed=0, items=None):
        self.items = items if items is not None else data_sources.make_items(data_config, height, width, seed)
        if not self.items:
            raise FileNotFoundError("no training images found (../shared/data, photographs, --synth-dir)")
        self.height, self.width = height, width
        self.homography, self.photometric = homography, photometric_params
        self.cache = {}

    def image(self, index):
        if index not in self.cache:
            image = data_sources.load_item(self.items[index], self.height, self.width)
            self.cache[index] = np.round(image * 255).astype(np.uint8)
        return self.cache[index].astype(np.float32) / 255

    def sample(self, rng, index=None):
        """(image0, image1, H): a crop and its warped copy, each photometrically changed."""
        index = int(rng.integers(len(self.items))) if index is None else index
        image = self.image(index)
        H = sample_homography(rng, self.height, self.width, self.homography)
        warped, valid = warp_image(image, H)
        image0 = photometric.augment(image, rng, self.photometric)
        image1 = photometric.augment(warped, rng, self.photometric) * valid
        return image0, image1, H

    def pair(self, rng, index=None):
        image0, image1, H = self.sample(rng, index)
        return image0, image1, homography_warp(H, self.height, self.width), \
            homography_warp(np.linalg.inv(H), self.height, self.width)


class SynthSequence:
    """One packed `pllvo synth` sequence: frames, depth (metres), K, T_world_cam."""

    def __init__(self, folder):
        self.folder = Path(folder)
        meta_path = self.folder / "meta.json"
        if not meta_path.is_file():
            raise FileNotFoundError(f"{meta_path}: missing (make it with training/make_data_pack.py)")
        meta = json.loads(meta_path.read_text())
        fx, fy, cx, cy = meta["K"]
        self.K = np.array([[fx, 0, cx], [0, fy, cy], [0, 0, 1]])
        self.unit = meta["depth_unit_m"]
        self.stamps = [f["stamp"] for f in meta["frames"]]
        self.poses = [np.array(f["T_world_cam"]).reshape(4, 4) for f in meta["frames"]]

    def image(self, i):
        path = self.folder / "frames" / f"{self.stamps[i]}.png"
        image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
        if image is None:
            raise FileNotFoundError(f"{path}: cannot read")
        return image.astype(np.float32) / 255

    def depth(self, i):
        path = self.folder / "depth" / f"{self.stamps[i]}.png"
        depth = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
        if depth is None:
            raise FileNotFoundError(f"{path}: cannot read")
        return depth.astype(np.float32) * self.unit

    def T_b_a(self, a, b):
        return np.linalg.inv(self.poses[b]) @ self.poses[a]


def depth_warp(depth_a, depth_b, K, T_b_a, relative_tolerance=0.03):
    """[H,W,2] pixel of A -> pixel of B through A's depth and the relative pose; NaN where A has no
    depth, the point falls outside B or behind its camera, or B's depth there says it is occluded."""
    height, width = depth_a.shape
    ys, xs = np.mgrid[0:height, 0:width].astype(np.float64)
    z = depth_a.astype(np.float64)
    rays = np.stack([(xs - K[0, 2]) / K[0, 0], (ys - K[1, 2]) / K[1, 1], np.ones_like(xs)], -1)
    points_b = (rays * z[..., None]) @ T_b_a[:3, :3].T + T_b_a[:3, 3]
    zb = points_b[..., 2]
    with np.errstate(divide="ignore", invalid="ignore"):
        u = K[0, 0] * points_b[..., 0] / zb + K[0, 2]
        v = K[1, 1] * points_b[..., 1] / zb + K[1, 2]
    ok = (z > 0) & (zb > 0.05) & (u >= 0) & (u <= width - 1) & (v >= 0) & (v <= height - 1)
    ui, vi = np.clip(np.round(u), 0, width - 1).astype(int), np.clip(np.round(v), 0, height - 1).astype(int)
    seen = depth_b[np.where(ok, vi, 0), np.where(ok, ui, 0)]
    ok &= (seen > 0) & (np.abs(seen - zb) <= relative_tolerance * zb)
    mapped = np.stack([u, v], -1)
    mapped[~ok] = np.nan
    return mapped.astype(np.float32)


class SynthPairs:
    def __init__(self, folders, max_gap, photometric_params=None):
        self.sequences = [SynthSequence(f) for f in folders]
        self.sequences = [s for s in self.sequences if len(s.stamps) > max_gap]
        if not self.sequences:
            raise FileNotFoundError("no packed synthetic sequences with enough frames")
        self.max_gap = max_gap
        self.photometric = photometric_params

    def pair(self, rng, choice=None):
        """choice (sequence index, frame a, frame b) for a fixed evaluation pair; else random."""
        if choice is None:
            s = int(rng.integers(len(self.sequences)))
            seq = self.sequences[s]
            gap = int(rng.integers(1, self.max_gap + 1))
            a = int(rng.integers(len(seq.stamps) - gap))
            b = a + gap
            if rng.random() < 0.5:
                a, b = b, a
        else:
            s, a, b = choice
            seq = self.sequences[s]
        image0, image1 = seq.image(a), seq.image(b)
        if self.photometric is not None:   # mild: the rendered lighting is the point of these pairs
            image0 = photometric.augment(image0, rng, self.photometric)
            image1 = photometric.augment(image1, rng, self.photometric)
        d0, d1 = seq.depth(a), seq.depth(b)
        return image0, image1, depth_warp(d0, d1, seq.K, seq.T_b_a(a, b)), depth_warp(d1, d0, seq.K, seq.T_b_a(b, a))

    def relative_pose(self, choice):
        s, a, b = choice
        return self.sequences[s].K, self.sequences[s].T_b_a(a, b)
