"""Exports a LightGlue training checkpoint to the safetensors layout pllvo's C++ port loads (the state-dict
names transformers.{i}.self_attn..., log_assignment.{i}..., token_confidence.{i}..., posenc.Wr), fp16 by
default, with the architecture and the training record in the file's metadata.

  /usr/bin/python3 training/lightglue/export.py out/lgtrain/gpu-short/checkpoint.pt models/pllvo_lightglue_v1.safetensors
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import argparse
import datetime
import json
from pathlib import Path

from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict
from pllvo_nets.safetensors_io import save_safetensors
from superpoint.trainer import load_state

SKIPPED = ("confidence_thresholds",)   # a function of n_layers, recomputed by every loader


def export_state(state_dict, target, metadata, fp16=True):
    tensors = {k: (v.half() if fp16 else v.float()) for k, v in state_dict.items() if k not in SKIPPED}
    architecture = lightglue_conf_from_state_dict(tensors)
    LightGlue(**architecture).load_state_dict({k: v.float() for k, v in tensors.items()})  # names and shapes
    meta = {"format": "pllvo-lightglue", "architecture": json.dumps(architecture)}
    meta.update({k: v if isinstance(v, str) else json.dumps(v) for k, v in metadata.items()})
    Path(target).parent.mkdir(parents=True, exist_ok=True)
    save_safetensors(target, tensors, meta)
    return architecture


def export(checkpoint, target, fp16=True, extra=None):
    state = load_state(checkpoint)
    metadata = {
        "licence": "pllvo project licence (trained by pllvo, no third-party weights)",
        "trained_steps": state.get("step"), "training_seconds": round(state.get("elapsed_s", 0.0)),
        "training_device": state.get("device"), "training_config": state.get("config"),
        "exported": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
    }
    metadata.update(extra or {})
    return export_state(state["model"], target, metadata, fp16)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("checkpoint")
    p.add_argument("target")
    p.add_argument("--fp32", action="store_true")
    args = p.parse_args()
    architecture = export(args.checkpoint, args.target, fp16=not args.fp32)
    size = Path(args.target).stat().st_size / 2**20
    print(f"exported {args.target} ({size:.1f} MiB): {architecture}")


if __name__ == "__main__":
    main()
