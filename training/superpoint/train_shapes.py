"""Stage 1 (MagicPoint): the detector trained on synthetic shapes with the 65-class cell cross-entropy."""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import numpy as np
import torch

from superpoint import photometric, synthetic_shapes, trainer
from superpoint.config import to_json
from superpoint.labels import cell_labels
from superpoint.losses import detector_loss
from superpoint.network import build_superpoint, initialise_for_training
from superpoint.validation import ShapesValidation

STAGE_ID = 1


def shapes_batch(rng, cfg):
    """[B,1,H,W] float images and [B,H/8,W/8] labels of freshly rendered, photometrically changed shapes."""
    images, labels = [], []
    for _ in range(cfg.batch):
        image, points = synthetic_shapes.render(rng, cfg.height, cfg.width)
        images.append(photometric.augment(image, rng, cfg.photometric))
        labels.append(cell_labels(points, cfg.height, cfg.width, rng))
    return torch.from_numpy(np.stack(images))[:, None], torch.from_numpy(np.stack(labels))


def train(config, out_dir, device, max_minutes=0.0, log=print):
    """Trains (or resumes) stage 1 into out_dir/shapes; returns the logged rows."""
    cfg = config.shapes
    model = initialise_for_training(build_superpoint(device="cpu"), config.seed).to(device)

    def make_batch(rng):
        return shapes_batch(rng, cfg)

    def compute_losses(batch):
        images, labels = batch
        logits, _ = model.dense(images.to(device))
        loss = detector_loss(logits, labels.to(device))
        return {"total": loss, "detector": loss}

    return trainer.run("shapes", STAGE_ID, model, cfg.steps, cfg.lr, make_batch, compute_losses, out_dir / "shapes",
                       to_json(config), config.seed, cfg.fixed_data, device, config.checkpoint_every,
                       config.log_every, max_minutes, config.workers, validate=ShapesValidation(cfg, config.seed),
                       log=log, stage_minutes=cfg.minutes)


def main():
    from superpoint import cli
    args = cli.parser(__doc__).parse_args()
    config, out, device = cli.setup(args)
    train(config, out, device, args.max_minutes)


if __name__ == "__main__":
    main()
