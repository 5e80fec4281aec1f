"""LightGlue training configuration: one dataclass, named presets, `key=value` overrides (as the
SuperPoint training: superpoint/config.py).

Presets:
  cpu-small  ~2 h on 2 CPU cores: 256 keypoints, batch 4; useful progress, not converged.
  gpu-short  a fixed 6 minutes of training on one GPU with 14 CPU workers making pairs (fits one
             10-minute call on a lent machine with the smoke test and the evaluation).
  smoke      seconds-long run on tiny images for the smoke test.
"""
import dataclasses
import json
import math
from dataclasses import dataclass, field

from superpoint.config import apply_override
from superpoint.data_sources import DataConfig
from superpoint.homographies import HomographyParams
from superpoint.photometric import DarkeningParams, PhotometricParams


@dataclass
class ModelConfig:
    """Recorded in the exported file's metadata; the C++ port infers it from the tensor shapes."""
    n_layers: int = 6              # official: 9; 6 keeps the fp16 file at ~16 MB and keyframes cheaper on a CPU
    descriptor_dim: int = 256
    num_heads: int = 4


@dataclass
class LightGlueTrainConfig:
    preset: str = "cpu-small"
    seed: int = 0
    model: ModelConfig = field(default_factory=ModelConfig)
    superpoint: str = "models/pllvo_superpoint_v1.safetensors"   # frozen feature extractor (repo-relative)
    keypoints: int = 256           # per image
    nms_radius: int = 4
    height: int = 240              # homography pairs: crops of this size (the VO's SuperPoint input is 240x376)
    width: int = 320
    batch: int = 4
    steps: int = 6000
    minutes: float = 0.0           # > 0: train for this long instead of `steps`
    lr: float = 1e-4
    p_synth: float = 0.5           # share of batches made of synthetic-sequence pairs (when packed sequences exist)
    synth_dirs: list = field(default_factory=list)
    synth_max_gap: int = 4         # packed frames apart (make_data_pack keeps every 3rd frame: up to 0.6 s)
    positive_px: float = 3.0
    negative_px: float = 5.0
    nll_balance: float = 0.5
    confidence_weight: float = 1.0
    filter_threshold: float = 0.1
    homography: HomographyParams = field(default_factory=lambda: HomographyParams(max_angle=math.pi / 6))
    photometric: PhotometricParams = field(default_factory=lambda: PhotometricParams(dark=DarkeningParams()))
    synth_photometric: PhotometricParams = field(default_factory=lambda: PhotometricParams(
        p_brightness=0.2, p_contrast=0.2, p_gamma=0.1, p_noise=0.2, p_blur=0.1, p_motion_blur=0.0, p_dark=0.1,
        dark=DarkeningParams()))
    data: DataConfig = field(default_factory=DataConfig)
    checkpoint_every: int = 200
    log_every: int = 20
    workers: int = 0
    validation_pairs: int = 16


def preset(name):
    config = LightGlueTrainConfig(preset=name)
    if name == "cpu-small":
        config.workers = 1
        return config
    if name == "gpu-short":
        config.keypoints, config.batch, config.steps, config.minutes = 512, 32, 200000, 6.0
        config.lr, config.workers, config.checkpoint_every, config.log_every = 2e-4, 14, 1000, 100
        config.validation_pairs = 64
        return config
    if name == "smoke":
        config.model = ModelConfig(n_layers=2, descriptor_dim=64, num_heads=2)
        config.keypoints, config.height, config.width, config.batch, config.steps = 64, 64, 80, 2, 30
        config.checkpoint_every, config.log_every, config.validation_pairs = 10, 5, 2
        config.data.photo_crops = 1
        return config
    raise ValueError(f"unknown preset {name!r} (cpu-small, gpu-short, smoke)")


def build_config(preset_name, overrides=()):
    config = preset(preset_name)
    for assignment in overrides:
        apply_override(config, assignment)
    return config


def to_json(config):
    return json.dumps(dataclasses.asdict(config), sort_keys=True, default=str)
