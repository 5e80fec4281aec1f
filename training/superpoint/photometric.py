"""Photometric changes for training pairs and for the low-light benchmark: brightness, contrast, gamma,
Gaussian noise, Gaussian and motion blur, and strong darkening with a sensor noise model (Poisson shot
noise, Gaussian read noise, 8-bit quantisation, optional digital gain), since low light is PLL-VO's point.
All functions take and return float32 [H,W] images in [0,1]."""
from dataclasses import dataclass

import cv2
import numpy as np


@dataclass
class PhotometricParams:
    p_brightness: float = 0.5
    brightness: float = 0.2            # additive, U(-b, b)
    p_contrast: float = 0.5
    contrast: tuple = (0.5, 1.5)       # multiplicative about the mean
    p_gamma: float = 0.3
    gamma: tuple = (0.5, 2.0)          # log-uniform exponent
    p_noise: float = 0.5
    noise_std: tuple = (0.0, 0.04)
    p_blur: float = 0.2
    blur_sigma: tuple = (0.3, 1.5)
    p_motion_blur: float = 0.15
    motion_blur_length: tuple = (3, 9)
    p_dark: float = 0.35
    dark: "DarkeningParams" = None


@dataclass
class DarkeningParams:
    factor: tuple = (0.02, 0.25)       # exposure relative to the original, log-uniform
    photons: tuple = (300.0, 3000.0)   # electrons at full scale before darkening, log-uniform
    read_noise: tuple = (0.5 / 255, 3.0 / 255)
    p_gain: float = 0.5                # probability that a digital gain brings the mean back up (high ISO)


def _log_uniform(rng, bounds):
    return float(np.exp(rng.uniform(np.log(bounds[0]), np.log(bounds[1]))))


def darken(image, rng, params=DarkeningParams(), gain=None):
    """Simulates a short exposure: fewer photons (shot noise), read noise, 8-bit quantisation; with a
    digital gain, the quantised dark image is amplified back (noisy, banded), as auto-gain cameras do."""
    factor = _log_uniform(rng, params.factor)
    photons = _log_uniform(rng, params.photons)
    electrons = rng.poisson(np.clip(image, 0, 1) * factor * photons).astype(np.float32)
    signal = electrons / photons + rng.normal(0, rng.uniform(*params.read_noise), image.shape).astype(np.float32)
    signal = np.round(np.clip(signal, 0, 1) * 255) / 255
    if gain is None:
        gain = rng.uniform() < params.p_gain
    if gain:
        signal = signal * min(0.45 / max(float(signal.mean()), 1e-3), 1.0 / factor)
    return np.clip(signal, 0, 1).astype(np.float32)


def motion_blur(image, rng, length):
    kernel = np.zeros((length, length), np.float32)
    kernel[length // 2] = 1.0 / length
    rotation = cv2.getRotationMatrix2D(((length - 1) / 2, (length - 1) / 2), rng.uniform(0, 180), 1.0)
    kernel = cv2.warpAffine(kernel, rotation, (length, length))
    return cv2.filter2D(image, -1, kernel / max(kernel.sum(), 1e-6))


def augment(image, rng, params=PhotometricParams()):
    """A random chain of photometric changes; the darkening, when drawn, comes last (it is the sensor)."""
    out = image.astype(np.float32)
    if rng.uniform() < params.p_brightness:
        out = out + rng.uniform(-params.brightness, params.brightness)
    if rng.uniform() < params.p_contrast:
        mean = float(out.mean())
        out = (out - mean) * rng.uniform(*params.contrast) + mean
    out = np.clip(out, 0, 1)
    if rng.uniform() < params.p_gamma:
        out = out ** _log_uniform(rng, params.gamma)
    if rng.uniform() < params.p_blur:
        out = cv2.GaussianBlur(out, (0, 0), rng.uniform(*params.blur_sigma))
    if rng.uniform() < params.p_motion_blur:
        out = motion_blur(out, rng, int(rng.integers(params.motion_blur_length[0], params.motion_blur_length[1] + 1)))
    if rng.uniform() < params.p_dark:
        return darken(out, rng, params.dark or DarkeningParams())
    if rng.uniform() < params.p_noise:
        out = out + rng.normal(0, rng.uniform(*params.noise_std), out.shape).astype(np.float32)
    return np.clip(out, 0, 1).astype(np.float32)
