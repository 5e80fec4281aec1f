"""Training configuration: one dataclass per stage, named presets, and `section.key=value` overrides.

Presets:
  cpu-small  ~2 h on 2 CPU cores (120x160 everywhere, short schedules): useful progress, not converged.
  gpu        closer to the paper's schedules (MagicPoint at 120x160, adaptation and joint training at
             240x320, 100 homographies); meant for one GPU.
  gpu-short  the gpu schedules cut to fixed training times (shapes 3 min, joint 3.5 min): fits one
             10-minute call on a lent GPU machine (an H200 with 16 cores: the CPU workers rendering batches
             are the limit, not the GPU).
  smoke      seconds-long runs on tiny images for the smoke test.
"""
import ast
import copy
import dataclasses
import json
import math
from dataclasses import dataclass, field

from superpoint.data_sources import DataConfig
from superpoint.homographies import HomographyParams
from superpoint.losses import DescriptorLossParams
from superpoint.photometric import DarkeningParams, PhotometricParams


@dataclass
class ShapesConfig:
    height: int = 120
    width: int = 160
    batch: int = 16
    steps: int = 2500
    lr: float = 1e-3
    photometric: PhotometricParams = field(default_factory=lambda: PhotometricParams(p_dark=0.2, dark=DarkeningParams()))
    fixed_data: bool = False       # the same batch every step (smoke test: checks that the loss can decrease)
    minutes: float = 0.0           # > 0: the stage trains for this long (summed over resumes) instead of `steps`


@dataclass
class AdaptationConfig:
    """Runs at the joint stage's resolution (the pseudo labels are its training targets)."""
    homographies: int = 32         # paper: 100
    batch: int = 8                 # warped copies per forward pass
    threshold: float = 0.015
    nms_radius: int = 4
    border: int = 4
    valid_margin: int = 3          # ignore responses this close to the border of each warped image
    homography: HomographyParams = field(default_factory=lambda: HomographyParams(max_angle=math.pi / 4))
    max_items: int = 0             # 0: all items
    min_mean_points: float = 5.0   # stop before stage 3 if the crops get fewer pseudo points than this on average


@dataclass
class JointConfig:
    height: int = 120
    width: int = 160
    batch: int = 4                 # image pairs per step
    steps: int = 4000
    lr: float = 1e-3
    lambda_loss: float = 1e-4      # weight of the descriptor loss (paper: 0.0001)
    descriptor: DescriptorLossParams = field(default_factory=DescriptorLossParams)
    homography: HomographyParams = field(default_factory=lambda: HomographyParams(max_angle=math.pi / 6))
    photometric: PhotometricParams = field(default_factory=lambda: PhotometricParams(dark=DarkeningParams()))
    init_from_shapes: bool = True  # start from the MagicPoint weights (the paper trains SuperPoint from scratch)
    fixed_data: bool = False
    minutes: float = 0.0           # > 0: the stage trains for this long (summed over resumes) instead of `steps`


@dataclass
class TrainConfig:
    preset: str = "cpu-small"
    seed: int = 0
    checkpoint_every: int = 100
    log_every: int = 10
    workers: int = 0               # processes making batches (0: in the training process)
    shapes: ShapesConfig = field(default_factory=ShapesConfig)
    adaptation: AdaptationConfig = field(default_factory=AdaptationConfig)
    joint: JointConfig = field(default_factory=JointConfig)
    data: DataConfig = field(default_factory=DataConfig)


def preset(name):
    config = TrainConfig(preset=name)
    if name == "cpu-small":
        return config
    if name == "gpu":
        config.checkpoint_every = 1000
        config.log_every = 100
        config.workers = 8
        config.shapes.batch, config.shapes.steps = 64, 60000
        config.adaptation.homographies, config.adaptation.batch = 100, 50
        config.joint.height, config.joint.width = 240, 320
        config.joint.batch, config.joint.steps = 16, 100000
        return config
    if name == "gpu-short":
        config = preset("gpu")
        config.preset = name
        config.checkpoint_every = 500
        config.workers = 14
        config.shapes.minutes, config.joint.minutes = 3.0, 3.5
        return config
    if name == "smoke":
        config.checkpoint_every = 10
        config.log_every = 5
        config.shapes = ShapesConfig(height=48, width=64, batch=4, steps=40, fixed_data=True)
        config.adaptation = AdaptationConfig(homographies=6, batch=6, threshold=0.01, max_items=3, min_mean_points=0.0)
        config.joint = JointConfig(height=48, width=64, batch=2, steps=40, fixed_data=True)
        return config
    raise ValueError(f"unknown preset {name!r} (cpu-small, gpu, gpu-short, smoke)")


def apply_override(config, assignment):
    """'joint.steps=500' or 'joint.homography.max_angle=0.3' -> sets the field (value parsed as a Python literal)."""
    if "=" not in assignment:
        raise ValueError(f"override {assignment!r} is not key=value")
    key, text = assignment.split("=", 1)
    *path, last = key.strip().split(".")
    target = config
    for name in path:
        if not hasattr(target, name):
            raise ValueError(f"override {assignment!r}: no section {name!r}")
        target = getattr(target, name)
    if not dataclasses.is_dataclass(target) or last not in {f.name for f in dataclasses.fields(target)}:
        raise ValueError(f"override {assignment!r}: unknown key {key!r}")
    try:
        value = ast.literal_eval(text)
    except (ValueError, SyntaxError):
        value = text
    setattr(target, last, value)
    return config


def build_config(preset_name, overrides=()):
    config = preset(preset_name)
    for assignment in overrides:
        apply_override(config, assignment)
    return config


def to_dict(config):
    return dataclasses.asdict(copy.deepcopy(config))


def to_json(config):
    return json.dumps(to_dict(config), sort_keys=True)
