"""Builds a self-contained folder of training images for a machine that has neither ../shared nor the
Debian photographs (a lent GPU machine: everything it reads must travel with the repository, within a
size limit). Run it here, carry the folder, and point the training at it:

  /usr/bin/python3 training/make_data_pack.py --out .devpack --synth /work/lgdata/raw/*
  # there:  PLLVO_SHARED=.devpack/shared PLLVO_PHOTOS=.devpack/photos python3 training/superpoint/pipeline.py \
  #           --set data.euroc_every=1 --set data.ecd_first_frame=0 --set data.ecd_every=1 --synth-dir .devpack/synth/<name>/frames ...

What goes in:
  shared/data/...   the training subset of ../shared/data in the same layout (EuRoC every 3rd frame, KITTI,
                    ECD from frame 55 on; JPEG quality 95 to fit the limit). Held-out data (scannet_pairs,
                    tum_fr3_office_snippet) is never packed.
  photos/           the Debian mate-backgrounds photographs (already JPEG).
  synth/<name>/     `pllvo synth --depth` sequences (rendered with zero distortion) at half resolution:
                    frames/<ns>.png, depth/<ns>.png (uint16 cm, nearest), meta.json with the pinhole K of the
                    half-resolution image and T_world_cam (row-major 4x4) per frame. Half resolution because the
                    VO runs SuperPoint at input scale 0.5: LightGlue is trained on the features it will see.
  synth_eval/<name> held-out sequences (other scenes) in the same form, for evaluation only.
  With --held-out: scannet_pairs and the TUM frames (evaluation images, never trained on).
"""
import argparse
import json
import shutil
import sys
from pathlib import Path

import cv2
import numpy as np

sys.path.insert(0, str(Path(__file__).resolve().parent))
from superpoint import data_sources  # noqa: E402


def pack_shared(out, quality):
    config = data_sources.DataConfig(use_photos=False)
    root = data_sources.shared_dir()
    count = 0
    for _, _, paths in data_sources.training_sources(config):
        for path in paths:
            target = out / "shared" / Path(path).relative_to(root).with_suffix(".jpg")
            target.parent.mkdir(parents=True, exist_ok=True)
            image = cv2.imread(str(path), cv2.IMREAD_GRAYSCALE)
            if image is None:
                raise SystemExit(f"make_data_pack: error: cannot read {path}")
            cv2.imwrite(str(target), image, [cv2.IMWRITE_JPEG_QUALITY, quality])
            count += 1
    return count


def pack_held_out(out):
    """The evaluation images (never trained on), for running the benchmarks there too: scannet_pairs as is,
    the TUM frames as grey PNG (the benchmarks read grey; a third of the size)."""
    root = data_sources.shared_dir() / "data"
    scannet = out / "shared" / "data" / "scannet_pairs"
    (scannet / "images").mkdir(parents=True, exist_ok=True)
    shutil.copy(root / "scannet_pairs" / "scannet_sample_pairs_with_gt.txt", scannet)
    count = 0
    for path in data_sources._images_in(root / "scannet_pairs" / "images"):
        shutil.copy(path, scannet / "images" / path.name)
        count += 1
    tum = out / "shared" / "data" / "tum_fr3_office_snippet" / "rgb"
    tum.mkdir(parents=True, exist_ok=True)
    for path in data_sources._images_in(root / "tum_fr3_office_snippet" / "rgb"):
        cv2.imwrite(str(tum / path.name), cv2.imread(str(path), cv2.IMREAD_GRAYSCALE), [cv2.IMWRITE_PNG_COMPRESSION, 9])
        count += 1
    return count


def pack_photos(out):
    folder = data_sources.DEBIAN_PHOTOS
    paths = data_sources._images_in(folder) if folder.is_dir() else []
    (out / "photos").mkdir(parents=True, exist_ok=True)
    for path in paths:
        shutil.copy(path, out / "photos" / path.name)
    return len(paths)


def read_matrix(yaml_path, key):
    """The numbers of a list or of an OpenCV-style matrix node ({rows, cols, data}) of a sensor.yaml."""
    fs = cv2.FileStorage(str(yaml_path), cv2.FILE_STORAGE_READ)
    node = fs.getNode(key)
    if node.isMap():
        node = node.getNode("data")
    if node.isNone() or not node.isSeq():
        raise SystemExit(f"make_data_pack: error: {yaml_path}: no list {key}")
    return np.array([node.at(i).real() for i in range(node.size())])


