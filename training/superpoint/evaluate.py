"""Side-by-side benchmark of SuperPoint weights against OpenCV ORB, SIFT and Shi-Tomasi + ORB, in one
run:

* Homography benchmark (HPatches-style) on held-out real images: each image and a copy warped by a random
  homography, both with their own photometric change; "normal" (mild brightness / contrast / gamma / noise)
  and "low" (strong darkening with shot noise, read noise and 8-bit quantisation, no gain); optionally
  "lowgain" (the same dark exposure brought back to a mean grey of ~0.45 by a digital gain, as an
  auto-gain camera does: bright but noisy and banded).
  Repeatability at 3 px, and homography correctness at 1 / 3 / 5 px (mean corner error of the RANSAC
  homography from mutual-nearest-neighbour matches).
* Relative pose on ../shared/data/scannet_pairs (640x480): essential matrix from mutual-NN matches,
  AUC of max(rotation, translation-direction) error at 5 / 10 / 20 degrees, normal and low light.

    nice -n 19 /usr/bin/python3 training/superpoint/evaluate.py \
        --weights official=../shared/models/superpoint_v1.safetensors --weights pllvo=models/pllvo_superpoint_v1.safetensors
"""
if __package__ in (None, ""):
    import pathlib
    import sys
    sys.path.insert(0, str(pathlib.Path(__file__).resolve().parents[1]))

import argparse
import json
import math
import time
from pathlib import Path

import cv2
import numpy as np
import torch

from superpoint import data_sources, eval_metrics
from superpoint.eval_features import build_extractors
from superpoint.homographies import HomographyParams, sample_homography, warp_image
from superpoint.photometric import DarkeningParams, PhotometricParams, augment, darken

CONDITIONS = ("normal", "low", "lowgain")
DEFAULT_CONDITIONS = ("normal", "low")
# Viewpoint changes of the size of HPatches' (no black borders: the patch stays inside the image).
EVAL_HOMOGRAPHY = HomographyParams(patch_ratio=0.8, perspective=0.2, scaling=0.2, max_angle=math.pi / 8,
                                   translation=True, allow_artifacts=False)
NORMAL_CHANGE = PhotometricParams(p_brightness=1.0, brightness=0.1, p_contrast=1.0, contrast=(0.8, 1.2), p_gamma=0.5,
                                  gamma=(0.8, 1.25), p_noise=1.0, noise_std=(0.0, 0.01), p_blur=0.0,
                                  p_motion_blur=0.0, p_dark=0.0)
# Exposure 8-20 % of normal: mean grey ~10-25 of 255, shot noise from 300-1000 electrons at full scale.
LOW_LIGHT = DarkeningParams(factor=(0.08, 0.2), photons=(300.0, 1000.0), read_noise=(1.0 / 255, 2.0 / 255), p_gain=0.0)


def change(image, rng, condition):
    if condition == "normal":
        return augment(image, rng, NORMAL_CHANGE)
    return darken(image, rng, LOW_LIGHT, gain=condition == "lowgain")


def resize_gray(path, width, height):
    return cv2.resize(data_sources.load_gray(path), (width, height), interpolation=cv2.INTER_AREA)


