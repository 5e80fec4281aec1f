#!/usr/bin/env python3
"""Test helper: writes a safetensors weight file as an official-layout .pth (torch.save of
a plain state dict, LightGlue names as released: self_attn.{i}.* / cross_attn.{i}.*, and no
confidence_thresholds buffer), to test scripts/convert_weights.py end to end.

    python3 tests/nn/write_official_pth.py WEIGHTS.safetensors OUT.pth
"""
import os
import re
import sys

import torch

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "..", "training"))
from pllvo_nets.safetensors_io import load_safetensors  # noqa: E402


def released_name(name):
    m = re.match(r"^transformers\.(\d+)\.(self_attn|cross_attn)\.(.*)$", name)
    return f"{m.group(2)}.{m.group(1)}.{m.group(3)}" if m else name


tensors, _ = load_safetensors(sys.argv[1])
state = {released_name(k): torch.from_numpy(v).float() for k, v in tensors.items() if k != "confidence_thresholds"}
torch.save(state, sys.argv[2])