def quaternion_matrix(w, x, y, z):
    return np.array([[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
                     [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
                     [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]])


def pack_synth(sequence, out, every, scale, max_frames=0, folder="synth"):
    cam = sequence / "mav0" / "cam0"
    distortion = read_matrix(cam / "sensor.yaml", "distortion_coefficients")
    if np.any(np.abs(distortion) > 0):
        raise SystemExit(f"make_data_pack: error: {cam / 'sensor.yaml'}: render with zero distortion "
                         "(camera: distortion: [0, 0, 0, 0]) so that depth reprojects with a pinhole K")
    fx, fy, cx, cy = read_matrix(cam / "sensor.yaml", "intrinsics")
    T_body_cam = read_matrix(cam / "sensor.yaml", "T_BS").reshape(4, 4)
    truth = {}
    for line in (sequence / "mav0" / "state_groundtruth_estimate0" / "data.csv").read_text().splitlines()[1:]:
        v = line.split(",")
        T = np.eye(4)
        T[:3, :3] = quaternion_matrix(*map(float, v[4:8]))
        T[:3, 3] = list(map(float, v[1:4]))
        truth[int(v[0])] = T @ T_body_cam
    target = out / folder / sequence.name
    (target / "frames").mkdir(parents=True, exist_ok=True)
    (target / "depth").mkdir(parents=True, exist_ok=True)
    frames = []
    rows = (cam / "data.csv").read_text().splitlines()[1:]
    for row in rows[::every][:max_frames or None]:
        stamp = int(row.split(",")[0])
        if stamp not in truth:
            raise SystemExit(f"make_data_pack: error: {sequence}: no ground-truth pose at {stamp}")
        image = cv2.imread(str(cam / "data" / f"{stamp}.png"), cv2.IMREAD_GRAYSCALE)
        depth = cv2.imread(str(cam / "depth" / f"{stamp}.png"), cv2.IMREAD_UNCHANGED)
        if image is None or depth is None:
            raise SystemExit(f"make_data_pack: error: {sequence}: frame or depth {stamp} missing (render with --depth)")
        size = (round(image.shape[1] * scale), round(image.shape[0] * scale))
        png = [cv2.IMWRITE_PNG_COMPRESSION, 9]
        cv2.imwrite(str(target / "frames" / f"{stamp}.png"), cv2.resize(image, size, interpolation=cv2.INTER_AREA), png)
        # Centimetres: a fifth of the millimetre file's size; 1 cm at 2 m moves a reprojection by ~0.1 px here.
        depth_cm = np.round(cv2.resize(depth, size, interpolation=cv2.INTER_NEAREST) / 10.0).astype(np.uint16)
        cv2.imwrite(str(target / "depth" / f"{stamp}.png"), depth_cm, png)
        frames.append({"stamp": stamp, "T_world_cam": truth[stamp].reshape(-1).tolist()})
    # Pixel centres: x' = (x + 0.5) * s - 0.5, so cx' = (cx + 0.5) * s - 0.5.
    K = [fx * scale, fy * scale, (cx + 0.5) * scale - 0.5, (cy + 0.5) * scale - 0.5]
    (target / "meta.json").write_text(json.dumps({"K": K, "depth_unit_m": 0.01, "frames": frames}))
    return len(frames)


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--out", required=True)
    p.add_argument("--synth", nargs="*", default=[], help="`pllvo synth --depth` output folders (zero distortion)")
    p.add_argument("--synth-every", type=int, default=3, help="keep every n-th synthetic frame")
    p.add_argument("--synth-max-frames", type=int, default=0, help="at most this many frames per sequence (0: all)")
    p.add_argument("--synth-eval", nargs="*", default=[], help="held-out `pllvo synth --depth` folders -> synth_eval/")
    p.add_argument("--held-out", action="store_true", help="also pack the held-out evaluation images")
    p.add_argument("--synth-scale", type=float, default=0.5)
    p.add_argument("--jpeg-quality", type=int, default=95)
    args = p.parse_args()
    out = Path(args.out)
    out.mkdir(parents=True, exist_ok=True)
    print(f"shared images: {pack_shared(out, args.jpeg_quality)}")
    print(f"photographs: {pack_photos(out)}")
    if args.held_out:
        print(f"held-out images: {pack_held_out(out)}")
    for sequence in args.synth:
        count = pack_synth(Path(sequence), out, args.synth_every, args.synth_scale, args.synth_max_frames)
        print(f"synth {Path(sequence).name}: {count} frames")
    for sequence in args.synth_eval:
        count = pack_synth(Path(sequence), out, args.synth_every, args.synth_scale, 0, "synth_eval")
        print(f"synth_eval {Path(sequence).name}: {count} frames")
    size = sum(f.stat().st_size for f in out.rglob("*") if f.is_file())
    print(f"pack: {out} ({size / 2**20:.1f} MiB)")


if __name__ == "__main__":
    main()
