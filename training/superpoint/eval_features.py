"""The feature extractors compared by the benchmark, behind one interface:
extractor(image float32 [H,W] in [0,1]) -> (xy float32 [N,2], descriptors, scores) with at most `max_keypoints`
points, strongest first; descriptors are float32 unit vectors (L2) or uint8 bit strings (Hamming)."""
import cv2
import numpy as np
import torch

from superpoint.keypoints import detect_and_describe
from superpoint.network import build_superpoint


def _to_uint8(image):
    return np.round(np.clip(image, 0, 1) * 255).astype(np.uint8)


class SuperPointExtractor:
    norm = "l2"

    def __init__(self, weights, max_keypoints, device="cpu", threshold=0.005, nms_radius=4, border=4):
        self.model = build_superpoint(weights, device).eval()
        self.max_keypoints, self.threshold, self.nms_radius, self.border = max_keypoints, threshold, nms_radius, border

    def __call__(self, image):
        # The official network sees 8-bit images scaled to [0,1]; quantise like a camera would.
        tensor = torch.from_numpy(_to_uint8(image).astype(np.float32) / 255)
        h, w = tensor.shape
        tensor = tensor[:h - h % 8, :w - w % 8]
        xy, scores, desc = detect_and_describe(self.model, tensor, self.threshold, self.nms_radius, self.border,
                                               self.max_keypoints)
        return xy.numpy(), desc.numpy(), scores.numpy()


def _from_keypoints(keypoints, descriptors, max_keypoints):
    if descriptors is None or len(keypoints) == 0:
        return np.zeros((0, 2), np.float32), np.zeros((0, 32), np.uint8), np.zeros(0, np.float32)
    order = np.argsort([-k.response for k in keypoints], kind="stable")[:max_keypoints]
    xy = np.array([keypoints[i].pt for i in order], np.float32)
    return xy, descriptors[order], np.array([keypoints[i].response for i in order], np.float32)


class OrbExtractor:
    norm = "hamming"

    def __init__(self, max_keypoints):
        self.orb = cv2.ORB_create(nfeatures=max_keypoints)
        self.max_keypoints = max_keypoints

    def __call__(self, image):
        keypoints, descriptors = self.orb.detectAndCompute(_to_uint8(image), None)
        return _from_keypoints(keypoints, descriptors, self.max_keypoints)


class SiftExtractor:
    norm = "l2"

    def __init__(self, max_keypoints):
        self.sift = cv2.SIFT_create(nfeatures=max_keypoints)
        self.max_keypoints = max_keypoints

    def __call__(self, image):
        keypoints, descriptors = self.sift.detectAndCompute(_to_uint8(image), None)
        xy, desc, scores = _from_keypoints(keypoints, descriptors, self.max_keypoints)
        if len(xy):
            desc = desc / np.maximum(np.linalg.norm(desc, axis=1, keepdims=True), 1e-6)
        return xy, desc.astype(np.float32), scores


class ShiTomasiOrbExtractor:
    """Shi-Tomasi corners (minimum eigenvalue, 4 px minimum distance as SuperPoint's NMS) described by ORB."""
    norm = "hamming"

    def __init__(self, max_keypoints, quality=0.001, min_distance=4):
        self.orb = cv2.ORB_create(nfeatures=max_keypoints)
        self.max_keypoints, self.quality, self.min_distance = max_keypoints, quality, min_distance

    def __call__(self, image):
        gray = _to_uint8(image)
        corners = cv2.goodFeaturesToTrack(gray, self.max_keypoints, self.quality, self.min_distance)
        if corners is None:
            return _from_keypoints([], None, 0)
        # goodFeaturesToTrack returns corners strongest first; keep that order as the response.
        keypoints = [cv2.KeyPoint(float(x), float(y), 31.0, -1, float(len(corners) - i))
                     for i, (x, y) in enumerate(corners.reshape(-1, 2))]
        keypoints, descriptors = self.orb.compute(gray, keypoints)
        return _from_keypoints(keypoints, descriptors, self.max_keypoints)


def build_extractors(weights, max_keypoints, device="cpu"):
    """{name: extractor}: every SuperPoint weights file given as name=path, then ORB, SIFT, Shi-Tomasi+ORB."""
    extractors = {}
    for spec in weights:
        name, path = spec.split("=", 1) if "=" in spec else (spec, spec)
        extractors[name] = SuperPointExtractor(path, max_keypoints, device)
    extractors["orb"] = OrbExtractor(max_keypoints)
    extractors["sift"] = SiftExtractor(max_keypoints)
    extractors["shitomasi+orb"] = ShiTomasiOrbExtractor(max_keypoints)
    return extractors
