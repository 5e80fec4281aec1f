#!/usr/bin/env python3
"""Checks pllvo's PyTorch reference networks (training/pllvo_nets) against the official
test vectors in ../shared/testvectors, with the tolerances of their READMEs.

    python3 training/check_nets.py [--shared ../shared]

Exit status 0 when every check passes; one line per check either way.
"""
import argparse
import json
import os
import sys

import numpy as np
import torch

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from pllvo_nets.image_io import read_png  # noqa: E402
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict  # noqa: E402
from pllvo_nets.safetensors_io import load_safetensors  # noqa: E402
from pllvo_nets.superpoint import SuperPoint  # noqa: E402

failures = []


def check(name, ok, detail=""):
    print(f"{'ok  ' if ok else 'FAIL'} {name} {detail}")
    if not ok:
        failures.append(name)


def max_abs(a, b):
    a, b = np.asarray(a, dtype=np.float64), np.asarray(b, dtype=np.float64)
    return float(np.abs(a - b).max()) if a.size else 0.0


def check_superpoint(root):
    sp_dir = os.path.join(root, "testvectors", "superpoint")
    weights, _ = load_safetensors(os.path.join(sp_dir, "superpoint_random_weights.safetensors"))
    images = ["icl250_640x480", "icl254_640x480", "sacre_coeur1_752x480", "sacre_coeur2_752x480"]
    for image in images:
        gray = torch.from_numpy(read_png(os.path.join(sp_dir, image + ".png"))).float() / 255
        for config in ["dense", "kall", "k512"]:
            path = os.path.join(sp_dir, f"{image}_{config}.safetensors")
            if not os.path.exists(path):
                continue
            ref, _ = load_safetensors(path)
            net = SuperPoint(max_num_keypoints=512 if config == "k512" else None).eval()
            net.load_state_dict({k: torch.from_numpy(v.astype(np.float32)) for k, v in weights.items()})
            with torch.no_grad():
                out = net(gray[None, None])
            tag = f"superpoint {image} {config}"
            if config == "dense":
                e = max_abs(ref["scores_dense"], out["scores_dense"][0])
                check(tag + " scores_dense", e <= 1e-4, f"max abs {e:.2e}")
                sub = out["descriptors_dense"][0][ref["descriptors_dense_channels"]]
                e = max_abs(ref["descriptors_dense_sub"], sub)
                check(tag + " descriptors_dense_sub", e <= 1e-4, f"max abs {e:.2e}")
                continue
            kp = out["keypoints"][0].numpy()
            order = order_within_ties(ref["keypoints"], ref["keypoint_scores"], kp)
            check(tag + " keypoints (set, and order up to ties)", order is not None,
                  f"{len(kp)} vs {len(ref['keypoints'])}")
            if order is not None:
                e = max_abs(ref["keypoint_scores"][order], out["keypoint_scores"][0])
                check(tag + " keypoint_scores", e <= 1e-5, f"max abs {e:.2e}")
                e = max_abs(ref["descriptors"][order], out["descriptors"][0])
                check(tag + " descriptors", e <= 1e-4, f"max abs {e:.2e}")


# Two keypoints whose official scores differ by less than this may come out in either order: the
# softmax's last bits depend on the CPU's convolution kernels (seen: 1.05e-8 apart on an AMD EPYC,
# sacre_coeur1 k512 ranks 407/408, swapped there both by PyTorch and by the C++ port).
SCORE_TIE = 1e-7


def order_within_ties(ref_kp, ref_scores, kp):
    """Index into the reference for each of our keypoints, or None when the sets differ or an
    order differs by more than a tie."""
    if kp.shape != ref_kp.shape:
        return None
    where = {tuple(p): j for j, p in enumerate(ref_kp.tolist())}
    order = []
    for i, p in enumerate(kp.tolist()):
        j = where.get(tuple(p))
        if j is None or abs(float(ref_scores[i]) - float(ref_scores[j])) > SCORE_TIE:
            return None
        order.append(j)
    return np.array(order) if len(set(order)) == len(order) else None


