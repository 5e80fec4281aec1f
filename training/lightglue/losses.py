"""Ground-truth assignment of keypoints from a dense correspondence, and LightGlue's training losses:
the negative log-likelihood of the assignment at every layer (deep supervision; matched pairs and
unmatchable points balanced half and half, as in LightGlue / glue-factory), and the token-confidence
classifiers trained to predict whether a layer's prediction for a point already equals the final one."""
import torch
import torch.nn.functional as F

from pllvo_nets.lightglue import filter_matches


def sample_warp(warp, keypoints):
    """warp [B,H,W,2], keypoints [B,N,2] pixels -> [B,N,2] at the nearest pixel (NaN stays NaN)."""
    b, h, w, _ = warp.shape
    x = keypoints[..., 0].round().long().clamp(0, w - 1)
    y = keypoints[..., 1].round().long().clamp(0, h - 1)
    batch = torch.arange(b, device=warp.device)[:, None]
    return warp[batch, y, x]


def ground_truth(kp0, kp1, warp01, warp10, positive_px=3.0, negative_px=5.0):
    """matches0 [B,M] (index into kp1 or -1), unmatched0 [B,M], unmatched1 [B,N] (bool).

    The distance of a candidate pair is the larger of the two reprojection errors (kp0 taken to image 1
    against kp1, and kp1 taken to image 0 against kp0). A pair is a match when it is the mutual nearest
    and closer than positive_px; a point is unmatchable when nothing is within negative_px (or it is not
    visible in the other image); points in between are left out of the loss."""
    p01, p10 = sample_warp(warp01, kp0), sample_warp(warp10, kp1)
    d01 = torch.cdist(p01.nan_to_num(1e6), kp1)
    d10 = torch.cdist(kp0, p10.nan_to_num(1e6)).clone()
    d01[torch.isnan(p01[..., 0])] = float("inf")
    d10.transpose(1, 2)[torch.isnan(p10[..., 0])] = float("inf")
    dist = torch.maximum(d01, d10)
    min0, arg0 = dist.min(2)
    min1, arg1 = dist.min(1)
    mutual0 = arg1.gather(1, arg0) == torch.arange(kp0.shape[1], device=kp0.device)[None]
    matches0 = torch.where(mutual0 & (min0 < positive_px), arg0, torch.full_like(arg0, -1))
    return matches0, min0 > negative_px, min1 > negative_px


def assignment_nll(log_assignment, matches0, unmatched0, unmatched1, balance=0.5):
    """Mean over the batch of balance * NLL(matches) + (1 - balance) * NLL(unmatchable points)."""
    b, m1, n1 = log_assignment.shape
    m, n = m1 - 1, n1 - 1
    positive = matches0 >= 0
    target = matches0.clamp(min=0)
    pos_log = log_assignment[:, :m, :n].gather(2, target[..., None])[..., 0]
    pos_log = torch.where(positive, pos_log, torch.zeros_like(pos_log))
    nll_pos = -pos_log.sum(1) / positive.sum(1).clamp(min=1)
    neg0 = torch.where(unmatched0, log_assignment[:, :m, n], torch.zeros_like(log_assignment[:, :m, n]))
    neg1 = torch.where(unmatched1, log_assignment[:, m, :n], torch.zeros_like(log_assignment[:, m, :n]))
    nll_neg = -(neg0.sum(1) + neg1.sum(1)) / (unmatched0.sum(1) + unmatched1.sum(1)).clamp(min=1)
    return (balance * nll_pos + (1 - balance) * nll_neg).mean()


def confidence_loss(log_assignments, token0, token1, threshold):
    """BCE of each layer's token confidence against 'this layer's match for the point is the final one'."""
    with torch.no_grad():
        final0, final1, _, _ = filter_matches(log_assignments[-1], threshold)
    losses = []
    for la, t0, t1 in zip(log_assignments, token0, token1):
        with torch.no_grad():
            m0, m1, _, _ = filter_matches(la, threshold)
        losses.append(F.binary_cross_entropy(t0, (m0 == final0).float()) +
                      F.binary_cross_entropy(t1, (m1 == final1).float()))
    return torch.stack(losses).mean() / 2 if losses else log_assignments[-1].new_zeros(())


def match_quality(pred0, matches0, unmatched0):
    """(precision, recall) of predicted matches0 against the ground truth, over points with a label."""
    predicted = pred0 >= 0
    labelled = (matches0 >= 0) | unmatched0
    correct = predicted & (pred0 == matches0)
    wrong = predicted & labelled & ~correct
    precision = correct.sum() / (correct.sum() + wrong.sum()).clamp(min=1)
    recall = correct.sum() / (matches0 >= 0).sum().clamp(min=1)
    return precision, recall
