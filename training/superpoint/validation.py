"""Progress measures computed during training on fixed, seeded data (never the held-out images):
stage 1: corner precision / recall on synthetic shapes; stage 3: repeatability and mutual-NN matching
precision on fixed homographic pairs of training crops."""
import numpy as np
import torch

from superpoint import eval_metrics, photometric, synthetic_shapes
from superpoint.homographies import sample_homography, warp_image
from superpoint.keypoints import extract_keypoints, heatmap_from_logits, sample_descriptors

VALIDATION_STAGE = 99


def _detections(model, images, threshold=0.015, nms_radius=4, border=4, top_k=None):
    device = next(model.parameters()).device
    with torch.no_grad():
        logits, descriptors = model.dense(torch.from_numpy(np.stack(images))[:, None].to(device))
    found = extract_keypoints(heatmap_from_logits(logits), threshold, nms_radius, border, top_k)
    return [(xy.cpu().numpy(), d) for (xy, _), d in zip(found, descriptors)]


class ShapesValidation:
    """Precision and recall (3 px) of the detected corners on 64 fixed synthetic images."""

    def __init__(self, cfg, seed, count=64):
        rng = np.random.default_rng([seed, VALIDATION_STAGE, 1])
        self.samples = [synthetic_shapes.render(rng, cfg.height, cfg.width) for _ in range(count)]

    def __call__(self, model):
        was_training = model.training
        model.eval()
        true_pos = found = expected = 0
        for start in range(0, len(self.samples), 16):
            chunk = self.samples[start:start + 16]
            for (xy, _), (_, corners) in zip(_detections(model, [c[0] for c in chunk]), chunk):
                found += len(xy)
                expected += len(corners)
                if len(xy) and len(corners):
                    d = np.linalg.norm(xy[:, None] - corners[None], axis=2)
                    true_pos += int((d.min(axis=1) <= 3).sum())
        model.train(was_training)
        return {"precision": round(true_pos / max(found, 1), 4), "recall": round(true_pos / max(expected, 1), 4)}


class JointValidation:
    """Repeatability (3 px, strongest 300) and mutual-NN match precision (3 px) on 16 fixed pairs."""

    def __init__(self, pair_source, seed, count=16):
        rng = np.random.default_rng([seed, VALIDATION_STAGE, 3])
        cfg = pair_source.cfg
        self.pairs = []
        for _ in range(count):
            image, _ = pair_source.crop(int(rng.integers(len(pair_source.items))))
            H = sample_homography(rng, cfg.height, cfg.width, cfg.homography)
            warped, _ = warp_image(image, H)
            self.pairs.append((photometric.augment(image, rng, cfg.photometric),
                               photometric.augment(warped, rng, cfg.photometric), H))
        self.shape = (cfg.height, cfg.width)

    def __call__(self, model):
        was_training = model.training
        model.eval()
        reps, precisions = [], []
        for image1, image2, H in self.pairs:
            (xy1, d1), (xy2, d2) = _detections(model, [image1, image2], threshold=0.005, top_k=300)
            if len(xy1) == 0 or len(xy2) == 0:
                reps.append(0.0)
                precisions.append(0.0)
                continue
            reps.append(eval_metrics.repeatability(xy1, xy2, H, self.shape, self.shape) or 0.0)
            desc1 = sample_descriptors(d1, torch.from_numpy(xy1).to(d1.device)).cpu().numpy()
            desc2 = sample_descriptors(d2, torch.from_numpy(xy2).to(d2.device)).cpu().numpy()
            matches = eval_metrics.mutual_nn(desc1, desc2, "l2")
            precisions.append(eval_metrics.match_precision(xy1, xy2, matches, H))
        model.train(was_training)
        return {"repeatability": round(float(np.mean(reps)), 4), "match_precision": round(float(np.mean(precisions)), 4)}

