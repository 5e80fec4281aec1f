"""Smoke test of the LightGlue training code on the CPU in seconds (CTest: training_lightglue_smoke):
ground truth from a homography and from depth + pose against analytic values, the losses, a few training
steps on a fixed batch (the loss must fall), and the export round trip."""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import sys
import tempfile
from pathlib import Path

import numpy as np
import torch

from lightglue import losses
from lightglue.config import ModelConfig, build_config
from lightglue.export import export_state
from lightglue.features import load_extractor
from lightglue.pairs import depth_warp, homography_warp
from lightglue.train import Step, build_model
from pllvo_nets.checks import Checks
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict
from pllvo_nets.safetensors_io import load_safetensors
from superpoint import synthetic_shapes
from superpoint.homographies import HomographyParams, sample_homography, warp_image, warp_points

REPO = Path(__file__).resolve().parents[2]
check = Checks()


def test_ground_truth():
    rng = np.random.default_rng(0)
    H = sample_homography(rng, 60, 80, HomographyParams(max_angle=0.3))
    kp0 = rng.uniform([10, 10], [70, 50], size=(40, 2))
    kp1 = warp_points(kp0, H)
    order = rng.permutation(40)
    kp1 = np.concatenate([kp1[order], [[1.0, 1.0], [78.0, 58.0]]])      # two points with no partner
    warp01, warp10 = homography_warp(H, 60, 80), homography_warp(np.linalg.inv(H), 60, 80)
    inside = ~np.isnan(warp01[np.round(kp0[:, 1]).astype(int), np.round(kp0[:, 0]).astype(int), 0])
    m0, un0, un1 = losses.ground_truth(torch.tensor(kp0, dtype=torch.float32)[None], torch.tensor(kp1, dtype=torch.float32)[None],
                                       torch.from_numpy(warp01)[None], torch.from_numpy(warp10)[None])
    expected = np.full(40, -1)
    expected[order] = np.arange(40)
    got = m0[0].numpy()
    check(np.array_equal(got[inside], expected[inside]) and inside.sum() > 30,
          f"ground truth from a homography recovers the {inside.sum()} true matches")
    check(bool(un1[0, -2:].all()), "points with no partner are unmatchable")


def test_depth_warp():
    K = np.array([[100.0, 0, 40], [0, 100.0, 30], [0, 0, 1]])
    depth = np.full((60, 80), 2.0, np.float32)         # fronto-parallel plane at 2 m
    T = np.eye(4)
    T[0, 3] = 0.1                                       # camera B 0.1 m to the left of A: x_B = x_A + 0.1
    warp = depth_warp(depth, depth, K, T)
    shift = warp[30, 20] - np.array([20, 30])
    check(np.allclose(shift, [100 * 0.1 / 2.0, 0], atol=1e-4), f"depth warp of a plane shifts by f*t/z (got {shift})")
    check(bool(np.isnan(warp[30, 79, 0])), "points leaving the image are not visible")
    occluder = depth.copy()
    occluder[:, 40:50] = 1.0                            # B sees something nearer there
    warp = depth_warp(depth, occluder, K, T)
    check(bool(np.isnan(warp[30, 38, 0])) and not np.isnan(warp[30, 20, 0]), "occluded points are not visible")


def fixed_batch(rng, n=2):
    images0, images1, w01, w10 = [], [], [], []
    for _ in range(n):
        image, _ = synthetic_shapes.render(rng, 64, 80)
        H = sample_homography(rng, 64, 80, HomographyParams(max_angle=0.2))
        warped, valid = warp_image(image, H)
        images0.append(image)
        images1.append(warped * valid)
        w01.append(homography_warp(H, 64, 80))
        w10.append(homography_warp(np.linalg.inv(H), 64, 80))
    return (torch.from_numpy(np.stack(images0))[:, None].float(), torch.from_numpy(np.stack(images1))[:, None].float(),
            torch.from_numpy(np.stack(w01)), torch.from_numpy(np.stack(w10)))


def test_training_steps():
    config = build_config("smoke")
    torch.manual_seed(0)
    extractor = load_extractor(REPO / "models" / "pllvo_superpoint_v1.safetensors", "cpu")
    model = build_model(config)
    step = Step(config, model, extractor, torch.device("cpu"))
    batch = fixed_batch(np.random.default_rng(1))
    optimizer = torch.optim.Adam(model.parameters(), lr=1e-3)
    totals = []
    for _ in range(40):
        out = step(batch)
        optimizer.zero_grad()
        out["total"].backward()
        optimizer.step()
        totals.append(float(out["total"]))
    check(totals[-1] < 0.8 * totals[0], f"loss falls on a fixed batch ({totals[0]:.3f} -> {totals[-1]:.3f})")
    check(len(model.transformers) == config.model.n_layers, "model has the configured depth")
    return model


def test_export(model):
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "lg.safetensors"
        export_state(model.state_dict(), path, {"note": "smoke"}, fp16=False)
        tensors, metadata = load_safetensors(path)
        state = {k: torch.from_numpy(np.asarray(v)) for k, v in tensors.items()}
        conf = lightglue_conf_from_state_dict(state)
        check(conf["n_layers"] == ModelConfig(n_layers=2).n_layers and "architecture" in metadata,
              f"export records the architecture ({conf})")
        loaded = LightGlue(**conf)
        loaded.load_state_dict(state)
        torch.manual_seed(2)
        data = [{"keypoints": torch.rand(1, 30, 2) * 60, "descriptors": torch.nn.functional.normalize(torch.randn(1, 30, 256), dim=-1),
                 "image_size": torch.tensor([[80.0, 64.0]])} for _ in range(2)]
        model.eval()
        with torch.no_grad():
            a, b = model.forward_train(*data)["log_assignment"][-1], loaded.forward_train(*data)["log_assignment"][-1]
        check(torch.allclose(a, b, atol=1e-6), "exported weights give the trained model's outputs")


def main():
    torch.set_num_threads(1)
    test_ground_truth()
    test_depth_warp()
    test_export(test_training_steps())
    return check.summary("lightglue smoke test")


if __name__ == "__main__":
    sys.exit(main())
