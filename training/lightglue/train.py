"""Trains pllvo's LightGlue on SuperPoint features (pllvo's own SuperPoint, frozen), LightGlue's recipe:
homography pairs from real images and, when packed `pllvo synth` sequences are given, pairs of frames with
exact depth and poses; deep-supervised assignment NLL + matchability + token confidence (losses.py).
Resumable (rerun the same command), time-capped (--max-minutes, or the preset's fixed training time).

  CPU:  nice -n 19 /usr/bin/python3 training/lightglue/train.py --preset cpu-small --max-minutes 120
  GPU:  python3 training/lightglue/train.py --preset gpu-short --device cuda --synth-dir PACK/synth/<name> ...
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import argparse
import sys
from pathlib import Path

import numpy as np
import torch

from lightglue import features, losses
from lightglue.config import build_config, to_json
from lightglue.pairs import HomographyPairs, SynthPairs
from pllvo_nets.lightglue import LightGlue, filter_matches
from pllvo_nets.mnn import mutual_nn_match
from pllvo_nets.safetensors_io import load_safetensors
from superpoint import trainer
from superpoint.data_sources import REPO_ROOT

STAGE_ID = 11


class PairBatches:
    """Batches of one kind each (homography or synthetic), so that images in a batch share a size."""

    def __init__(self, config):
        self.config = config
        self.homography = HomographyPairs(config.data, config.height, config.width, config.homography,
                                          config.photometric, config.seed)
        self.synth = SynthPairs(config.synth_dirs, config.synth_max_gap, config.synth_photometric) \
            if config.synth_dirs else None

    def __call__(self, rng):
        use_synth = self.synth is not None and rng.random() < self.config.p_synth
        source = self.synth if use_synth else self.homography
        pairs = [source.pair(rng) for _ in range(self.config.batch)]
        stack = [torch.from_numpy(np.stack([p[k] for p in pairs])) for k in range(4)]
        return stack[0][:, None], stack[1][:, None], stack[2], stack[3]


def build_model(config):
    m = config.model
    return LightGlue(n_layers=m.n_layers, descriptor_dim=m.descriptor_dim, num_heads=m.num_heads,
                     filter_threshold=config.filter_threshold)


class Step:
    """Features (frozen SuperPoint) -> ground truth -> LightGlue at every layer -> losses."""

    def __init__(self, config, model, extractor, device):
        self.config, self.model, self.extractor, self.device = config, model, extractor, device

    def prepare(self, batch):
        image0, image1, warp01, warp10 = (t.to(self.device) for t in batch)
        kp0, desc0, _ = features.extract(self.extractor, image0, self.config.keypoints, self.config.nms_radius)
        kp1, desc1, _ = features.extract(self.extractor, image1, self.config.keypoints, self.config.nms_radius)
        h, w = image0.shape[-2:]
        size = torch.tensor([[w, h]], device=self.device, dtype=torch.float32).expand(len(kp0), 2)
        gt = losses.ground_truth(kp0, kp1, warp01, warp10, self.config.positive_px, self.config.negative_px)
        data0 = {"keypoints": kp0, "descriptors": desc0, "image_size": size}
        data1 = {"keypoints": kp1, "descriptors": desc1, "image_size": size}
        return data0, data1, gt

    def __call__(self, batch):
        data0, data1, (matches0, unmatched0, unmatched1) = self.prepare(batch)
        out = self.model.forward_train(data0, data1)
        nll = torch.stack([losses.assignment_nll(la, matches0, unmatched0, unmatched1, self.config.nll_balance)
                           for la in out["log_assignment"]]).mean()
        confidence = losses.confidence_loss(out["log_assignment"][:-1], out["token0"], out["token1"],
                                            self.config.filter_threshold)
        with torch.no_grad():
            pred0 = filter_matches(out["log_assignment"][-1], self.config.filter_threshold)[0]
            precision, recall = losses.match_quality(pred0, matches0, unmatched0)
        return {"total": nll + self.config.confidence_weight * confidence, "nll": nll.detach(),
                "confidence": confidence.detach(), "precision": precision, "recall": recall}


class Validation:
    """Precision / recall of LightGlue (all layers) and of mutual nearest neighbours on fixed pairs."""

    def __init__(self, config, step):
        self.step = step
        make = PairBatches(config)
        rng = np.random.default_rng([config.seed, STAGE_ID, 10**9])
        count = max(1, config.validation_pairs // config.batch)
        self.batches = [make(rng) for _ in range(count)]

    @torch.no_grad()
    def __call__(self, model):
        model.eval()
        scores = {"lg_precision": [], "lg_recall": [], "mnn_precision": [], "mnn_recall": []}
        for batch in self.batches:
            data0, data1, (matches0, unmatched0, _) = self.step.prepare(batch)
            la = model.forward_train(data0, data1)["log_assignment"][-1]
            pred = filter_matches(la, self.step.config.filter_threshold)[0]
            for name, p in (("lg", pred), ("mnn", mnn_batch(data0["descriptors"], data1["descriptors"]))):
                precision, recall = losses.match_quality(p, matches0, unmatched0)
                scores[f"{name}_precision"].append(float(precision))
                scores[f"{name}_recall"].append(float(recall))
        model.train()
        return {k: round(float(np.mean(v)), 4) for k, v in scores.items()}


def mnn_batch(desc0, desc1, max_distance=0.7):
    """matches0 [B,M] of mutual nearest neighbours (the VO's MNN, distance threshold 0.7)."""
    rows = []
    for d0, d1 in zip(desc0.cpu(), desc1.cpu()):
        matches, _ = mutual_nn_match(d0, d1, distance_threshold=max_distance)
        row = torch.full((len(d0),), -1, dtype=torch.long)
        row[matches[:, 0]] = matches[:, 1]
        rows.append(row)
    return torch.stack(rows).to(desc0.device)


def parser(description):
    p = argparse.ArgumentParser(description=description, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--preset", default="cpu-small", help="cpu-small, gpu-short or smoke (see config.py)")
    p.add_argument("--set", action="append", default=[], metavar="KEY=VALUE", help="override, e.g. batch=8")
    p.add_argument("--out", default=None, help="run folder (default: out/lgtrain/<preset>)")
    p.add_argument("--device", default="cpu")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--max-minutes", type=float, default=0.0, help="stop after this many minutes (resumable)")
    p.add_argument("--superpoint", default=None, help="SuperPoint weights (default: the config's, repo models/)")
    p.add_argument("--synth-dir", action="append", default=[], help="packed synthetic sequence (make_data_pack.py)")
    p.add_argument("--init", default=None, help="start from these LightGlue weights (.safetensors) instead of random")
    return p


def setup(args):
    torch.set_num_threads(max(1, args.threads))
    config = build_config(args.preset, args.set)
    config.synth_dirs = list(config.synth_dirs) + [str(Path(d).resolve()) for d in args.synth_dir]
    if args.superpoint:
        config.superpoint = str(Path(args.superpoint).resolve())
    elif not Path(config.superpoint).is_absolute():
        config.superpoint = str(REPO_ROOT / config.superpoint)
    if not Path(config.superpoint).is_file():
        sys.exit(f"lgtrain: error: SuperPoint weights {config.superpoint} not found (--superpoint PATH)")
    device = torch.device(args.device)
    if device.type == "cuda":
        if not torch.cuda.is_available():
            sys.exit("lgtrain: error: --device cuda requested but torch sees no CUDA device")
        torch.backends.cuda.matmul.allow_tf32 = True
        torch.backends.cudnn.allow_tf32 = True
    out = Path(args.out) if args.out else REPO_ROOT / "out" / "lgtrain" / args.preset
    return config, out, device


def train(config, out, device, max_minutes=0.0, log=print, init=None):
    torch.manual_seed(config.seed)
    model = build_model(config)
    if init:   # a checkpoint in `out` still wins (trainer.run resumes from it)
        tensors, _ = load_safetensors(init)
        model.load_state_dict({k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in tensors.items()})
        log(f"[lightglue] initialised from {init}")
    model = model.to(device)
    extractor = features.load_extractor(config.superpoint, device)
    step = Step(config, model, extractor, device)
    batches = PairBatches(config)
    log(f"[lightglue] {len(batches.homography.items)} homography crops, "
        f"{len(batches.synth.sequences) if batches.synth else 0} synthetic sequences, {config.model}")
    return trainer.run("lightglue", STAGE_ID, model, config.steps, config.lr, batches, step, out, to_json(config),
                       config.seed, False, device, config.checkpoint_every, config.log_every, max_minutes,
                       config.workers, validate=Validation(config, step), log=log, stage_minutes=config.minutes)


def main():
    args = parser(__doc__).parse_args()
    config, out, device = setup(args)
    train(config, out, device, args.max_minutes, init=args.init)


if __name__ == "__main__":
    main()
