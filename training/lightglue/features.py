"""SuperPoint features for LightGlue training: pllvo's own SuperPoint, frozen, run batched on the training
device. A fixed number of keypoints per image (the best N after NMS and border removal, whatever their
score) keeps batches rectangular; the VO's adaptive threshold gives fewer, which LightGlue handles."""
import torch

from pllvo_nets.superpoint import SuperPoint, sample_descriptors, scores_to_map, simple_nms
from superpoint.network import load_weights


def load_extractor(weights, device):
    model = SuperPoint()
    load_weights(model, weights)
    return model.to(device).eval().requires_grad_(False)


@torch.no_grad()
def extract(model, images, keypoints, nms_radius=4, border=4):
    """images [B,1,H,W] in [0,1] -> keypoints [B,N,2] (x, y pixels), descriptors [B,N,256], scores [B,N]."""
    logits, descriptors = model.dense(images)
    scores = simple_nms(scores_to_map(logits), nms_radius)
    if border:
        scores[:, :border] = -1
        scores[:, -border:] = -1
        scores[:, :, :border] = -1
        scores[:, :, -border:] = -1
    b, h, w = scores.shape
    # A tiny random tie-break spreads the zero-score points that fill up sparse images.
    flat = scores.reshape(b, -1) + 1e-7 * torch.rand(b, h * w, device=scores.device)
    top, index = flat.topk(keypoints, dim=1)
    xy = torch.stack([index % w, torch.div(index, w, rounding_mode="floor")], -1).float()
    desc = sample_descriptors(xy, torch.nn.functional.normalize(descriptors, dim=1)).transpose(1, 2)
    return xy, desc.contiguous(), top
