"""The trained weights run in the C++ port unchanged: the same keypoints, descriptors and matches from the
Python networks the training uses (training/pllvo_nets) and from `pllvo extract` / `pllvo match`.

  /usr/bin/python3 training/fidelity_test.py build/bin/pllvo

1. pllvo's SuperPoint (models/pllvo_superpoint_v1.safetensors) on three generated images (synthetic shapes,
   a textured scene, a dark noisy copy): identical keypoint sets, descriptors and scores within 1e-4.
2. pllvo's LightGlue (models/pllvo_lightglue_v1.safetensors) on those features: identical matches, stop layer
   and pruning, scores within 1e-3.
3. A random LightGlue exported by training/lightglue/export.py (3 layers, width 64, fp16): the same, so any
   architecture the training may choose loads and computes identically.
Exit status 0 when every check passes; each failure is printed.
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import cv2
import numpy as np
import torch

TRAINING = Path(__file__).resolve().parent
REPO = TRAINING.parent
sys.path.insert(0, str(TRAINING))

from lightglue.export import export_state  # noqa: E402
from pllvo_nets.checks import Checks  # noqa: E402
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict  # noqa: E402
from pllvo_nets.safetensors_io import load_safetensors, save_safetensors  # noqa: E402
from pllvo_nets.superpoint import SuperPoint  # noqa: E402
from superpoint import synthetic_shapes  # noqa: E402

check = Checks()


def images():
    rng = np.random.default_rng(3)
    shapes, _ = synthetic_shapes.render(rng, 240, 320)
    texture = cv2.GaussianBlur(rng.random((240, 320)).astype(np.float32), (0, 0), 2.0)
    for _ in range(12):
        x, y = rng.integers(0, 280), rng.integers(0, 200)
        cv2.rectangle(texture, (int(x), int(y)), (int(x + rng.integers(10, 60)), int(y + rng.integers(10, 60))),
                      float(rng.random()), -1)
    texture = cv2.normalize(texture, None, 0, 1, cv2.NORM_MINMAX)
    dark = np.clip(texture * 0.08 + rng.normal(0, 0.01, texture.shape), 0, 1)
    return {name: np.round(np.clip(im, 0, 1) * 255).astype(np.uint8)
            for name, im in (("shapes", shapes), ("texture", texture), ("dark", dark))}


def tensors(path):
    return {k: np.asarray(v) for k, v in load_safetensors(path)[0].items()}


def python_superpoint(weights):
    model = SuperPoint(max_num_keypoints=None)
    state = {k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in load_safetensors(weights)[0].items()}
    model.load_state_dict(state)
    return model.eval()


def compare_superpoint(cli, weights, tmp):
    model = python_superpoint(weights)
    features = {}
    for name, image in images().items():
        png, out = tmp / f"{name}.png", tmp / f"{name}_cpp.safetensors"
        cv2.imwrite(str(png), image)
        subprocess.run([cli, "extract", str(png), "--weights", str(weights), "--out", str(out), "--threads", "1"],
                       check=True, capture_output=True)
        cpp = tensors(out)
        with torch.no_grad():
            py = model(torch.from_numpy(image.astype(np.float32) / 255)[None, None])
        kp, desc, scores = (py[k][0].numpy() for k in ("keypoints", "descriptors", "keypoint_scores"))
        same = cpp["keypoints"].shape == kp.shape and np.array_equal(cpp["keypoints"], kp)
        check(same and len(kp) > 20, f"superpoint {name}: identical keypoints ({len(kp)} Python, "
                                     f"{len(cpp['keypoints'])} C++)")
        if same:
            check(np.abs(cpp["descriptors"] - desc).max() < 1e-4, f"superpoint {name}: descriptors within 1e-4 "
                  f"(max {np.abs(cpp['descriptors'] - desc).max():.2e})")
            check(np.abs(cpp["scores"] - scores).max() < 1e-4, f"superpoint {name}: scores within 1e-4")
        features[name] = out
    return features


def python_lightglue(weights, filter_threshold):
    state = {k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in load_safetensors(weights)[0].items()}
    model = LightGlue(**lightglue_conf_from_state_dict(state), filter_threshold=filter_threshold)
    model.load_state_dict(state)
    return model.eval()


def compare_lightglue(cli, weights, f0, f1, tmp, label, filter_threshold=0.1):
    """filter_threshold: a random model's scores are low; a low threshold still gives it matches to compare."""
    out = tmp / f"{label}_matches.safetensors".replace(" ", "_")
    subprocess.run([cli, "match", str(f0), str(f1), "--weights", str(weights), "--out", str(out), "--threads", "1",
                    "--filter-threshold", str(filter_threshold)], check=True, capture_output=True)
    cpp = tensors(out)
    model = python_lightglue(weights, filter_threshold)
    data = []
    for f in (f0, f1):
        t = tensors(f)
        data.append({"keypoints": torch.from_numpy(t["keypoints"])[None],
                     "descriptors": torch.from_numpy(t["descriptors"])[None],
                     "image_size": torch.from_numpy(t["image_size"].astype(np.float32))[None]})
    with torch.no_grad():
        py = model(*data)
    for name in ("matches0", "matches1", "prune0", "prune1"):
        check(np.array_equal(cpp[name], py[name].numpy()), f"lightglue {label}: identical {name}")
    check(int(cpp["stop"].reshape(-1)[0]) == py["stop"], f"lightglue {label}: same stop layer ({py['stop']})")
    check(len(py["matches"]) >= 10, f"lightglue {label}: {len(py['matches'])} matches to compare")
    if np.array_equal(cpp["matches"], py["matches"].numpy()):
        check(np.abs(cpp["scores"] - py["scores"].numpy()).max(initial=0) < 1e-3,
              f"lightglue {label}: scores within 1e-3 ({len(py['matches'])} matches)")


def random_features(tmp, rng, n, dim, name):
    keypoints = rng.uniform([0, 0], [319, 239], size=(n, 2)).astype(np.float32)
    desc = rng.normal(size=(n, dim)).astype(np.float32)
    desc /= np.linalg.norm(desc, axis=1, keepdims=True)
    path = tmp / name
    save_safetensors(path, {"keypoints": keypoints, "scores": np.ones(n, np.float32), "descriptors": desc,
                            "image_size": np.array([320, 240], np.int64)})
    return path


def main():
    cli = sys.argv[1] if len(sys.argv) > 1 else str(REPO / "build" / "bin" / "pllvo")
    with tempfile.TemporaryDirectory() as tmp:
        tmp = Path(tmp)
        features = compare_superpoint(cli, REPO / "models" / "pllvo_superpoint_v1.safetensors", tmp)
        compare_lightglue(cli, REPO / "models" / "pllvo_lightglue_v1.safetensors", features["texture"],
                          features["dark"], tmp, "pllvo weights")
        torch.manual_seed(0)
        random = LightGlue(n_layers=3, descriptor_dim=64, num_heads=2, input_dim=64)
        export_state(random.state_dict(), tmp / "random_lg.safetensors", {"note": "fidelity test"}, fp16=True)
        rng = np.random.default_rng(0)
        f0, f1 = random_features(tmp, rng, 300, 64, "r0.safetensors"), random_features(tmp, rng, 280, 64, "r1.safetensors")
        compare_lightglue(cli, tmp / "random_lg.safetensors", f0, f1, tmp, "random export", filter_threshold=0.0)
    return check.summary("fidelity")


if __name__ == "__main__":
    sys.exit(main())
