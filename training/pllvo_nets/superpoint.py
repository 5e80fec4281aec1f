"""SuperPoint (DeTone, Malisiewicz, Rabinovich: "SuperPoint: Self-Supervised Interest
Point Detection and Description", CVPR-W 2018), written for pllvo.

The network has the layer names of Magic Leap's `superpoint_v1.pth`; the keypoint
selection after it follows the LightGlue project's extractor (NMS radius 4, border
removal, strict score threshold, optional top-k, bilinear descriptor sampling with
`align_corners=True`). pllvo's C++ port (src/pllvo/nn/superpoint.cpp) computes the same
function; both are checked against ../shared/testvectors/superpoint.

Training code uses `SuperPoint.dense(image)` (logits and raw descriptors, no
post-processing); inference uses `SuperPoint(image)`.
"""
import torch
import torch.nn.functional as F
from torch import nn


def max_pool_nms(scores, radius):
    """Max over a (2r+1)^2 window (stride 1, -inf padding) of a [B, H, W] map."""
    return F.max_pool2d(scores, kernel_size=2 * radius + 1, stride=1, padding=radius)


def simple_nms(scores, radius):
    """Keeps the local maxima of a [B, H, W] score map and zeroes the rest.

    A point survives if it equals the maximum of its window. Two more rounds then
    recover maxima whose window holds no surviving point (they were only hidden by a
    suppressed neighbour). Equal values all survive.
    """
    is_max = scores == max_pool_nms(scores, radius)
    for _ in range(2):
        near_max = max_pool_nms(is_max.float(), radius) > 0
        rest = torch.where(near_max, torch.zeros_like(scores), scores)
        is_max = is_max | ((rest == max_pool_nms(rest, radius)) & ~near_max)
    return torch.where(is_max, scores, torch.zeros_like(scores))


def sample_descriptors(keypoints, descriptors, cell=8):
    """Bilinear sampling of [B, D, h, w] descriptors at [B, N, 2] pixel keypoints.

    Pixel p maps to cell coordinate (p - cell/2 + 0.5) / (w*cell - cell/2 - 0.5) * (w - 1),
    the convention of the official code (grid_sample with align_corners=True).
    Returns [B, D, N], L2-normalised.
    """
    b, d, h, w = descriptors.shape
    grid = keypoints - cell / 2 + 0.5
    grid = grid / grid.new_tensor([w * cell - cell / 2 - 0.5, h * cell - cell / 2 - 0.5])
    grid = grid * 2 - 1
    sampled = F.grid_sample(descriptors, grid.view(b, 1, -1, 2), mode="bilinear", align_corners=True)
    return F.normalize(sampled.reshape(b, d, -1), p=2, dim=1)


def scores_to_map(logits):
    """[B, 65, h, w] detector logits -> [B, 8h, 8w] probabilities (dustbin dropped).

    score[8y + r, 8x + c] = softmax(logits)[8r + c, y, x] (depth-to-space).
    """
    prob = logits.softmax(1)[:, :-1]
    b, _, h, w = prob.shape
    prob = prob.permute(0, 2, 3, 1).reshape(b, h, w, 8, 8)
    return prob.permute(0, 1, 3, 2, 4).reshape(b, h * 8, w * 8)


class SuperPoint(nn.Module):
    default_conf = {
        "descriptor_dim": 256,
        "nms_radius": 4,
        "detection_threshold": 0.0005,  # strict: keeps score > threshold
        "remove_borders": 4,
        "max_num_keypoints": None,  # None: all; else the best N by score
    }

    def __init__(self, **conf):
        super().__init__()
        self.conf = {**self.default_conf, **conf}
        c1, c2, c3, c4, c5 = 64, 64, 128, 128, 256

        def conv(cin, cout, k=3):
            return nn.Conv2d(cin, cout, kernel_size=k, stride=1, padding=k // 2)

        # Shared VGG-style encoder (1/8 resolution).
        self.conv1a, self.conv1b = conv(1, c1), conv(c1, c1)
        self.conv2a, self.conv2b = conv(c1, c2), conv(c2, c2)
        self.conv3a, self.conv3b = conv(c2, c3), conv(c3, c3)
        self.conv4a, self.conv4b = conv(c3, c4), conv(c4, c4)
        # Detector head: 64 pixel positions of each 8x8 cell + a "no keypoint" dustbin.
        self.convPa, self.convPb = conv(c4, c5), conv(c5, 65, k=1)
        # Descriptor head.
        self.convDa, self.convDb = conv(c4, c5), conv(c5, self.conf["descriptor_dim"], k=1)

    def dense(self, image):
        """image [B, 1, H, W] in [0, 1] -> (detector logits [B, 65, H/8, W/8],
        raw descriptors [B, D, H/8, W/8], not normalised)."""
        x = image
        for a, b in [(self.conv1a, self.conv1b), (self.conv2a, self.conv2b), (self.conv3a, self.conv3b)]:
            x = F.max_pool2d(F.relu(b(F.relu(a(x)))), kernel_size=2, stride=2)
        x = F.relu(self.conv4b(F.relu(self.conv4a(x))))
        logits = self.convPb(F.relu(self.convPa(x)))
        descriptors = self.convDb(F.relu(self.convDa(x)))
        return logits, descriptors

    def forward(self, image):
        """image [B, 1, H, W] in [0, 1] (gray/255). Returns lists (one entry per image):
        keypoints [N, 2] (x, y) pixels, keypoint_scores [N], descriptors [N, D]; and the
        dense maps scores_dense [B, 8h, 8w] and descriptors_dense [B, D, h, w]."""
        logits, descriptors = self.dense(image)
        scores_dense = scores_to_map(logits)
        descriptors_dense = F.normalize(descriptors, p=2, dim=1)

        scores = simple_nms(scores_dense, self.conf["nms_radius"])
        pad = self.conf["remove_borders"]
        if pad:
            scores[:, :pad] = -1
            scores[:, :, :pad] = -1
            scores[:, -pad:] = -1
            scores[:, :, -pad:] = -1

        out = {"keypoints": [], "keypoint_scores": [], "descriptors": []}
        for i in range(scores.shape[0]):
            # torch.nonzero lists (y, x) in row-major order.
            yx = torch.nonzero(scores[i] > self.conf["detection_threshold"])
            kept = scores[i][yx[:, 0], yx[:, 1]]
            k = self.conf["max_num_keypoints"]
            if k is not None and k < len(kept):
                kept, order = torch.topk(kept, k, sorted=True)
                yx = yx[order]
            keypoints = yx.flip(1).float()
            desc = sample_descriptors(keypoints[None], descriptors_dense[i : i + 1])[0].t()
            out["keypoints"].append(keypoints)
            out["keypoint_scores"].append(kept)
            out["descriptors"].append(desc.contiguous())
        out["scores_dense"] = scores_dense
        out["descriptors_dense"] = descriptors_dense
        return out
