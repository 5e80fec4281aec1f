"""All stages in order, each resumed where it stopped: synthetic shapes -> homographic adaptation ->
joint training -> export. Rerun the same command to continue after an interruption or a --max-minutes stop.

Long CPU run:  nice -n 19 python3 training/superpoint/pipeline.py --preset cpu-small --max-minutes 125
GPU run:       python3 training/superpoint/pipeline.py --preset gpu --device cuda --threads 8
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import json
import time

from superpoint import homographic_adaptation, train_joint, train_shapes
from superpoint.export import export
from superpoint.trainer import Checkpoint

EXPORT_NAME = "pllvo_superpoint.safetensors"


def run(config, out, device, max_minutes=0.0, log=print):
    """Returns the exported weights path, or None when the time budget stopped the run first."""
    deadline = time.time() + 60 * max_minutes if max_minutes else None

    def remaining():
        return 0.0 if deadline is None else max((deadline - time.time()) / 60, 1e-3)

    out.mkdir(parents=True, exist_ok=True)
    train_shapes.train(config, out, device, remaining(), log)
    if not Checkpoint(out / "shapes").is_finished():
        return None
    labels = homographic_adaptation.run(config, out, device, out / "shapes" / "checkpoint.pt", deadline, log)
    if labels is None:
        return None
    mean_points = json.loads((labels / "manifest.json").read_text())["points_per_crop_mean"]
    if mean_points < config.adaptation.min_mean_points:
        raise RuntimeError(f"homographic adaptation gave {mean_points:.1f} points per crop on average (minimum "
                           f"{config.adaptation.min_mean_points}): the stage-1 detector is too weak; train it longer "
                           f"(--set shapes.steps=...) or lower adaptation.threshold")
    train_joint.train(config, out, device, labels, remaining(), log)
    if not Checkpoint(out / "joint").is_finished():
        return None
    target = out / EXPORT_NAME
    export(out / "joint" / "checkpoint.pt", target, fp16=True)
    log(f"[export] {target}")
    return target


def main():
    from superpoint import cli
    args = cli.parser(__doc__).parse_args()
    config, out, device = cli.setup(args)
    result = run(config, out, device, args.max_minutes)
    print(f"pipeline: {'done, weights in ' + str(result) if result else 'stopped early; rerun the same command to resume'}")


if __name__ == "__main__":
    main()
