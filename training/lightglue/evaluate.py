"""Held-out benchmark of pllvo's LightGlue against mutual nearest neighbours, both on
the same SuperPoint keypoints and descriptors, in one run:

* synth: pairs of frames of held-out `pllvo synth` sequences (other scenes than training: the suite's seed)
  packed by make_data_pack.py, 1-4 packed frames apart: match precision / recall from the exact depth and
  poses, and relative-pose AUC at 5/10/20 deg (essential matrix: OpenCV RANSAC, 1 px, by default;
  --estimators ransac magsac and --ransac-px add OpenCV MAGSAC++ and other thresholds, each reported for both
  matchers as pose_auc_5_10_20_<estimator><px>px; --raw-errors writes every pair's pose error);
* homography: held-out real images (scannet_pairs and tum_fr3_office_snippet frames, never trained on) with
  a random homography and photometric changes, normal and low light: precision / recall and homography
  correctness at 3 px;
* scannet: the 15 wide-baseline scannet_pairs with their true relative pose: pose AUC.
For LightGlue (adaptive depth and width on, as the VO runs it) it also reports the mean stop layer and the
share of points pruned before the last layer.

  python3 training/lightglue/evaluate.py --lightglue models/pllvo_lightglue_v1.safetensors \
      --superpoint models/pllvo_superpoint_v1.safetensors --synth-dir PACK/synth_eval/<name> ...
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import argparse
import json
import time
from pathlib import Path

import cv2
import numpy as np
import torch

from lightglue import features, losses
from lightglue.pairs import HomographyPairs, SynthPairs, homography_warp
from pllvo_nets.lightglue import LightGlue, lightglue_conf_from_state_dict
from pllvo_nets.mnn import mutual_nn_match
from pllvo_nets.safetensors_io import load_safetensors
from superpoint import data_sources, eval_metrics
from superpoint.homographies import HomographyParams
from superpoint.photometric import DarkeningParams, PhotometricParams

NORMAL = PhotometricParams(p_dark=0.0)
LOW = PhotometricParams(p_brightness=0.0, p_contrast=0.0, p_gamma=0.0, p_noise=0.0, p_blur=0.0, p_motion_blur=0.0,
                        p_dark=1.0, dark=DarkeningParams(factor=(0.03, 0.1), p_gain=0.5))
# Essential-matrix estimators (--estimators): OpenCV RANSAC and MAGSAC++.
ESTIMATORS = {"ransac": cv2.RANSAC, "magsac": cv2.USAC_MAGSAC}


def load_lightglue(path, device, adaptive=True):
    tensors, _ = load_safetensors(path)
    state = {k: torch.from_numpy(np.asarray(v, np.float32)) for k, v in tensors.items()}
    conf = lightglue_conf_from_state_dict(state)
    if not adaptive:
        conf.update(depth_confidence=-1, width_confidence=-1)
    model = LightGlue(**conf)
    model.load_state_dict(state)
    return model.to(device).eval()


class Matchers:
    def __init__(self, lightglue, device):
        self.lightglue, self.device = lightglue, device
        self.stats = {"stop": [], "pruned": [], "lg_ms": [], "mnn_ms": []}

    @torch.no_grad()
    def __call__(self, kp0, d0, kp1, d1, size):
        """{name: matches0 [M] (numpy, -1 none)} for one pair."""
        t = time.perf_counter()
        m, _ = mutual_nn_match(d0.cpu(), d1.cpu(), distance_threshold=0.7)
        mnn = np.full(len(kp0), -1)
        mnn[m[:, 0].numpy()] = m[:, 1].numpy()
        self.stats["mnn_ms"].append(1000 * (time.perf_counter() - t))
        t = time.perf_counter()
        s = torch.tensor([size], dtype=torch.float32, device=self.device)
        out = self.lightglue({"keypoints": kp0[None], "descriptors": d0[None], "image_size": s},
                             {"keypoints": kp1[None], "descriptors": d1[None], "image_size": s})
        self.stats["lg_ms"].append(1000 * (time.perf_counter() - t))
        stop = out["stop"]
        self.stats["stop"].append(stop)
        pruned = torch.cat([out["prune0"], out["prune1"]]) < stop
        self.stats["pruned"].append(float(pruned.float().mean()))
        return {"mnn": mnn, "lightglue": out["matches0"].cpu().numpy()}


def to_pairs(matches0):
    index = np.where(matches0 >= 0)[0]
    return np.stack([index, matches0[index]], -1) if len(index) else np.zeros((0, 2), int)


def extract_pair(extractor, image0, image1, keypoints, device):
    out = []
    for image in (image0, image1):
        t = torch.from_numpy(np.ascontiguousarray(image, np.float32))[None, None].to(device)
        kp, desc, _ = features.extract(extractor, t, keypoints)
        out += [kp[0], desc[0]]
    return out


def score_dense(kp0, kp1, warp01, warp10, matches0):
    """(precision, recall) of matches0 against the ground truth of a dense correspondence."""
    gt0, un0, _ = losses.ground_truth(kp0[None].cpu(), kp1[None].cpu(), torch.from_numpy(warp01)[None],
                                      torch.from_numpy(warp10)[None])
    p, r = losses.match_quality(torch.from_numpy(matches0)[None], gt0, un0)
    return float(p), float(r)


def run_synth(pairs, extractor, matchers, args, device):
    results = {name: {"precision": [], "recall": [], "pose_error": []} for name in ("mnn", "lightglue")}
    rng = np.random.default_rng(args.seed)
    for s, seq in enumerate(pairs.sequences):
        for _ in range(args.synth_pairs):
            gap = int(rng.integers(args.min_gap, args.max_gap + 1))
            a = int(rng.integers(len(seq.stamps) - gap))
            choice = (s, a, a + gap)
            image0, image1, w01, w10 = pairs.pair(rng, choice)
            kp0, d0, kp1, d1 = extract_pair(extractor, image0, image1, args.keypoints, device)
            K, T_b_a = pairs.relative_pose(choice)
            for name, m0 in matchers(kp0, d0, kp1, d1, image0.shape[::-1]).items():
                p, r = score_dense(kp0, kp1, w01, w10, m0)
                results[name]["precision"].append(p)
                results[name]["recall"].append(r)
                # The same matches scored by every estimator and threshold; both matchers get the same ones
                # (nothing is chosen per matcher).
                for estimator in args.estimators:
                    for px in args.ransac_px:
                        estimate = eval_metrics.relative_pose(kp0.cpu().numpy(), kp1.cpu().numpy(), to_pairs(m0),
                                                              K, K, pixel_threshold=px, method=ESTIMATORS[estimator])
                        results[name].setdefault(pose_key(estimator, px, args), []).append(
                            eval_metrics.pose_error(T_b_a, estimate))
    return summarise(results, args.raw_errors)


def pose_key(estimator, px, args):
    """The first estimator at the first threshold is the headline 'pose_error'; the others are named."""
    if estimator == args.estimators[0] and px == args.ransac_px[0]:
        return "pose_error"
    return f"pose_error_{estimator}{px:g}px"


def run_homography(extractor, matchers, args, device, photometric_params):
    height, width = args.height, args.width
    items = []
    for path in data_sources.evaluation_images()[:args.max_images or None]:   # whole images (all 4:3), resized
        h, w = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE).shape
        items.append(data_sources.Item(str(path), (0.0, 0.0, float(w), float(h)), "eval"))
    if not items:
        raise SystemExit("lg-eval: error: no held-out images (../shared/data/scannet_pairs, tum_fr3_office_snippet)")
    pairs = HomographyPairs(None, height, width, HomographyParams(max_angle=np.pi / 6), photometric_params, items=items)
    results = {name: {"precision": [], "recall": [], "h_correct_3px": []} for name in ("mnn", "lightglue")}
    rng = np.random.default_rng(args.seed + 1)
    for index in range(len(items)):
        image0, image1, H_true = pairs.sample(rng, index)
        w01, w10 = homography_warp(H_true, height, width), homography_warp(np.linalg.inv(H_true), height, width)
        kp0, d0, kp1, d1 = extract_pair(extractor, image0, image1, args.keypoints, device)
        for name, m0 in matchers(kp0, d0, kp1, d1, (width, height)).items():
            p, r = score_dense(kp0, kp1, w01, w10, m0)
            H = eval_metrics.estimate_homography(kp0.cpu().numpy(), kp1.cpu().numpy(), to_pairs(m0))
            correct = H is not None and eval_metrics.corner_error(H_true, H, (height, width)) <= 3.0
            results[name]["precision"].append(p)
            results[name]["recall"].append(r)
            results[name]["h_correct_3px"].append(float(correct))
    return summarise(results)


def run_scannet(extractor, matchers, args, device):
    from superpoint.evaluate import read_scannet_pairs
    height, width = args.height, args.width
    results = {"mnn": {}, "lightglue": {}}
    for path0, path1, K0, K1, T in read_scannet_pairs()[:args.max_images or None]:
        images, Ks = [], []
        for path, K in ((path0, K0), (path1, K1)):
            gray = data_sources.load_gray(path)
            images.append(cv2.resize(gray, (width, height), interpolation=cv2.INTER_AREA))
            Ks.append(np.diag([width / gray.shape[1], height / gray.shape[0], 1.0]) @ K)
        kp0, d0, kp1, d1 = extract_pair(extractor, images[0], images[1], args.keypoints, device)
        for name, m0 in matchers(kp0, d0, kp1, d1, (width, height)).items():
            for estimator in args.estimators:
                for px in args.ransac_px:
                    estimate = eval_metrics.relative_pose(kp0.cpu().numpy(), kp1.cpu().numpy(), to_pairs(m0),
                                                          Ks[0], Ks[1], pixel_threshold=px,
                                                          method=ESTIMATORS[estimator])
                    results[name].setdefault(pose_key(estimator, px, args), []).append(
                        eval_metrics.pose_error(T, estimate))
    return summarise(results, args.raw_errors)


def summarise(results, raw_errors=False):
    out = {}
    for name, values in results.items():
        row = {k: round(float(np.mean(v)), 4) for k, v in values.items() if not k.startswith("pose_error")}
        for key, errors in values.items():
            if key.startswith("pose_error"):
                row[key.replace("pose_error", "pose_auc_5_10_20")] = \
                    [round(a, 4) for a in eval_metrics.pose_auc(errors)]
                if raw_errors:
                    row[key] = [round(e, 3) if np.isfinite(e) else None for e in errors]
        row["pairs"] = len(next(iter(values.values())))
        out[name] = row
    return out


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--lightglue", required=True)
    p.add_argument("--superpoint", required=True)
    p.add_argument("--synth-dir", action="append", default=[], help="held-out packed synthetic sequence")
    p.add_argument("--synth-pairs", type=int, default=20, help="pairs per synthetic sequence")
    p.add_argument("--min-gap", type=int, default=1, help="synthetic pairs: packed frames apart, at least")
    p.add_argument("--max-gap", type=int, default=4, help="synthetic pairs: packed frames apart, at most")
    p.add_argument("--sets", default="synth,homography,scannet", help="which benchmarks to run")
    p.add_argument("--filter-threshold", type=float, default=0.1, help="LightGlue's minimum match score")
    p.add_argument("--keypoints", type=int, default=512)
    p.add_argument("--height", type=int, default=240)
    p.add_argument("--width", type=int, default=320)
    p.add_argument("--seed", type=int, default=7)
    p.add_argument("--max-images", type=int, default=0, help="at most this many held-out images / ScanNet pairs (0: all)")
    p.add_argument("--device", default="cpu")
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--no-adaptive", action="store_true", help="LightGlue with all layers and points")
    p.add_argument("--ransac-px", type=float, nargs="+", default=[1.0],
                   help="essential-matrix RANSAC thresholds in pixels (the first is the headline)")
    p.add_argument("--estimators", nargs="+", default=["ransac"], choices=sorted(ESTIMATORS),
                   help="essential-matrix estimators (ransac: OpenCV RANSAC; magsac: OpenCV MAGSAC++)")
    p.add_argument("--raw-errors", action="store_true", help="also write every pair's pose error")
    p.add_argument("--out", default=None, help="JSON results file")
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    device = torch.device(args.device)
    extractor = features.load_extractor(args.superpoint, device)
    lightglue = load_lightglue(args.lightglue, device, adaptive=not args.no_adaptive)
    lightglue.conf["filter_threshold"] = args.filter_threshold
    matchers = Matchers(lightglue, device)
    report = {"settings": {k: v for k, v in vars(args).items() if k not in ("synth_dir",)}}
    sets = args.sets.split(",")
    if args.synth_dir and "synth" in sets:
        report["synth"] = run_synth(SynthPairs(args.synth_dir, args.max_gap), extractor, matchers, args, device)
    if "homography" in sets:
        report["homography_normal"] = run_homography(extractor, matchers, args, device, NORMAL)
        report["homography_low"] = run_homography(extractor, matchers, args, device, LOW)
    if "scannet" in sets and (data_sources.shared_dir() / "data" / "scannet_pairs").is_dir():
        report["scannet"] = run_scannet(extractor, matchers, args, device)
    st = matchers.stats
    report["lightglue_adaptivity"] = {"mean_stop_layer": round(float(np.mean(st["stop"])), 2),
                                      "pruned_share": round(float(np.mean(st["pruned"])), 3),
                                      "lightglue_ms": round(float(np.median(st["lg_ms"])), 2),
                                      "mnn_ms": round(float(np.median(st["mnn_ms"])), 2), "device": str(device)}
    text = json.dumps(report, indent=1)
    print(text)
    if args.out:
        Path(args.out).parent.mkdir(parents=True, exist_ok=True)
        Path(args.out).write_text(text)


if __name__ == "__main__":
    main()
