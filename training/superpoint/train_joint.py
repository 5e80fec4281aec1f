"""Stage 3: joint training of detector and descriptor (SuperPoint section 3.4) on pairs (crop, warped crop)
related by a random homography, each with its own photometric changes (including strong darkening), the
detector trained on the pseudo labels of stage 2 and the descriptor with the dense hinge loss."""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

from pathlib import Path

import numpy as np
import torch

from superpoint import data_sources, photometric, trainer
from superpoint.config import to_json
from superpoint.homographies import inside, sample_homography, warp_image, warp_points
from superpoint.labels import cell_labels, cell_mask
from superpoint.losses import descriptor_loss, detector_loss
from superpoint.network import build_superpoint, initialise_for_training, read_weights
from superpoint.validation import JointValidation

STAGE_ID = 3


class PairSource:
    """Training crops with their pseudo labels, turned into augmented homographic pairs."""

    def __init__(self, config, labels_folder):
        cfg = config.joint
        self.cfg = cfg
        self.items = data_sources.make_items(config.data, cfg.height, cfg.width, config.seed)
        if config.adaptation.max_items:
            self.items = self.items[:config.adaptation.max_items]
        self.labels_folder = labels_folder
        self.cache = {}
        missing = [i for i in self.items if not (labels_folder / f"{i.key(cfg.height, cfg.width)}.npy").exists()]
        if missing:
            raise FileNotFoundError(f"{len(missing)} crops have no pseudo labels in {labels_folder}; run stage 2")

    def crop(self, index):
        if index not in self.cache:
            item = self.items[index]
            image = data_sources.load_item(item, self.cfg.height, self.cfg.width)
            points = np.load(self.labels_folder / f"{item.key(self.cfg.height, self.cfg.width)}.npy")
            self.cache[index] = (np.round(image * 255).astype(np.uint8), points)
        image, points = self.cache[index]
        return image.astype(np.float32) / 255, points

    def pair(self, rng):
        cfg = self.cfg
        image, points = self.crop(int(rng.integers(len(self.items))))
        H = sample_homography(rng, cfg.height, cfg.width, cfg.homography)
        warped, valid = warp_image(image, H)
        points2 = warp_points(points, H)
        keep = inside(points2, cfg.height, cfg.width)
        points2 = points2[keep]
        rounded = np.round(points2).astype(int)
        points2 = points2[valid[rounded[:, 1], rounded[:, 0]]] if len(points2) else points2
        image1 = photometric.augment(image, rng, cfg.photometric)
        image2 = photometric.augment(warped, rng, cfg.photometric) * valid
        return (image1, cell_labels(points, cfg.height, cfg.width, rng),
                image2, cell_labels(points2, cfg.height, cfg.width, rng), cell_mask(valid), H)

    def batch(self, rng):
        pairs = [self.pair(rng) for _ in range(self.cfg.batch)]
        stack = [torch.from_numpy(np.stack([p[k] for p in pairs])) for k in range(6)]
        return stack[0][:, None].float(), stack[1], stack[2][:, None].float(), stack[3], stack[4], stack[5].float()


def train(config, out_dir, device, labels_folder, max_minutes=0.0, log=print):
    cfg = config.joint
    model = initialise_for_training(build_superpoint(device="cpu"), config.seed + 1)
    shapes_weights = out_dir / "shapes" / "checkpoint.pt"
    if cfg.init_from_shapes and shapes_weights.exists():
        model.load_state_dict(read_weights(shapes_weights))
    model = model.to(device)
    pairs = PairSource(config, labels_folder)
    log(f"[joint] {len(pairs.items)} crops from {data_sources.summary(pairs.items)}")

    def compute_losses(batch):
        image1, labels1, image2, labels2, valid2, H = (t.to(device) for t in batch)
        logits, descriptors = model.dense(torch.cat([image1, image2]))
        b = image1.shape[0]
        det1 = detector_loss(logits[:b], labels1)
        det2 = detector_loss(logits[b:], labels2, valid2)
        desc = descriptor_loss(descriptors[:b], descriptors[b:], H, valid2, cfg.descriptor)
        return {"total": det1 + det2 + cfg.lambda_loss * desc, "detector": (det1 + det2) / 2, "descriptor": desc}

    extra = {"data": data_sources.summary(pairs.items), "labels": str(labels_folder)}
    return trainer.run("joint", STAGE_ID, model, cfg.steps, cfg.lr, pairs.batch, compute_losses, out_dir / "joint",
                       to_json(config), config.seed, cfg.fixed_data, device, config.checkpoint_every,
                       config.log_every, max_minutes, config.workers, extra_state=extra,
                       validate=JointValidation(pairs, config.seed), log=log, stage_minutes=cfg.minutes)


def main():
    from superpoint import cli
    from superpoint.homographic_adaptation import labels_dir
    p = cli.parser(__doc__)
    p.add_argument("--labels", default=None, help="pseudo-label folder (default: the one of <out>/shapes)")
    args = p.parse_args()
    config, out, device = cli.setup(args)
    folder = args.labels or labels_dir(out, out / "shapes" / "checkpoint.pt")
    train(config, out, device, Path(folder), args.max_minutes)


if __name__ == "__main__":
    main()