def homography_benchmark(extractors, images, pairs_per_image, size, conditions, seed, log, repeatability_keypoints=300):
    height, width = size
    rows = {(name, c): [] for name in extractors for c in conditions}
    for index, path in enumerate(images):
        source = resize_gray(path, width, height)
        for k in range(pairs_per_image):
            rng = np.random.default_rng([seed, index, k])
            H = sample_homography(rng, height, width, EVAL_HOMOGRAPHY)
            warped, _ = warp_image(source, H, erosion=0)
            for condition in conditions:
                crng = np.random.default_rng([seed, index, k, CONDITIONS.index(condition)])
                image1, image2 = change(source, crng, condition), change(warped, crng, condition)
                for name, extract in extractors.items():
                    xy1, d1, _ = extract(image1)
                    xy2, d2, _ = extract(image2)
                    matches = eval_metrics.mutual_nn(d1, d2, extract.norm)
                    H_est = eval_metrics.estimate_homography(xy1, xy2, matches)
                    error = eval_metrics.corner_error(H, H_est, (height, width)) if H_est is not None else float("inf")
                    rows[(name, condition)].append({
                        "image": Path(path).name, "pair": k, "keypoints": (len(xy1) + len(xy2)) / 2,
                        # Repeatability depends on point density: compare equal budgets (the strongest
                        # `repeatability_keypoints` of each method, as the SuperPoint paper's 300).
                        "repeatability": eval_metrics.repeatability(xy1[:repeatability_keypoints], xy2[:repeatability_keypoints],
                                                                    H, (height, width), (height, width)),
                        "repeatability_all": eval_metrics.repeatability(xy1, xy2, H, (height, width), (height, width)),
                        "matches": len(matches), "match_precision": eval_metrics.match_precision(xy1, xy2, matches, H),
                        "corner_error": error})
        log(f"[homography] {index + 1}/{len(images)} images")
    summary = {}
    for (name, condition), values in rows.items():
        errors = np.array([v["corner_error"] for v in values])
        reps = [v["repeatability"] for v in values if v["repeatability"] is not None]
        reps_all = [v["repeatability_all"] for v in values if v["repeatability_all"] is not None]
        summary[f"{name}/{condition}"] = {
            "pairs": len(values), "repeatability@3": float(np.mean(reps)) if reps else 0.0,
            "repeatability_all@3": float(np.mean(reps_all)) if reps_all else 0.0,
            "H@1": float((errors <= 1).mean()), "H@3": float((errors <= 3).mean()), "H@5": float((errors <= 5).mean()),
            "keypoints": float(np.mean([v["keypoints"] for v in values])),
            "matches": float(np.mean([v["matches"] for v in values])),
            "match_precision@3": float(np.mean([v["match_precision"] for v in values]))}
    return summary, rows


def read_scannet_pairs():
    root = data_sources.shared_dir() / "data" / "scannet_pairs"
    pairs = []
    for line in (root / "scannet_sample_pairs_with_gt.txt").read_text().splitlines():
        fields = line.split()
        if len(fields) != 38:
            continue
        values = np.array(fields[4:], np.float64)
        pairs.append((root / "images" / fields[0], root / "images" / fields[1], values[:9].reshape(3, 3),
                      values[9:18].reshape(3, 3), values[18:].reshape(4, 4)))
    return pairs


def pose_benchmark(extractors, size, conditions, seed, log):
    height, width = size
    errors = {(name, c): [] for name in extractors for c in conditions}
    for index, (path0, path1, K0, K1, T) in enumerate(read_scannet_pairs()):
        originals = [cv2.imread(str(p), cv2.IMREAD_GRAYSCALE).shape for p in (path0, path1)]
        scaled = [np.diag([width / s[1], height / s[0], 1.0]) @ K for s, K in zip(originals, (K0, K1))]
        images = [resize_gray(p, width, height) for p in (path0, path1)]
        for condition in conditions:
            crng = np.random.default_rng([seed, 1000 + index, CONDITIONS.index(condition)])
            pair = [im if condition == "normal" else darken(im, crng, LOW_LIGHT, gain=condition == "lowgain")
                    for im in images]
            for name, extract in extractors.items():
                (xy0, d0, _), (xy1, d1, _) = extract(pair[0]), extract(pair[1])
                matches = eval_metrics.mutual_nn(d0, d1, extract.norm)
                estimate = eval_metrics.relative_pose(xy0, xy1, matches, scaled[0], scaled[1])
                errors[(name, condition)].append(eval_metrics.pose_error(T, estimate))
        log(f"[pose] {index + 1} pairs")
    return {f"{name}/{condition}": dict(zip(("AUC@5", "AUC@10", "AUC@20"), eval_metrics.pose_auc(values)))
            for (name, condition), values in errors.items()}, errors


