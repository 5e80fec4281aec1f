"""Stage 2: homographic adaptation (SuperPoint section 5). The detector's corner probabilities over many
random homographies of a real image (identity included) are warped back and averaged; NMS + threshold
on the average give that image's pseudo ground-truth points, cached on disk per training crop."""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import hashlib
import json
import time
from pathlib import Path

import numpy as np
import torch

from superpoint import data_sources
from superpoint.homographies import sample_homography, warp_batch
from superpoint.keypoints import extract_keypoints, heatmap_from_logits
from superpoint.network import build_superpoint, load_weights, read_weights

STAGE_ID = 2


@torch.no_grad()
def aggregate_heatmap(model, image, homographies, batch, valid_margin):
    """image [H,W] float tensor on the model's device; homographies [N,3,3] (source -> warped).
    Returns the mean over homographies of the back-warped heatmaps, [H,W] (0 where never seen)."""
    height, width = image.shape
    device = image.device
    total = torch.zeros(height, width, device=device)
    count = torch.zeros(height, width, device=device)
    ys, xs = torch.meshgrid(torch.arange(height, device=device, dtype=torch.float64),
                            torch.arange(width, device=device, dtype=torch.float64), indexing="ij")
    pixels = torch.stack([xs, ys, torch.ones_like(xs)], -1).reshape(-1, 3)
    for start in range(0, len(homographies), batch):
        H = homographies[start:start + batch].to(device)
        warped = warp_batch(image[None, None].expand(len(H), 1, height, width), H)
        logits, _ = model.dense(warped)
        heat = heatmap_from_logits(logits)[:, None]
        back = warp_batch(heat, torch.linalg.inv(H))[:, 0]
        # A source pixel counts for a homography when it lands inside that warped image, off its border.
        mapped = pixels[None] @ H.transpose(1, 2)
        mapped = mapped[..., :2] / mapped[..., 2:3]
        seen = ((mapped[..., 0] >= valid_margin) & (mapped[..., 0] <= width - 1 - valid_margin) &
                (mapped[..., 1] >= valid_margin) & (mapped[..., 1] <= height - 1 - valid_margin))
        seen = seen.reshape(len(H), height, width).float()
        total += (back * seen).sum(0)
        count += seen.sum(0)
    return total / count.clamp(min=1.0)


def homographies_for(rng, count, height, width, params):
    """Identity first (the image itself), then count-1 random homographies."""
    Hs = [np.eye(3)] + [sample_homography(rng, height, width, params) for _ in range(count - 1)]
    return torch.from_numpy(np.stack(Hs))


def pseudo_labels(model, image, rng, cfg, device):
    """[N,2] float32 xy pseudo ground-truth points of one float32 [H,W] image."""
    height, width = image.shape
    Hs = homographies_for(rng, cfg.homographies, height, width, cfg.homography)
    heat = aggregate_heatmap(model, torch.from_numpy(image).to(device), Hs, cfg.batch, cfg.valid_margin)
    (xy, _), = extract_keypoints(heat[None], cfg.threshold, cfg.nms_radius, cfg.border)
    return xy.cpu().numpy().astype(np.float32)


def weights_fingerprint(path):
    """Hash of the detector's weights (not of the file, which also holds optimiser state and times)."""
    digest = hashlib.sha1()
    for name, tensor in sorted(read_weights(path).items()):
        digest.update(name.encode())
        digest.update(tensor.numpy().tobytes())
    return digest.hexdigest()[:12]


def labels_dir(out_dir, detector_weights):
    return Path(out_dir) / "adaptation" / f"labels_{weights_fingerprint(detector_weights)}"


def run(config, out_dir, device, detector_weights, deadline=None, log=print):
    """Labels every training crop (skipping crops already labelled); returns the labels folder, or None
    when the deadline (a time.time() value) passed first (rerun to continue)."""
    cfg, height, width = config.adaptation, config.joint.height, config.joint.width
    model = load_weights(build_superpoint(device="cpu"), detector_weights).to(device).eval()
    items = data_sources.make_items(config.data, height, width, config.seed)
    if cfg.max_items:
        items = items[:cfg.max_items]
    folder = labels_dir(out_dir, detector_weights)
    folder.mkdir(parents=True, exist_ok=True)
    started, done, counts = time.time(), 0, []
    for index, item in enumerate(items):
        target = folder / f"{item.key(height, width)}.npy"
        if target.exists():
            counts.append(len(np.load(target)))
            continue
        if deadline is not None and time.time() > deadline:
            log(f"[adaptation] time budget spent after {index}/{len(items)} crops; rerun to resume")
            return None
        rng = np.random.default_rng([config.seed, STAGE_ID, index])
        points = pseudo_labels(model, data_sources.load_item(item, height, width), rng, cfg, device)
        np.save(target.with_name(target.stem + ".tmp.npy"), points)
        target.with_name(target.stem + ".tmp.npy").replace(target)
        counts.append(len(points))
        done += 1
        if done % 25 == 0:
            log(f"[adaptation] {index + 1}/{len(items)} crops, {(time.time() - started) / done:.2f} s per crop")
    manifest = {"detector_weights": str(detector_weights), "items": len(items), "resolution": [height, width],
                "points_per_crop_mean": float(np.mean(counts)) if counts else 0.0,
                "sources": data_sources.summary(items), "config": vars(cfg) | {"homography": vars(cfg.homography)}}
    (folder / "manifest.json").write_text(json.dumps(manifest, indent=1, default=str))
    log(f"[adaptation] {len(items)} crops labelled in {folder} (mean {manifest['points_per_crop_mean']:.1f} points)")
    return folder


def main():
    from superpoint import cli
    p = cli.parser(__doc__)
    p.add_argument("--detector", default=None, help="detector weights (default: <out>/shapes/checkpoint.pt)")
    args = p.parse_args()
    config, out, device = cli.setup(args)
    run(config, out, device, args.detector or out / "shapes" / "checkpoint.pt")


if __name__ == "__main__":
    main()
