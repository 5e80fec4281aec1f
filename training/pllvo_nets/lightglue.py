"""LightGlue (Lindenberger, Sarlin, Pollefeys: "LightGlue: Local Feature Matching at
Light Speed", ICCV 2023), written for pllvo.

Parameter names are those of the official `LightGlue.state_dict()` after its loader's
renaming (`transformers.{i}.self_attn...`), so weights move unchanged between this module,
the official code and pllvo's C++ port (src/pllvo/nn/lightglue.cpp). Checked against
../shared/testvectors/lightglue.

* `LightGlue.forward(data)` is inference on one pair (batch 1) with adaptive depth (early
  exit) and adaptive width (point pruning), as the official code runs on a CPU.
* `LightGlue.forward_train(data)` runs every layer on a batch (optionally with padding
  masks) and returns what the LightGlue losses need: the log-assignment of every layer
  (deep supervision) and the token confidences.
"""
import numpy as np
import torch
import torch.nn.functional as F
from torch import nn


def normalize_keypoints(kpts, size):
    """[B, N, 2] pixels -> centred, divided by half the longer image side. size: [B, 2] (W, H)."""
    size = size.to(kpts)
    return (kpts - size[:, None] / 2) / (size.max(-1).values / 2)[:, None, None]


def rotate_half(x):
    """Adjacent feature pairs (a, b) -> (-b, a)."""
    x = x.unflatten(-1, (-1, 2))
    return torch.stack((-x[..., 1], x[..., 0]), -1).flatten(-2)


def apply_rotary(encoding, x):
    """encoding [2, B, 1, N, dh] (cos, sin); x [B, H, N, dh]."""
    return x * encoding[0] + rotate_half(x) * encoding[1]


