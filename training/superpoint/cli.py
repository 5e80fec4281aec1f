"""Command-line options shared by the stage scripts and the pipeline."""
import argparse
import sys
from pathlib import Path

import torch

from superpoint.config import build_config
from superpoint.data_sources import REPO_ROOT


def parser(description):
    p = argparse.ArgumentParser(description=description, formatter_class=argparse.ArgumentDefaultsHelpFormatter)
    p.add_argument("--preset", default="cpu-small", help="cpu-small, gpu, gpu-short or smoke (see config.py)")
    p.add_argument("--set", action="append", default=[], metavar="SECTION.KEY=VALUE",
                   help="override a configuration value, e.g. joint.steps=500 (repeatable)")
    p.add_argument("--out", default=None, help="run folder (default: out/sptrain/<preset>)")
    p.add_argument("--device", default="cpu", help="cpu, cuda, cuda:1, ...")
    p.add_argument("--threads", type=int, default=2, help="CPU threads for torch")
    p.add_argument("--max-minutes", type=float, default=0.0,
                   help="stop each training stage after this many minutes with a checkpoint (0: no limit)")
    p.add_argument("--synth-dir", action="append", default=[], help="folder of `pllvo synth` frames (repeatable)")
    p.add_argument("--image-dir", action="append", default=[], help="extra folder of training images (repeatable)")
    return p


def setup(args):
    """(config, run folder, torch device) from parsed arguments."""
    torch.set_num_threads(max(1, args.threads))
    config = build_config(args.preset, args.set)
    config.data.synth_dirs = list(config.data.synth_dirs) + [str(Path(d).resolve()) for d in args.synth_dir]
    config.data.image_dirs = list(config.data.image_dirs) + [str(Path(d).resolve()) for d in args.image_dir]
    out = Path(args.out) if args.out else REPO_ROOT / "out" / "sptrain" / args.preset
    device = torch.device(args.device)
    if device.type == "cuda" and not torch.cuda.is_available():
        sys.exit("sptrain: error: --device cuda requested but torch sees no CUDA device")
    if device.type == "cuda":   # TF32 convolutions/matmuls: ~3x faster on Ampere/Hopper, ample for training
        torch.backends.cuda.matmul.allow_tf32 = True
        torch.backends.cudnn.allow_tf32 = True
        torch.backends.cudnn.benchmark = True
    return config, out, device
