"""Turns SuperPoint's raw outputs into keypoints and descriptors (the official post-processing:
softmax over 65 channels, dustbin dropped, depth-to-space, NMS, threshold, border, top-k, bilinear
descriptor sampling with L2 normalisation)."""
import torch
import torch.nn.functional as F

CELL = 8


def heatmap_from_logits(logits):
    """[B,65,Hc,Wc] logits -> [B,H,W] corner probability; channel c is pixel (c // 8, c % 8) of its cell."""
    prob = torch.softmax(logits, dim=1)[:, :-1]
    return F.pixel_shuffle(prob, CELL)[:, 0]


def _window_max(values, radius):
    return F.max_pool2d(values[:, None], 2 * radius + 1, stride=1, padding=radius)[:, 0]


def nms(heatmap, radius):
    """Keeps the local maxima of a [B,H,W] map over a (2r+1)^2 window, zeroes the rest. As in the official
    post-processing, a point whose window maximum was itself suppressed by a stronger neighbour gets a
    second chance (two rounds), so that suppression does not cascade."""
    if radius <= 0:
        return heatmap
    keep = heatmap == _window_max(heatmap, radius)
    for _ in range(2):
        covered = _window_max(keep.float(), radius) > 0
        remaining = torch.where(covered, torch.zeros_like(heatmap), heatmap)
        keep = keep | ((remaining == _window_max(remaining, radius)) & ~covered)
    return torch.where(keep, heatmap, torch.zeros_like(heatmap))


def extract_keypoints(heatmap, threshold=0.005, nms_radius=4, border=4, top_k=None):
    """Per image of a [B,H,W] heatmap: (xy float [N,2], scores [N]) sorted by score."""
    suppressed = nms(heatmap, nms_radius)
    if border > 0:
        suppressed[:, :border] = 0
        suppressed[:, -border:] = 0
        suppressed[:, :, :border] = 0
        suppressed[:, :, -border:] = 0
    results = []
    for single in suppressed:
        ys, xs = torch.nonzero(single > threshold, as_tuple=True)
        scores = single[ys, xs]
        order = torch.argsort(scores, descending=True)
        if top_k is not None:
            order = order[:top_k]
        xy = torch.stack([xs[order], ys[order]], dim=1).float()
        results.append((xy, scores[order]))
    return results


def sample_descriptors(descriptor_map, xy):
    """Bilinear interpolation of the L2-normalised [256,Hc,Wc] map at pixel positions xy [N,2]; unit-length
    [N,256]. Official convention (SuperPoint / SuperGlue code, kept by pllvo's C++ port): pixel x maps to
    cell coordinate (x - 3.5) / (8 Wc - 4.5) * (Wc - 1), so pixel 3.5 is cell 0 and the last pixel the last cell."""
    channels, hc, wc = descriptor_map.shape
    descriptor_map = F.normalize(descriptor_map, dim=0)
    span = torch.tensor([CELL * wc - CELL / 2 - 0.5, CELL * hc - CELL / 2 - 0.5], dtype=xy.dtype, device=xy.device)
    grid = (xy - CELL / 2 + 0.5) / span * 2 - 1
    sampled = F.grid_sample(descriptor_map[None], grid[None, None], mode="bilinear", align_corners=True)
    return F.normalize(sampled[0, :, 0].t(), dim=1)


@torch.no_grad()
def detect_and_describe(model, image, threshold=0.005, nms_radius=4, border=4, top_k=None):
    """One [H,W] float image in [0,1] -> (xy [N,2], scores [N], descriptors [N,256]) on the CPU."""
    device = next(model.parameters()).device
    logits, descriptors = model.dense(image[None, None].to(device))
    heat = heatmap_from_logits(logits)
    (xy, scores), = extract_keypoints(heat, threshold, nms_radius, border, top_k)
    desc = sample_descriptors(descriptors[0], xy)
    return xy.cpu(), scores.cpu(), desc.cpu()