def check_lightglue(root):
    lg_dir = os.path.join(root, "testvectors", "lightglue")
    base, _ = load_safetensors(os.path.join(lg_dir, "lightglue_sp_random_l9_d256.safetensors"))
    override, _ = load_safetensors(os.path.join(lg_dir, "lightglue_sp_random_l9_d256_b_token_confidence.safetensors"))
    small, _ = load_safetensors(os.path.join(lg_dir, "lightglue_random_l3_d64.safetensors"))
    weights = {"a": base, "b": {**base, **override}, "c": small}
    for setting in "abc":
        for pair in "AB":
            ref, meta = load_safetensors(os.path.join(lg_dir, f"{setting}_pair{pair}.safetensors"))
            conf = json.loads(meta["conf"])
            state = {k: torch.from_numpy(v.astype(np.float32)) for k, v in weights[setting].items()}
            net = LightGlue(
                **lightglue_conf_from_state_dict(state),
                depth_confidence=conf["depth_confidence"],
                width_confidence=conf["width_confidence"],
                filter_threshold=conf["filter_threshold"],
                pruning_keypoint_threshold=-1,
            ).eval()
            net.load_state_dict(state)
            data = []
            for key in ("image0", "image1"):
                f, _ = load_safetensors(os.path.join(root, "testvectors", meta[key]))
                data.append({
                    "keypoints": torch.from_numpy(f["keypoints"])[None],
                    "descriptors": torch.from_numpy(f["descriptors"])[None],
                    "image_size": torch.from_numpy(f["image_size"]).float()[None],
                })
            trace = {}
            with torch.no_grad():
                out = net(data[0], data[1], trace=trace)
            tag = f"lightglue {setting} pair{pair}"
            check(tag + " stop", out["stop"] == int(ref["stop"][0]), f"{out['stop']} vs {int(ref['stop'][0])}")
            for key in ("matches0", "matches1", "prune0", "prune1", "matches"):
                ok = tuple(out[key].shape) == ref[key].shape and (out[key].numpy() == ref[key]).all()
                check(f"{tag} {key}", ok)
            for key in ("matching_scores0", "matching_scores1", "scores"):
                e = max_abs(ref[key], out[key]) if tuple(out[key].shape) == ref[key].shape else np.inf
                check(f"{tag} {key}", e <= 1e-4, f"max abs {e:.2e}")
            la = trace["log_assignment"].numpy()
            if "log_assignment" in ref:
                excess = float((np.abs(ref["log_assignment"] - la) - 1e-5 * np.abs(ref["log_assignment"])).max())
                check(tag + " log_assignment", excess <= 1e-3, f"max abs - 1e-5|ref| {excess:.2e}")
            if "log_assignment_rows" in ref:
                rows = la[ref["log_assignment_row_index"]]
                excess = float((np.abs(ref["log_assignment_rows"] - rows) - 1e-5 * np.abs(ref["log_assignment_rows"])).max())
                check(tag + " log_assignment_rows", excess <= 1e-3, f"max abs - 1e-5|ref| {excess:.2e}")
            if "posenc0_first256" in ref:
                for side in "01":
                    e = max_abs(ref["posenc" + side + "_first256"], trace["posenc" + side][:, 0, 0, :256])
                    check(f"{tag} posenc{side}_first256", e <= 1e-4, f"max abs {e:.2e}")
                    e = max_abs(ref[f"desc{side}_after_layer0"], trace[f"desc{side}_after_layer0"])
                    check(f"{tag} desc{side}_after_layer0", e <= 1e-4, f"max abs {e:.2e}")


def check_lightglue_training_path(root):
    """forward_train on a padded batch gives the same last-layer log-assignment as forward."""
    lg_dir = os.path.join(root, "testvectors", "lightglue")
    state = {k: torch.from_numpy(v.astype(np.float32))
             for k, v in load_safetensors(os.path.join(lg_dir, "lightglue_random_l3_d64.safetensors"))[0].items()}
    net = LightGlue(**lightglue_conf_from_state_dict(state), depth_confidence=-1, width_confidence=-1).eval()
    net.load_state_dict(state)
    feats = []
    for name in ("icl250_640x480_k512", "icl254_640x480_k512"):
        f, _ = load_safetensors(os.path.join(root, "testvectors", "superpoint", name + ".safetensors"))
        feats.append({"keypoints": torch.from_numpy(f["keypoints"])[None], "descriptors": torch.from_numpy(f["descriptors"])[None],
                      "image_size": torch.from_numpy(f["image_size"]).float()[None]})
    trace = {}
    net(feats[0], feats[1], trace=trace)
    # Batch of two: the pair itself, and the pair with image 0 cut to 400 points (padded back to 512).
    m, n = 512, 512
    batch = [{k: torch.cat([f[k], f[k]]) for k in f} for f in feats]
    mask0 = torch.ones(2, m, dtype=torch.bool)
    mask0[1, 400:] = False
    mask1 = torch.ones(2, n, dtype=torch.bool)
    out = net.forward_train(batch[0], batch[1], mask0, mask1)
    last = out["log_assignment"][-1]
    e = max_abs(trace["log_assignment"], last[0])
    check("lightglue forward_train = forward (batch item 0)", e <= 1e-3, f"max abs {e:.2e}")
    cut = {k: (v[:, :400] if k != "image_size" else v) for k, v in feats[0].items()}
    trace_cut = {}
    net(cut, feats[1], trace=trace_cut)
    ref = trace_cut["log_assignment"]
    ours = torch.cat([last[1, :400, : n + 1], last[1, m : m + 1, : n + 1]])  # real rows + dustbin row
    e = max_abs(ref, ours)
    check("lightglue forward_train padded item = forward on the unpadded pair", e <= 1e-3, f"max abs {e:.2e}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    parser.add_argument("--shared", default=os.environ.get("PLLVO_SHARED", os.path.join(here, "..", "..", "shared")))
    args = parser.parse_args()
    torch.set_grad_enabled(False)
    check_superpoint(args.shared)
    check_lightglue(args.shared)
    check_lightglue_training_path(args.shared)
    print(f"{len(failures)} failed" if failures else "all checks passed")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
