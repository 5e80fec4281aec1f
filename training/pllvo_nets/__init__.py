"""pllvo's PyTorch reference networks (SuperPoint, LightGlue) and safetensors I/O.

The modules carry the state-dict names of the official checkpoints (after LightGlue's
renaming), so that weights trained here load unchanged into pllvo's C++ port
(src/pllvo/nn) and vice versa. Validated against ../shared/testvectors by
training/check_nets.py.
"""
from .safetensors_io import load_safetensors, save_safetensors

__all__ = ["load_safetensors", "save_safetensors"]
