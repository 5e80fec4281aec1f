"""SuperPoint's losses: the detector's 65-class cross-entropy over 8x8 cells (paper eq. 8, masked to valid
cells) and the dense descriptor hinge loss over all pairs of cells of two images related by a homography
(paper eqs. 3-6: positive margin 1, negative margin 0.2, positive weight lambda_d = 250)."""
from dataclasses import dataclass

import torch
import torch.nn.functional as F

CELL = 8


def detector_loss(logits, labels, valid=None):
    """logits [B,65,Hc,Wc], labels int64 [B,Hc,Wc], valid bool [B,Hc,Wc]: mean CE over valid cells."""
    loss = F.cross_entropy(logits, labels, reduction="none")
    if valid is None:
        return loss.mean()
    valid = valid.to(loss.dtype)
    return (loss * valid).sum() / valid.sum().clamp(min=1.0)


@dataclass
class DescriptorLossParams:
    positive_margin: float = 1.0
    negative_margin: float = 0.2
    lambda_d: float = 250.0
    correspondence_radius: float = 7.5   # paper: <= 8 px; 7.5 so that exact grid neighbours (8 px apart) do not pair


def cell_centres(hc, wc, device, dtype=torch.float32):
    ys, xs = torch.meshgrid(torch.arange(hc, device=device, dtype=dtype), torch.arange(wc, device=device, dtype=dtype),
                            indexing="ij")
    return torch.stack([xs * CELL + (CELL - 1) / 2, ys * CELL + (CELL - 1) / 2], dim=-1).reshape(-1, 2)


def correspondences(H, hc, wc, radius):
    """[B, Hc*Wc, Hc*Wc] float: 1 where cell i of image 1, mapped by H (image 1 -> image 2), lands within
    `radius` pixels of the centre of cell j of image 2 (paper eq. 5)."""
    centres = cell_centres(hc, wc, H.device, H.dtype)
    homogeneous = torch.cat([centres, torch.ones_like(centres[:, :1])], dim=1)
    mapped = homogeneous[None] @ H.transpose(1, 2)
    mapped = mapped[..., :2] / mapped[..., 2:3]
    return (torch.cdist(mapped, centres[None].expand(H.shape[0], -1, -1)) <= radius).to(H.dtype)


def descriptor_loss(descriptors1, descriptors2, H, valid2=None, params=DescriptorLossParams()):
    """Raw descriptor maps [B,D,Hc,Wc] of image 1 and image 2 = warp(image 1, H); valid2 bool [B,Hc,Wc]
    marks cells of image 2 that saw image 1. Mean hinge loss over all valid (cell1, cell2) pairs."""
    b, d, hc, wc = descriptors1.shape
    d1 = F.normalize(descriptors1.reshape(b, d, -1), dim=1)
    d2 = F.normalize(descriptors2.reshape(b, d, -1), dim=1)
    dot = d1.transpose(1, 2) @ d2
    s = correspondences(H.to(dot.dtype), hc, wc, params.correspondence_radius)
    loss = params.lambda_d * s * F.relu(params.positive_margin - dot) + (1 - s) * F.relu(dot - params.negative_margin)
    if valid2 is None:
        return loss.mean()
    weight = valid2.reshape(b, 1, -1).to(loss.dtype).expand_as(loss)
    return (loss * weight).sum() / weight.sum().clamp(min=1.0)
