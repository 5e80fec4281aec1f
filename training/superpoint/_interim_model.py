"""Stand-in for training/pllvo_nets/superpoint.py until the nn branch lands on main.

Same architecture and state-dict names as the official SuperPoint (conv1a.weight ... convDb.bias),
and the entry point the training code uses, as in pllvo_nets.superpoint: dense([B,1,H,W] in [0,1]) returns
the raw detector logits [B,65,H/8,W/8] and the raw (not normalised) descriptor map [B,256,H/8,W/8].
Delete this file once pllvo_nets.superpoint is merged; network.py prefers that module already.
"""
import torch
from torch import nn


class SuperPoint(nn.Module):
    _ENCODER = [("conv1a", 1, 64), ("conv1b", 64, 64), ("conv2a", 64, 64), ("conv2b", 64, 64),
                ("conv3a", 64, 128), ("conv3b", 128, 128), ("conv4a", 128, 128), ("conv4b", 128, 128)]

    def __init__(self):
        super().__init__()
        for name, cin, cout in self._ENCODER:
            setattr(self, name, nn.Conv2d(cin, cout, 3, padding=1))
        self.convPa = nn.Conv2d(128, 256, 3, padding=1)
        self.convPb = nn.Conv2d(256, 65, 1)
        self.convDa = nn.Conv2d(128, 256, 3, padding=1)
        self.convDb = nn.Conv2d(256, 256, 1)

    def dense(self, image: torch.Tensor):
        x = image
        for i, (name, _, _) in enumerate(self._ENCODER):
            x = torch.relu(getattr(self, name)(x))
            if i in (1, 3, 5):
                x = nn.functional.max_pool2d(x, 2, 2)
        logits = self.convPb(torch.relu(self.convPa(x)))
        descriptors = self.convDb(torch.relu(self.convDa(x)))
        return logits, descriptors