def markdown(homography, pose, extractors, conditions):
    lines = ["| method | light | repeatability@3px (best 300) | (all points) | H corr. @1px | @3px | @5px | keypoints | MNN matches | match precision@3px | pose AUC@5 | @10 | @20 |",
             "|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for condition in conditions:
        for name in extractors:
            h = homography.get(f"{name}/{condition}", {})
            p = pose.get(f"{name}/{condition}", {})
            cells = [f"{h[k]:.3f}" if k in h else "-" for k in ("repeatability@3", "repeatability_all@3", "H@1", "H@3", "H@5")]
            cells += [f"{h[k]:.0f}" if k in h else "-" for k in ("keypoints", "matches")]
            cells += [f"{h['match_precision@3']:.3f}" if h else "-"]
            cells += [f"{100 * p[k]:.1f}" if k in p else "-" for k in ("AUC@5", "AUC@10", "AUC@20")]
            lines.append(f"| {name} | {condition} | " + " | ".join(cells) + " |")
    return "\n".join(lines)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--weights", action="append", default=[], metavar="NAME=PATH",
                   help="SuperPoint weights (.safetensors or training checkpoint), repeatable")
    p.add_argument("--max-keypoints", type=int, default=1024, help="keypoint budget of every method")
    p.add_argument("--pairs-per-image", type=int, default=2)
    p.add_argument("--repeatability-keypoints", type=int, default=300,
                   help="repeatability compares the strongest N points of every method")
    p.add_argument("--max-images", type=int, default=0, help="0: all 46 held-out images")
    p.add_argument("--size", default="480x640", help="HxW of the homography benchmark images")
    p.add_argument("--pose-size", default="480x640", help="HxW of the ScanNet images")
    p.add_argument("--skip-pose", action="store_true")
    p.add_argument("--conditions", default=",".join(DEFAULT_CONDITIONS), help=f"comma-separated, of {CONDITIONS}")
    p.add_argument("--seed", type=int, default=0)
    p.add_argument("--threads", type=int, default=2)
    p.add_argument("--device", default="cpu")
    p.add_argument("--out", default=str(data_sources.REPO_ROOT / "out" / "sptrain" / "eval"), help="results folder")
    args = p.parse_args()
    torch.set_num_threads(args.threads)
    conditions = tuple(c for c in args.conditions.split(",") if c)
    unknown = set(conditions) - set(CONDITIONS)
    if unknown:
        p.error(f"unknown conditions {sorted(unknown)}")
    cv2.setNumThreads(args.threads)
    weights = args.weights or [f"official={data_sources.shared_dir() / 'models' / 'superpoint_v1.safetensors'}"]
    extractors = build_extractors(weights, args.max_keypoints, args.device)
    images = data_sources.evaluation_images()
    if args.max_images:
        images = images[:args.max_images]
    started = time.time()
    size = tuple(int(v) for v in args.size.split("x"))
    homography, rows = homography_benchmark(extractors, images, args.pairs_per_image, size, conditions, args.seed, print,
                                            args.repeatability_keypoints)
    pose, pose_errors = ({}, {}) if args.skip_pose else pose_benchmark(
        extractors, tuple(int(v) for v in args.pose_size.split("x")), conditions, args.seed, print)
    table = markdown(homography, pose, extractors, conditions)
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    result = {"command": " ".join(sys.argv), "conditions": conditions, "weights": weights, "images": [str(i) for i in images],
              "pairs_per_image": args.pairs_per_image, "max_keypoints": args.max_keypoints, "size": args.size,
              "homography": homography, "pose": pose, "seconds": round(time.time() - started, 1),
              "per_pair": {f"{k[0]}/{k[1]}": v for k, v in rows.items()},
              "pose_errors_deg": {f"{k[0]}/{k[1]}": v for k, v in pose_errors.items()}}
    (out / "results.json").write_text(json.dumps(result, indent=1))
    (out / "results.md").write_text(table + "\n")
    print(table)
    print(f"{len(images)} images x {args.pairs_per_image} homographies, {time.time() - started:.0f} s; results in {out}")


if __name__ == "__main__":
    import sys
    main()
