"""pllvo: point-line visual odometry (SuperPoint, LightGlue, EDLines, sliding-window bundle adjustment).

    import pllvo
    odometry = pllvo.Odometry(pllvo.Calibration.load("camera.yaml"))
    result = odometry.track(timestamp, image)        # uint8 (H, W) gray or (H, W, 3) BGR
    result.T_world_cam0                              # numpy 4x4
    odometry.finish(); odometry.save("out")          # what `pllvo run --out` writes

    stats = pllvo.run("dataset_folder", out="out")   # `pllvo run`, stats.json as a dict
    ape = pllvo.evaluate("out/trajectory.tum", "groundtruth.tum", metric="ape", align="se3")

Bad input raises pllvo.InputError (a ValueError) with pllvo's message; wrong array dtypes raise TypeError.
"""
from pathlib import Path as _Path

from ._pllvo import CameraIntrinsics, Calibration, Dataset, InputError, TrackResult
from ._pllvo import Odometry as _Odometry
from ._pllvo import evaluate
from ._pllvo import run as _run

__all__ = ["CameraIntrinsics", "Calibration", "Dataset", "InputError", "TrackResult", "Odometry", "run", "evaluate"]


def _installed_models_dir():
    """<prefix>/share/pllvo/models when this package is the installed one (<prefix>/lib/pllvo/python/pllvo)."""
    here = _Path(__file__).resolve().parent
    if len(here.parents) < 4:
        return ""
    candidate = here.parents[3] / "share" / "pllvo" / "models"
    return str(candidate) if candidate.is_dir() else ""


def Odometry(calibration, config="", overrides=None, stereo=True, single_thread=False, live=False, models_dir=None):
    """The odometry for `calibration`; `config`: a VO YAML; `overrides`: {"dotted.key": value}."""
    return _Odometry(calibration, config=str(config), overrides=dict(overrides or {}), stereo=stereo,
                     single_thread=single_thread, live=live,
                     models_dir=str(models_dir) if models_dir else _installed_models_dir())


def run(dataset, out="", config="", overrides=None, mono=False, single_thread=False, first=0, max_frames=0,
        realtime=False, speed=1.0, format="auto", camera="", models_dir=None):
    """`pllvo run DATASET`: returns stats.json as a dict; writes the run's files to `out` when given."""
    return _run(str(dataset), out=str(out), config=str(config), overrides=dict(overrides or {}), mono=mono,
                single_thread=single_thread, first=first, max_frames=max_frames, realtime=realtime, speed=speed,
                format=format, camera=str(camera),
                models_dir=str(models_dir) if models_dir else _installed_models_dir())
