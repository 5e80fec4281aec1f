"""Exports trained weights to safetensors with the official SuperPoint tensor names (conv1a.weight ...
convDb.bias), so that the C++ port loads them unchanged, plus metadata: stages, steps, time, device,
data, configuration, licence."""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import argparse
import datetime
import json
import platform
from pathlib import Path

import torch

from superpoint.network import OFFICIAL_NAMES, build_superpoint, read_weights
from superpoint.safetensors_io import read_safetensors, write_safetensors
from superpoint.trainer import load_state

LICENCE = ("pllvo's own weights, under the pllvo project's licence; trained only on generated images, "
           "Debian mate-backgrounds photographs (GPL-2+) and the real images listed in 'data' (see docs/superpoint_training.md)")


def _stage_summary(checkpoint_path):
    if not Path(checkpoint_path).is_file():
        return None
    state = load_state(checkpoint_path)
    return {"steps": state["step"], "finished": state.get("finished", False), "elapsed_s": round(state.get("elapsed_s", 0.0)),
            "device": state.get("device", "?"), "data": state.get("data")}


def export(checkpoint, output, fp16=True, extra_metadata=None):
    """Writes `output` from a joint (or any) checkpoint; returns the metadata written."""
    checkpoint = Path(checkpoint)
    state = read_weights(checkpoint)
    missing = set(OFFICIAL_NAMES) - set(state)
    if missing or len(state) != len(OFFICIAL_NAMES):
        raise ValueError(f"{checkpoint}: not a SuperPoint state dict (missing {sorted(missing)})")
    build_superpoint().load_state_dict(state)        # shapes must match the architecture
    dtype = torch.float16 if fp16 else torch.float32
    tensors = {name: state[name].to(dtype) for name in OFFICIAL_NAMES}
    run_dir = checkpoint.parent.parent
    meta = {"format": "pllvo SuperPoint weights v1",
            "architecture": "SuperPoint (DeTone et al. 2018), official layout and tensor names, no batch norm",
            "input": "grey image, float in [0,1], [B,1,H,W], H and W multiples of 8",
            "outputs": "detector logits [B,65,H/8,W/8] (softmax, dustbin last), descriptors [B,256,H/8,W/8] (L2-normalise)",
            "precision": "F16" if fp16 else "F32",
            "licence": LICENCE,
            "created": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
            "host": f"{platform.node()} {platform.machine()} torch {torch.__version__}",
            "source_checkpoint": str(checkpoint)}
    if checkpoint.suffix == ".pt":
        full = load_state(checkpoint)
        meta["config"] = json.dumps(full.get("config", {}), sort_keys=True)
        stages = {name: _stage_summary(run_dir / name / "checkpoint.pt") for name in ("shapes", "joint")}
        meta["stages"] = json.dumps({k: v for k, v in stages.items() if v}, sort_keys=True)
        if full.get("data"):
            meta["data"] = json.dumps(full["data"], sort_keys=True)
    meta.update(extra_metadata or {})
    write_safetensors(output, tensors, meta)
    # Read back: names, shapes and values must survive the round trip (up to the fp16 rounding).
    back, _ = read_safetensors(output)
    for name in OFFICIAL_NAMES:
        if not torch.allclose(back[name].float(), state[name], rtol=1e-3, atol=1e-4 if fp16 else 0):
            raise RuntimeError(f"{output}: tensor {name} did not survive the export")
    return meta


def main():
    p = argparse.ArgumentParser(description=__doc__)
    p.add_argument("checkpoint", help="training checkpoint (.pt), e.g. out/sptrain/cpu-small/joint/checkpoint.pt")
    p.add_argument("output", help="e.g. models/pllvo_superpoint_v1.safetensors")
    p.add_argument("--fp32", action="store_true", help="keep float32 (default: float16)")
    p.add_argument("--note", default=None, help="free text stored as metadata 'note' (hardware, duration, ...)")
    args = p.parse_args()
    meta = export(args.checkpoint, args.output, fp16=not args.fp32, extra_metadata={"note": args.note} if args.note else None)
    print(f"wrote {args.output} ({Path(args.output).stat().st_size} bytes, {meta['precision']})")


if __name__ == "__main__":
    main()