class FourierPositionalEncoding(nn.Module):
    """Learnable Fourier features of keypoint positions, used as rotary encodings."""

    def __init__(self, in_dim, head_dim):
        super().__init__()
        self.Wr = nn.Linear(in_dim, head_dim // 2, bias=False)
        nn.init.normal_(self.Wr.weight, mean=0.0, std=1.0)

    def forward(self, x):
        """x [B, N, in_dim] -> [2, B, 1, N, head_dim]: cos and sin, each frequency twice."""
        p = self.Wr(x)
        return torch.stack([p.cos(), p.sin()], 0).unsqueeze(-3).repeat_interleave(2, dim=-1)


def attention(q, k, v, mask=None):
    """Scaled dot-product attention on [B, H, N, dh]."""
    sim = torch.einsum("...id,...jd->...ij", q, k) * q.shape[-1] ** -0.5
    if mask is not None:
        sim = sim.masked_fill(~mask, -float("inf"))
        return torch.einsum("...ij,...jd->...id", sim.softmax(-1), v).nan_to_num()  # padded rows -> 0
    return torch.einsum("...ij,...jd->...id", sim.softmax(-1), v)


def feed_forward(dim):
    """Linear(2d, 2d) - LayerNorm - GELU (exact) - Linear(2d, d): indices 0, 1, 3 hold weights."""
    return nn.Sequential(nn.Linear(2 * dim, 2 * dim), nn.LayerNorm(2 * dim), nn.GELU(), nn.Linear(2 * dim, dim))


class SelfBlock(nn.Module):
    def __init__(self, dim, heads):
        super().__init__()
        self.heads = heads
        self.Wqkv = nn.Linear(dim, 3 * dim)  # output features interleave q, k, v: h*3*dh + j*3 + s
        self.out_proj = nn.Linear(dim, dim)
        self.ffn = feed_forward(dim)

    def forward(self, x, encoding, mask=None):
        qkv = self.Wqkv(x).unflatten(-1, (self.heads, -1, 3)).transpose(1, 2)  # [B, H, N, dh, 3]
        q, k, v = qkv[..., 0], qkv[..., 1], qkv[..., 2]
        q, k = apply_rotary(encoding, q), apply_rotary(encoding, k)
        context = attention(q, k, v, mask)
        message = self.out_proj(context.transpose(1, 2).flatten(-2))
        return x + self.ffn(torch.cat([x, message], -1))


class CrossBlock(nn.Module):
    def __init__(self, dim, heads):
        super().__init__()
        self.heads = heads
        self.scale = (dim // heads) ** -0.5
        self.to_qk = nn.Linear(dim, dim)  # shared for queries and keys: the similarity is symmetric
        self.to_v = nn.Linear(dim, dim)
        self.to_out = nn.Linear(dim, dim)
        self.ffn = feed_forward(dim)

    def forward(self, x0, x1, mask=None):
        def heads(t):
            return t.unflatten(-1, (self.heads, -1)).transpose(1, 2)

        qk0, qk1 = heads(self.to_qk(x0)) * self.scale**0.5, heads(self.to_qk(x1)) * self.scale**0.5
        v0, v1 = heads(self.to_v(x0)), heads(self.to_v(x1))
        sim = torch.einsum("bhid,bhjd->bhij", qk0, qk1)
        if mask is not None:
            sim = sim.masked_fill(~mask, -float("inf"))
        m0 = torch.einsum("bhij,bhjd->bhid", sim.softmax(-1), v1)
        m1 = torch.einsum("bhij,bhid->bhjd", sim.softmax(-2), v0)
        if mask is not None:
            m0, m1 = m0.nan_to_num(), m1.nan_to_num()
        m0, m1 = self.to_out(m0.transpose(1, 2).flatten(-2)), self.to_out(m1.transpose(1, 2).flatten(-2))
        return x0 + self.ffn(torch.cat([x0, m0], -1)), x1 + self.ffn(torch.cat([x1, m1], -1))


class TransformerLayer(nn.Module):
    def __init__(self, dim, heads):
        super().__init__()
        self.self_attn = SelfBlock(dim, heads)
        self.cross_attn = CrossBlock(dim, heads)

    def forward(self, desc0, desc1, enc0, enc1, mask0=None, mask1=None, mask01=None):
        desc0 = self.self_attn(desc0, enc0, mask0)
        desc1 = self.self_attn(desc1, enc1, mask1)
        return self.cross_attn(desc0, desc1, mask01)


def log_double_softmax(sim, z0, z1):
    """[B, M, N] similarities and [B, M, 1], [B, N, 1] matchability logits ->
    [B, M+1, N+1] log-assignment: dual softmax + matchability, dustbins from 1 - sigmoid(z)."""
    b, m, n = sim.shape
    scores = sim.new_zeros((b, m + 1, n + 1))
    scores[:, :m, :n] = (
        F.log_softmax(sim, 2) + F.log_softmax(sim, 1) + F.logsigmoid(z0) + F.logsigmoid(z1).transpose(1, 2)
    )
    scores[:, :m, n] = F.logsigmoid(-z0.squeeze(-1))
    scores[:, m, :n] = F.logsigmoid(-z1.squeeze(-1))
    return scores


class MatchAssignment(nn.Module):
    def __init__(self, dim):
        super().__init__()
        self.matchability = nn.Linear(dim, 1)
        self.final_proj = nn.Linear(dim, dim)

    def forward(self, desc0, desc1, mask=None):
        """mask [B, M, N] (True: both points real) keeps padding out of the softmaxes; padded
        entries of the result are -inf."""
        d = desc0.shape[-1]
        md0, md1 = self.final_proj(desc0) / d**0.25, self.final_proj(desc1) / d**0.25
        sim = torch.einsum("bmd,bnd->bmn", md0, md1)
        if mask is not None:
            sim = sim.masked_fill(~mask, -float("inf"))
        scores = log_double_softmax(sim, self.matchability(desc0), self.matchability(desc1))
        if mask is not None:
            scores = torch.where(torch.isnan(scores), scores.new_tensor(-float("inf")), scores)
        return scores, sim

    def matchability_prob(self, desc):
        return torch.sigmoid(self.matchability(desc)).squeeze(-1)


class TokenConfidence(nn.Module):
    def __init__(self, dim):
        super().__init__()
        self.token = nn.Sequential(nn.Linear(dim, 1), nn.Sigmoid())

    def forward(self, desc0, desc1):
        return self.token(desc0.detach()).squeeze(-1), self.token(desc1.detach()).squeeze(-1)


def filter_matches(scores, threshold):
    """Mutual argmax of the inner log-assignment block. Returns matches0 [B, M], matches1
    [B, N] (-1: none), and their scores exp(max), set for every mutual pair, including those
    under the threshold (which are then not matches)."""
    inner = scores[:, :-1, :-1]
    max0, max1 = inner.max(2), inner.max(1)
    m0, m1 = max0.indices, max1.indices
    mutual0 = torch.arange(m0.shape[1], device=m0.device)[None] == m1.gather(1, m0)
    mutual1 = torch.arange(m1.shape[1], device=m1.device)[None] == m0.gather(1, m1)
    zero = scores.new_tensor(0)
    mscores0 = torch.where(mutual0, max0.values.exp(), zero)
    mscores1 = torch.where(mutual1, mscores0.gather(1, m1), zero)
    valid0 = mutual0 & (mscores0 > threshold)
    valid1 = mutual1 & valid0.gather(1, m1)
    return torch.where(valid0, m0, -1), torch.where(valid1, m1, -1), mscores0, mscores1


class LightGlue(nn.Module):
    default_conf = {
        "input_dim": 256,  # descriptor size of the features
        "descriptor_dim": 256,  # transformer width
        "add_scale_ori": False,
        "n_layers": 9,
        "num_heads": 4,
        "filter_threshold": 0.1,
        "depth_confidence": 0.95,  # early exit; <= 0 off
        "width_confidence": 0.99,  # point pruning; <= 0 off
        "pruning_keypoint_threshold": -1,  # prune only while an image has more points (official: -1 on CPU)
    }

    def __init__(self, **conf):
        super().__init__()
        self.conf = conf = {**self.default_conf, **conf}
        d, h, n = conf["descriptor_dim"], conf["num_heads"], conf["n_layers"]
        if conf["input_dim"] != d:
            self.input_proj = nn.Linear(conf["input_dim"], d)
        else:
            self.input_proj = nn.Identity()
        self.posenc = FourierPositionalEncoding(2 + 2 * conf["add_scale_ori"], d // h)
        self.transformers = nn.ModuleList([TransformerLayer(d, h) for _ in range(n)])
        self.log_assignment = nn.ModuleList([MatchAssignment(d) for _ in range(n)])
        self.token_confidence = nn.ModuleList([TokenConfidence(d) for _ in range(n - 1)])
        thresholds = [np.clip(0.8 + 0.1 * np.exp(-4.0 * i / n), 0, 1) for i in range(n)]
        self.register_buffer("confidence_thresholds", torch.Tensor(thresholds))

    def load_state_dict(self, state_dict, strict=True):
        """Accepts the released checkpoints' names (self_attn.{i}., cross_attn.{i}.) too, and
        a missing confidence_thresholds buffer."""
        renamed = {}
        for key, value in state_dict.items():
            parts = key.split(".")
            if parts[0] in ("self_attn", "cross_attn") and parts[1].isdigit():
                key = ".".join(["transformers", parts[1], parts[0]] + parts[2:])
            renamed[key] = value
        renamed.setdefault("confidence_thresholds", self.confidence_thresholds)
        return super().load_state_dict(renamed, strict=strict)

    def encode(self, data0, data1):
        kpts0 = normalize_keypoints(data0["keypoints"], data0["image_size"])
        kpts1 = normalize_keypoints(data1["keypoints"], data1["image_size"])
        if self.conf["add_scale_ori"]:
            kpts0 = torch.cat([kpts0, data0["scales"][..., None], data0["oris"][..., None]], -1)
            kpts1 = torch.cat([kpts1, data1["scales"][..., None], data1["oris"][..., None]], -1)
        desc0 = self.input_proj(data0["descriptors"].contiguous())
        desc1 = self.input_proj(data1["descriptors"].contiguous())
        return desc0, desc1, self.posenc(kpts0), self.posenc(kpts1)

    def forward_train(self, data0, data1, mask0=None, mask1=None):
        """Every layer on a batch. mask0 [B, M], mask1 [B, N]: True for real (not padding)
        points; padding stays out of attention and of the assignment softmaxes (padded pairs
        get -inf; the dustbin entries of padded points are meaningless: leave them out of the
        loss). Returns log_assignment (list over layers of [B, M+1, N+1]) and token0/token1
        (lists over the first n_layers-1 layers)."""
        desc0, desc1, enc0, enc1 = self.encode(data0, data1)
        masks = (None, None, None)
        if mask0 is not None and mask1 is not None:
            masks = (
                (mask0[:, :, None] & mask0[:, None, :])[:, None],
                (mask1[:, :, None] & mask1[:, None, :])[:, None],
                (mask0[:, :, None] & mask1[:, None, :])[:, None],
            )
        out = {"log_assignment": [], "token0": [], "token1": []}
        for i, layer in enumerate(self.transformers):
            desc0, desc1 = layer(desc0, desc1, enc0, enc1, *masks)
            pair_mask = None if masks[2] is None else masks[2][:, 0]
            out["log_assignment"].append(self.log_assignment[i](desc0, desc1, pair_mask)[0])
            if i < len(self.token_confidence):
                token0, token1 = self.token_confidence[i](desc0, desc1)
                out["token0"].append(token0)
                out["token1"].append(token1)
        return out

    def forward(self, data0, data1, trace=None):
        """Inference on one pair (batch 1) with adaptive depth and width.

        data: keypoints [1, N, 2] pixels, descriptors [1, N, input_dim], image_size [1, 2] (W, H).
        Returns matches0/1, matching_scores0/1, matches [K, 2], scores [K], stop (layers run),
        prune0/1 (layers each point went through). `trace` (a dict) receives intermediate values.
        """
        conf = self.conf
        m, n = data0["keypoints"].shape[1], data1["keypoints"].shape[1]
        desc0, desc1, enc0, enc1 = self.encode(data0, data1)
        if trace is not None:
            trace["posenc0"], trace["posenc1"] = enc0, enc1
        early_stop = conf["depth_confidence"] > 0
        pruning = conf["width_confidence"] > 0
        ind0 = torch.arange(m, device=desc0.device)
        ind1 = torch.arange(n, device=desc1.device)
        prune0 = torch.ones(m, dtype=torch.long, device=desc0.device)
        prune1 = torch.ones(n, dtype=torch.long, device=desc1.device)

        i = 0
        for i in range(conf["n_layers"]):
            if desc0.shape[1] == 0 or desc1.shape[1] == 0:
                break
            desc0, desc1 = self.transformers[i](desc0, desc1, enc0, enc1)
            if trace is not None and i == 0:
                trace["desc0_after_layer0"], trace["desc1_after_layer0"] = desc0[0], desc1[0]
            if i == conf["n_layers"] - 1:
                break
            threshold = self.confidence_thresholds[i]
            token0 = token1 = None
            if early_stop:
                token0, token1 = self.token_confidence[i](desc0, desc1)
                # Pruned points count as confident: the denominator is the original m + n.
                unsure = (token0 < threshold).float().sum() + (token1 < threshold).float().sum()
                if 1.0 - unsure / (m + n) > conf["depth_confidence"]:
                    break
            if not pruning:
                continue
            for side in (0, 1):
                desc, token = (desc0, token0) if side == 0 else (desc1, token1)
                if desc.shape[1] <= conf["pruning_keypoint_threshold"]:
                    continue
                keep = self.log_assignment[i].matchability_prob(desc) > 1 - conf["width_confidence"]
                if token is not None:
                    keep |= token <= threshold  # points the layer is unsure about are never pruned
                keep = torch.where(keep[0])[0]
                if side == 0:
                    desc0, enc0, ind0 = desc0[:, keep], enc0[..., keep, :], ind0[keep]
                    prune0[ind0] += 1
                else:
                    desc1, enc1, ind1 = desc1[:, keep], enc1[..., keep, :], ind1[keep]
                    prune1[ind1] += 1

        dev = desc0.device
        out = {
            "matches0": torch.full((m,), -1, dtype=torch.long, device=dev),
            "matches1": torch.full((n,), -1, dtype=torch.long, device=dev),
            "matching_scores0": torch.zeros(m, device=dev),
            "matching_scores1": torch.zeros(n, device=dev),
            "stop": i + 1,
            "prune0": prune0 if pruning else torch.full((m,), conf["n_layers"], dtype=torch.long),
            "prune1": prune1 if pruning else torch.full((n,), conf["n_layers"], dtype=torch.long),
            "matches": torch.zeros((0, 2), dtype=torch.long, device=dev),
            "scores": torch.zeros(0, device=dev),
        }
        if desc0.shape[1] == 0 or desc1.shape[1] == 0:
            return out
        scores, _ = self.log_assignment[i](desc0, desc1)
        if trace is not None:
            trace["log_assignment"] = scores[0]
        m0, m1, s0, s1 = (t[0] for t in filter_matches(scores, conf["filter_threshold"]))
        # Back to the original indices (identity without pruning).
        out["matches0"][ind0] = torch.where(m0 >= 0, ind1[m0.clamp(min=0)], m0)
        out["matches1"][ind1] = torch.where(m1 >= 0, ind0[m1.clamp(min=0)], m1)
        out["matching_scores0"][ind0] = s0
        out["matching_scores1"][ind1] = s1
        valid = torch.where(out["matches0"] >= 0)[0]
        out["matches"] = torch.stack([valid, out["matches0"][valid]], -1)
        out["scores"] = out["matching_scores0"][valid]
        return out


def lightglue_conf_from_state_dict(state_dict):
    """The architecture held by a state dict (the same inference as the C++ loader)."""
    names = set(state_dict)
    d = state_dict["transformers.0.self_attn.out_proj.weight"].shape[0]
    wr = state_dict["posenc.Wr.weight"].shape
    n_layers = 0
    while f"transformers.{n_layers}.self_attn.Wqkv.weight" in names:
        n_layers += 1
    return {
        "input_dim": state_dict["input_proj.weight"].shape[1] if "input_proj.weight" in names else d,
        "descriptor_dim": d,
        "n_layers": n_layers,
        "num_heads": d // (2 * wr[0]),
        "add_scale_ori": wr[1] == 4,
    }


__all__ = ["LightGlue", "filter_matches", "normalize_keypoints", "lightglue_conf_from_state_dict"]
