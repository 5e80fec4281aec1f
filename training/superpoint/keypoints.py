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


def nms(heatmap, radius):
    """Keeps the local maxima of a [B,H,W] map over a (2r+1)^2 window, zeroes the rest."""
    if radius <= 0:
        return heatmap
    peak = F.max_pool2d(heatmap[:, None], 2 * radius + 1, stride=1, padding=radius)[:, 0]
    return torch.where(heatmap == peak, heatmap, torch.zeros_like(heatmap))


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
    """Bilinear interpolation of a [256,Hc,Wc] map at pixel positions xy [N,2] (pixel centres at integer
    coordinates, cell (i, j) centred on pixel (8j + 3.5, 8i + 3.5)); unit-length [N,256]."""
    channels, hc, wc = descriptor_map.shape
    gx = (xy[:, 0] - (CELL - 1) / 2) / CELL
    gy = (xy[:, 1] - (CELL - 1) / 2) / CELL
    grid = torch.stack([2 * gx / max(wc - 1, 1) - 1, 2 * gy / max(hc - 1, 1) - 1], dim=1)
    sampled = F.grid_sample(descriptor_map[None], grid[None, None], mode="bilinear", align_corners=True)
    return F.normalize(sampled[0, :, 0].t(), dim=1)


@torch.no_grad()
def detect_and_describe(model, image, threshold=0.005, nms_radius=4, border=4, top_k=None):
    """One [H,W] float image in [0,1] -> (xy [N,2], scores [N], descriptors [N,256]) on the CPU."""
    device = next(model.parameters()).device
    logits, descriptors = model(image[None, None].to(device))
    heat = heatmap_from_logits(logits)
    (xy, scores), = extract_keypoints(heat, threshold, nms_radius, border, top_k)
    desc = sample_descriptors(descriptors[0], xy)
    return xy.cpu(), scores.cpu(), desc.cpu()
