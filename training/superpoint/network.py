"""Builds pllvo's PyTorch SuperPoint and moves weights in and out of it.

The architecture comes from training/pllvo_nets/superpoint.py (the nn module, validated against the
official test vectors). Training uses their `dense` method: a [B,1,H,W] float image in [0,1] -> (raw detector logits
[B,65,H/8,W/8], raw descriptor map [B,256,H/8,W/8]).
"""
import math
import sys
from pathlib import Path

import torch
from torch import nn

from superpoint.safetensors_io import read_safetensors
from superpoint.trainer import load_state

TRAINING_DIR = Path(__file__).resolve().parents[1]
REPO_ROOT = TRAINING_DIR.parent
OFFICIAL_NAMES = [f"{layer}.{kind}" for layer in
                  ("conv1a", "conv1b", "conv2a", "conv2b", "conv3a", "conv3b", "conv4a", "conv4b",
                   "convPa", "convPb", "convDa", "convDb") for kind in ("weight", "bias")]


def superpoint_class():
    if str(TRAINING_DIR) not in sys.path:
        sys.path.insert(0, str(TRAINING_DIR))
    from pllvo_nets.superpoint import SuperPoint
    return SuperPoint


def build_superpoint(weights=None, device="cpu"):
    """A SuperPoint on `device`, with weights from a .safetensors file or a training checkpoint if given."""
    model = superpoint_class()()
    missing = set(OFFICIAL_NAMES) - set(model.state_dict())
    if missing:
        raise RuntimeError(f"SuperPoint module lacks the official tensor names {sorted(missing)}")
    if weights is not None:
        load_weights(model, weights)
    return model.to(device)


def initialise_for_training(model, seed):
    """He initialisation for the ReLU convolutions (the net has no batch norm, as the official weights),
    so that activations keep their scale through the 10 stacked layers; zero biases."""
    generator = torch.Generator().manual_seed(seed)
    for module in model.modules():
        if isinstance(module, nn.Conv2d):
            fan_in = module.in_channels * module.kernel_size[0] * module.kernel_size[1]
            with torch.no_grad():
                module.weight.copy_(torch.randn(module.weight.shape, generator=generator) * math.sqrt(2.0 / fan_in))
                module.bias.zero_()
    return model


def read_weights(path):
    """State dict (float32) from a .safetensors export or from a training checkpoint (.pt)."""
    path = Path(path)
    if path.suffix == ".safetensors":
        tensors, _ = read_safetensors(path)
    else:
        tensors = load_state(path)["model"]
    return {k: v.float() for k, v in tensors.items()}


def load_weights(model, path):
    state = read_weights(path)
    unexpected = set(state) - set(OFFICIAL_NAMES)
    if unexpected:
        raise ValueError(f"{path}: unexpected tensors {sorted(unexpected)}")
    model.load_state_dict(state, strict=True)
    return model
