"""Random homographies (SuperPoint's recipe: a centred patch perturbed by perspective, scaling, rotation
and translation, stretched onto the whole image) and warping of images, masks and points.

Convention: H maps pixel coordinates of the source image to the warped image (x_w ~ H x_s), pixel
centres at integer coordinates; the warped image is I_w(x) = I_s(H^-1 x), same size as the source.
"""
import math
from dataclasses import dataclass

import cv2
import numpy as np
import torch
import torch.nn.functional as F


@dataclass
class HomographyParams:
    patch_ratio: float = 0.85      # side of the source patch relative to the image before perturbation
    perspective: float = 0.2       # corner displacement, fraction of the patch side
    scaling: float = 0.2           # scale ~ N(1, scaling/2) clipped to [1-scaling, 1+scaling]
    max_angle: float = math.pi / 4  # rotation ~ U(-max_angle, max_angle)
    translation: bool = True
    allow_artifacts: bool = True   # let the patch leave the image (black borders in the warped image)


def sample_homography(rng, height, width, params=HomographyParams()):
    """3x3 float64 H (source -> warped) for an image of the given size."""
    w, h = width - 1.0, height - 1.0
    margin = (1.0 - params.patch_ratio) / 2.0
    patch = np.array([[margin, margin], [1 - margin, margin], [1 - margin, 1 - margin], [margin, 1 - margin]])
    if params.perspective > 0:
        amplitude = params.perspective * params.patch_ratio / 2.0
        if not params.allow_artifacts:
            amplitude = min(amplitude, margin)
        patch = patch + rng.uniform(-amplitude, amplitude, size=(4, 2))
    patch = patch * [w, h]
    centre = patch.mean(axis=0)
    if params.scaling > 0:
        scale = float(np.clip(rng.normal(1.0, params.scaling / 2.0), 1 - params.scaling, 1 + params.scaling))
        patch = centre + (patch - centre) * scale
    if params.max_angle > 0:
        angle = rng.uniform(-params.max_angle, params.max_angle)
        c, s = math.cos(angle), math.sin(angle)
        patch = centre + (patch - centre) @ np.array([[c, s], [-s, c]])
    if params.translation:
        low, high = -patch.min(axis=0), np.array([w, h]) - patch.max(axis=0)
        if params.allow_artifacts:
            slack = margin * np.array([w, h])
            low, high = np.minimum(low, 0) - slack, np.maximum(high, 0) + slack
        patch = patch + rng.uniform(np.minimum(low, high), np.maximum(low, high))
    target = np.array([[0, 0], [w, 0], [w, h], [0, h]], dtype=np.float64)
    return cv2.getPerspectiveTransform(patch.astype(np.float32), target.astype(np.float32)).astype(np.float64)


def warp_points(points, H):
    """[N,2] xy -> [N,2] xy under H."""
    points = np.asarray(points, dtype=np.float64).reshape(-1, 2)
    homogeneous = np.concatenate([points, np.ones((len(points), 1))], axis=1) @ H.T
    return homogeneous[:, :2] / homogeneous[:, 2:3]


def inside(points, height, width, border=0.0):
    return ((points[:, 0] >= border) & (points[:, 0] <= width - 1 - border) &
            (points[:, 1] >= border) & (points[:, 1] <= height - 1 - border))


def warp_image(image, H, erosion=2):
    """Warps an [H,W] float image; returns (warped, valid) where valid marks pixels that saw the source,
    eroded by `erosion` pixels so that border interpolation artefacts are not trusted."""
    height, width = image.shape
    warped = cv2.warpPerspective(image, H, (width, height), flags=cv2.INTER_LINEAR,
                                 borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    valid = cv2.warpPerspective(np.ones_like(image, dtype=np.uint8), H, (width, height),
                                flags=cv2.INTER_NEAREST, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
    if erosion > 0:
        valid = cv2.erode(valid, np.ones((2 * erosion + 1, 2 * erosion + 1), np.uint8))
    return warped, valid.astype(bool)


def warp_batch(images, H, mode="bilinear"):
    """Torch version for batches: images [N,C,H,W], H [N,3,3] (source -> warped); zeros outside."""
    n, _, height, width = images.shape
    ys, xs = torch.meshgrid(torch.arange(height, dtype=images.dtype, device=images.device),
                            torch.arange(width, dtype=images.dtype, device=images.device), indexing="ij")
    target = torch.stack([xs, ys, torch.ones_like(xs)], dim=-1).reshape(1, -1, 3)
    source = target @ torch.linalg.inv(H).to(images.dtype).transpose(1, 2)
    source = source[..., :2] / source[..., 2:3]
    grid = torch.stack([2 * source[..., 0] / (width - 1) - 1, 2 * source[..., 1] / (height - 1) - 1], dim=-1)
    return F.grid_sample(images, grid.reshape(n, height, width, 2), mode=mode, align_corners=True,
                         padding_mode="zeros")
