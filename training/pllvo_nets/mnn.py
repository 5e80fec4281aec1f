"""Mutual nearest-neighbour matching of L2-normalised descriptors: the baseline LightGlue is
measured against, and pllvo's fallback matcher (src/pllvo/nn/mnn_matcher.cpp computes the
same: squared distance 2 (1 - cos), optional ratio test and distance threshold, as hloc)."""
import torch


def mutual_nn_match(desc0, desc1, mutual=True, ratio_threshold=0.0, distance_threshold=0.7):
    """desc0 [M, D], desc1 [N, D] -> matches [K, 2] (index0 ascending), scores [K] (cosine)."""
    if len(desc0) == 0 or len(desc1) == 0:
        return torch.zeros((0, 2), dtype=torch.long), torch.zeros(0)
    sim = desc0 @ desc1.t()
    top = sim.topk(min(2, sim.shape[1]), dim=1)
    best, nn0 = top.values[:, 0], top.indices[:, 0]
    keep = torch.ones_like(best, dtype=torch.bool)
    if mutual:
        nn1 = sim.argmax(0)
        keep &= nn1[nn0] == torch.arange(len(desc0))
    dist2 = 2 * (1 - top.values)
    if ratio_threshold > 0 and sim.shape[1] > 1:
        keep &= dist2[:, 0] <= ratio_threshold**2 * dist2[:, 1]
    if distance_threshold > 0:
        keep &= dist2[:, 0] <= distance_threshold**2
    index0 = torch.where(keep)[0]
    return torch.stack([index0, nn0[index0]], -1), best[index0]
