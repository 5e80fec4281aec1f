"""CPU smoke test of the SuperPoint training code: unit checks of the geometry and the labels, then every
stage for a few iterations on tiny images (the training stages on one fixed batch, so their losses must
fall), the export, and a reload of the exported file. Self-contained: its "real" images are rendered
shapes written to a temporary folder, so it needs neither ../shared nor the Debian photographs.

    /usr/bin/python3 training/superpoint/smoke_test.py        (exit status 0 when every check passes)
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import math
import sys
import tempfile
import time
from pathlib import Path

import cv2
import numpy as np
import torch

from pllvo_nets.checks import Checks
from superpoint import cli, pipeline, synthetic_shapes, train_shapes
from superpoint.config import build_config
from superpoint.homographies import HomographyParams, sample_homography, warp_batch, warp_image, warp_points
from superpoint.keypoints import extract_keypoints, heatmap_from_logits, sample_descriptors
from superpoint.labels import DUSTBIN, cell_labels, cell_mask
from superpoint.losses import correspondences, descriptor_loss, detector_loss
from superpoint.network import OFFICIAL_NAMES, build_superpoint, read_weights
from superpoint.safetensors_io import read_safetensors

check = Checks()


def test_labels():
    rng = np.random.default_rng(0)
    labels = cell_labels(np.array([[3, 2], [9.4, 17.6], [15, 23]]), 32, 32, rng)
    check(labels[0, 0] == 2 * 8 + 3 and labels[2, 1] in (2 * 8 + 1, 7 * 8 + 7) and (labels == DUSTBIN).sum() == 14,
          f"cell labels: positions and dustbin ({labels[0, 0]}, {labels[2, 1]})")
    picks = {int(cell_labels(np.array([[9.0, 17.0], [15.0, 23.0]]), 32, 32, np.random.default_rng(s))[2, 1]) for s in range(20)}
    check(picks == {1 * 8 + 1, 7 * 8 + 7}, f"two corners in one cell: both drawn at random ({sorted(picks)})")
    mask = np.ones((16, 16), bool)
    mask[3, 12] = False
    check(cell_mask(mask).tolist() == [[True, False], [True, True]], "cell mask: a cell with one invalid pixel is invalid")


def test_geometry():
    rng = np.random.default_rng(1)
    H = sample_homography(rng, 48, 64, HomographyParams())
    image = np.zeros((48, 64), np.float32)
    image[20, 30] = 1.0
    warped, _ = warp_image(image, H, erosion=0)
    expected = warp_points([[30, 20]], H)[0]
    peak = np.array(np.unravel_index(np.argmax(warped), warped.shape))[::-1]
    check(np.hypot(*(peak - expected)) < 1.5 or not (0 <= expected[0] < 64 and 0 <= expected[1] < 48),
          f"warp_image moves a bright pixel where warp_points says ({peak} vs {np.round(expected, 1)})")
    texture = rng.random((48, 64)).astype(np.float32)
    cv_warped, valid = warp_image(texture, H, erosion=1)
    torch_warped = warp_batch(torch.from_numpy(texture)[None, None], torch.from_numpy(H)[None])[0, 0].numpy()
    # cv2 interpolates with 1/32-pixel fixed-point weights, hence the tolerance.
    error = np.abs(torch_warped - cv_warped)[valid].max()
    check(error < 0.03, f"torch warp_batch equals cv2.warpPerspective inside the valid area (max {error:.4f})")
    s = correspondences(torch.eye(3)[None], 3, 4, 7.5)[0]
    check(torch.equal(s, torch.eye(12)), "descriptor correspondences under the identity: each cell with itself only")
    shift = torch.tensor([[[1.0, 0, 8], [0, 1, 0], [0, 0, 1]]])
    s = correspondences(shift, 3, 4, 7.5)[0]
    check(s[0, 1] == 1 and s[0, 0] == 0 and s.sum() == 9, "descriptor correspondences under an 8 px shift")


def test_losses_and_decoding():
    logits = torch.full((1, 65, 2, 2), -10.0)
    logits[0, 64] = 10.0
    logits[0, 64, 1, 0], logits[0, 10, 1, 0] = -10.0, 10.0
    labels = torch.tensor([[[64, 64], [10, 64]]])
    check(float(detector_loss(logits, labels)) < 1e-6, "detector loss of a perfect prediction is 0")
    check(float(detector_loss(logits, torch.tensor([[[64, 64], [11, 64]]]))) > 4, "detector loss of a wrong cell is large")
    heat = heatmap_from_logits(logits)
    (xy, _), = extract_keypoints(heat, 0.5, 1, 0)
    check(xy.tolist() == [[2.0, 9.0]], f"decoding: channel 10 of cell (1,0) is pixel (x=2, y=9) ({xy.tolist()})")
    d = torch.randn(1, 256, 3, 4)
    corners = sample_descriptors(d[0], torch.tensor([[3.5, 3.5], [31.0, 23.0]]))
    check(torch.allclose(corners[0], torch.nn.functional.normalize(d[0, :, 0, 0], dim=0), atol=1e-5) and
          torch.allclose(corners[1], torch.nn.functional.normalize(d[0, :, 2, 3], dim=0), atol=1e-5),
          "descriptor sampling: pixel 3.5 reads the first cell, the last pixel the last cell (official convention)")
    same = descriptor_loss(d, d, torch.eye(3)[None])
    other = descriptor_loss(d, torch.roll(d, 1, dims=3), torch.eye(3)[None])
    check(float(same) < float(other), f"descriptor loss prefers matching descriptors ({float(same):.3f} < {float(other):.3f})")


def falls(rows, key, ratio):
    first, last = rows[0][key], rows[-1][key]
    check(last < ratio * first, f"{key} loss falls: {first:.4f} -> {last:.4f} (needs < {ratio} x)")


def test_pipeline(tmp):
    images = tmp / "images"
    images.mkdir()
    rng = np.random.default_rng(5)
    for i in range(3):
        image, _ = synthetic_shapes.render(rng, 96, 128, ["checkerboard", "multiple_polygons", "cube"][i])
        cv2.imwrite(str(images / f"{i}.png"), np.round(image * 255).astype(np.uint8))
    args = cli.parser("smoke").parse_args(["--preset", "smoke", "--out", str(tmp / "run"), "--threads", "1",
                                            "--set", "data.use_shared=False", "--set", "data.use_photos=False",
                                            "--image-dir", str(images)])
    config, out, device = cli.setup(args)
    logs = []
    started = time.time()
    exported = pipeline.run(config, out, device, log=logs.append)
    print(f"     pipeline took {time.time() - started:.1f} s")
    check(exported is not None and exported.is_file(), "pipeline ran every stage and exported")
    rows = {stage: [dict(zip(h.split(","), map(float, l.split(",")))) for h, *ls in
                    [(out / stage / "log.csv").read_text().split()] for l in ls] for stage in ("shapes", "joint")}
    falls(rows["shapes"], "detector", 0.7)
    falls(rows["joint"], "detector", 0.8)
    falls(rows["joint"], "descriptor", 0.9)
    labels = list((out / "adaptation").glob("labels_*/*.npy"))
    check(len(labels) == 3, f"homographic adaptation cached labels for the 3 crops ({len(labels)})")
    tensors, meta = read_safetensors(exported)
    check(sorted(tensors) == sorted(OFFICIAL_NAMES) and all(t.dtype == torch.float16 for t in tensors.values()),
          "export: the 24 official tensor names, float16")
    check("stages" in meta and "config" in meta, "export: metadata has stages and config")
    trained = build_superpoint(out / "joint" / "checkpoint.pt").eval()
    reloaded = build_superpoint(exported).eval()
    x = torch.rand(1, 1, 48, 64)
    with torch.no_grad():
        (la, da), (lb, db) = trained.dense(x), reloaded.dense(x)
    prob = float((heatmap_from_logits(la) - heatmap_from_logits(lb)).abs().max())
    desc = float((torch.nn.functional.normalize(da, dim=1) - torch.nn.functional.normalize(db, dim=1)).abs().max())
    check(prob < 0.01 and desc < 0.01,
          f"exported fp16 weights reproduce the checkpoint (max diff: probability {prob:.4f}, descriptor {desc:.4f})")
    # Resume: rerunning a finished pipeline changes nothing and trains no further step.
    before = read_weights(out / "joint" / "checkpoint.pt")
    pipeline.run(config, out, device, log=logs.append)
    after = read_weights(out / "joint" / "checkpoint.pt")
    check(all(torch.equal(before[k], after[k]) for k in before), "rerunning a finished run resumes and trains nothing more")
    folders = list((out / "adaptation").glob("labels_*"))
    check(len(folders) == 1, f"rerunning reuses the cached pseudo labels ({len(folders)} label folders)")
    validations = [(out / stage / "validation.csv").read_text().split()[0] for stage in ("shapes", "joint")]
    check(validations == ["step,precision,recall", "step,repeatability,match_precision"],
          f"validation measures logged at checkpoints ({validations})")
    config.adaptation.min_mean_points = 1e6
    try:
        pipeline.run(config, out, device, log=logs.append)
        check(False, "too few pseudo labels stop the pipeline before stage 3")
    except RuntimeError as error:
        check("points per crop" in str(error), "too few pseudo labels stop the pipeline before stage 3")


def test_resume(tmp):
    """A run stopped after 10 steps and resumed to 20 logs the same losses as an uninterrupted one."""
    def shapes_log(folder, *steps):
        for n in steps:
            args = cli.parser("smoke").parse_args(["--preset", "smoke", "--out", str(folder), "--threads", "1",
                                                    "--set", "shapes.fixed_data=False", "--set", f"shapes.steps={n}"])
            config, out, device = cli.setup(args)
            train_shapes.train(config, out, device, log=lambda _: None)
        rows = [line.split(",") for line in (folder / "shapes" / "log.csv").read_text().split()]
        return [row[:1] + row[2:] for row in rows]          # without the time column
    resumed, straight = shapes_log(tmp / "resumed", 10, 20), shapes_log(tmp / "straight", 20)
    check(resumed == straight, "resumed training reproduces the uninterrupted run's losses exactly")


def main():
    torch.manual_seed(0)
    test_labels()
    test_geometry()
    test_losses_and_decoding()
    with tempfile.TemporaryDirectory(prefix="sptrain_smoke_") as tmp:
        test_pipeline(Path(tmp))
        test_resume(Path(tmp))
    return check.summary("smoke test")


if __name__ == "__main__":
    sys.exit(main())
