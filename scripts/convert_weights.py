#!/usr/bin/env python3
"""Converts an official PyTorch checkpoint to the safetensors file pllvo loads.

    python3 scripts/convert_weights.py superpoint_v1.pth models/superpoint_v1.safetensors
    python3 scripts/convert_weights.py superpoint_lightglue.pth models/superpoint_lightglue.safetensors

Accepted inputs (the kind is recognised from the tensor names):
  * SuperPoint: Magic Leap's `superpoint_v1.pth` (magicleap/SuperPointPretrainedNetwork;
    licence: academic or non-profit noncommercial research use only). Names are kept.
  * LightGlue: `superpoint_lightglue.pth` (cvg/LightGlue release v0.1_arxiv; Apache-2.0).
    The released names `self_attn.{i}.*` / `cross_attn.{i}.*` are renamed to
    `transformers.{i}.self_attn.*` / `transformers.{i}.cross_attn.*`, as the official
    loader does. The architecture is read from the shapes and stored in the metadata.

The tensors are checked by loading them strictly into pllvo's reference modules
(training/pllvo_nets). Needs only Debian's python3-torch and python3-numpy.
"""
import argparse
import hashlib
import json
import os
import re
import sys

import torch

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "training"))
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict  # noqa: E402
from pllvo_nets.safetensors_io import save_safetensors  # noqa: E402
from pllvo_nets.superpoint import SuperPoint  # noqa: E402

LICENCES = {
    "superpoint": "Magic Leap SuperPoint weights: academic or non-profit noncommercial research use only",
    "lightglue": "LightGlue (cvg/LightGlue): Apache-2.0",
}


def rename_lightglue(name):
    """self_attn.{i}.rest -> transformers.{i}.self_attn.rest (same for cross_attn)."""
    m = re.match(r"^(self_attn|cross_attn)\.(\d+)\.(.*)$", name)
    return f"transformers.{m.group(2)}.{m.group(1)}.{m.group(3)}" if m else name


def read_state_dict(path):
    state = torch.load(path, map_location="cpu")
    for key in ("model", "state_dict"):  # training checkpoints wrap the weights
        if isinstance(state, dict) and key in state and isinstance(state[key], dict):
            state = state[key]
    if not isinstance(state, dict) or not all(torch.is_tensor(v) for v in state.values()):
        raise SystemExit(f"{path}: not a state dict of tensors")
    return {k: v.detach().float().contiguous() for k, v in state.items()}


def convert(state):
    """Returns (kind, tensors, config) after renaming and a strict load into our modules."""
    if "conv1a.weight" in state:
        net = SuperPoint(descriptor_dim=state["convDb.weight"].shape[0])
        net.load_state_dict(state, strict=True)
        return "superpoint", state, {"descriptor_dim": state["convDb.weight"].shape[0]}
    if "posenc.Wr.weight" in state:
        state = {rename_lightglue(k): v for k, v in state.items()}
        conf = lightglue_conf_from_state_dict(state)
        net = LightGlue(**conf)
        net.load_state_dict(state, strict=True)  # tolerates a missing confidence_thresholds buffer
        return "lightglue", state, conf
    raise SystemExit("unrecognised checkpoint: neither SuperPoint (conv1a.weight) nor LightGlue (posenc.Wr.weight)")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("input", help="official .pth checkpoint")
    parser.add_argument("output", help="safetensors file to write")
    parser.add_argument("--fp16", action="store_true", help="store weights as F16 (halves the size)")
    args = parser.parse_args()

    kind, tensors, config = convert(read_state_dict(args.input))
    if args.fp16:
        tensors = {k: (v if k == "confidence_thresholds" else v.half()) for k, v in tensors.items()}
    with open(args.input, "rb") as f:
        digest = hashlib.sha256(f.read()).hexdigest()
    metadata = {
        "format": f"pllvo {kind} weights, names as the official state dict",
        "config": json.dumps(config),
        "source": f"{os.path.basename(args.input)} (sha256 {digest})",
        "converted_by": "scripts/convert_weights.py",
        "licence": LICENCES[kind],
    }
    save_safetensors(args.output, tensors, metadata)
    print(f"{kind}: {len(tensors)} tensors -> {args.output} ({'F16' if args.fp16 else 'F32'}), config {json.dumps(config)}")


if __name__ == "__main__":
    main()
