"""Benchmark measures: repeatability and homography correctness (SuperPoint paper, section 7.2/7.3),
mutual-nearest-neighbour matching, and two-view relative pose errors with their AUC (SuperGlue's protocol)."""
import cv2
import numpy as np

from superpoint.homographies import warp_points


def repeatability(xy1, xy2, H, shape1, shape2, distance=3.0):
    """Fraction of points of both images, among those seen by the other image, that have a point of the
    other image within `distance` px after warping by the true H (image 1 -> image 2). None if no points."""
    def visible(points, shape):
        return (points[:, 0] >= 0) & (points[:, 0] <= shape[1] - 1) & (points[:, 1] >= 0) & (points[:, 1] <= shape[0] - 1)
    if len(xy1) == 0 or len(xy2) == 0:
        return 0.0
    warped1 = warp_points(xy1, H)
    warped2 = warp_points(xy2, np.linalg.inv(H))
    a = warped1[visible(warped1, shape2)]              # image-1 points seen by image 2, in image 2
    b = xy2[visible(warped2, shape1)]                  # image-2 points seen by image 1
    if len(a) + len(b) == 0:
        return None
    if len(a) == 0 or len(b) == 0:
        return 0.0
    d = np.linalg.norm(a[:, None] - b[None], axis=2)
    return float(((d.min(axis=1) <= distance).sum() + (d.min(axis=0) <= distance).sum()) / (len(a) + len(b)))


def mutual_nn(desc1, desc2, norm):
    """Index pairs [M,2] of mutual nearest neighbours (L2 on unit vectors, or Hamming on bit strings)."""
    if len(desc1) == 0 or len(desc2) == 0:
        return np.zeros((0, 2), int)
    matcher = cv2.BFMatcher(cv2.NORM_HAMMING if norm == "hamming" else cv2.NORM_L2, crossCheck=True)
    matches = matcher.match(np.ascontiguousarray(desc1), np.ascontiguousarray(desc2))
    return np.array([[m.queryIdx, m.trainIdx] for m in matches], int).reshape(-1, 2)


def corner_error(H_true, H_est, shape):
    """Mean distance of the four image corners mapped by the estimated vs the true homography."""
    h, w = shape
    corners = np.array([[0, 0], [w - 1, 0], [w - 1, h - 1], [0, h - 1]], np.float64)
    return float(np.linalg.norm(warp_points(corners, H_true) - warp_points(corners, H_est), axis=1).mean())


def estimate_homography(xy1, xy2, matches, ransac_px=3.0):
    if len(matches) < 4:
        return None
    cv2.setRNGSeed(0)
    H, _ = cv2.findHomography(xy1[matches[:, 0]].astype(np.float64), xy2[matches[:, 1]].astype(np.float64),
                              cv2.RANSAC, ransac_px, maxIters=5000, confidence=0.999)
    return H


def match_precision(xy1, xy2, matches, H, distance=3.0):
    if len(matches) == 0:
        return 0.0
    error = np.linalg.norm(warp_points(xy1[matches[:, 0]], H) - xy2[matches[:, 1]], axis=1)
    return float((error <= distance).mean())


def relative_pose(xy0, xy1, matches, K0, K1, pixel_threshold=1.0, method=cv2.RANSAC):
    """(R, t) from an essential matrix on normalised coordinates (RANSAC, threshold 1 px / mean focal), or None.

    method: cv2.RANSAC (the default) or e.g. cv2.USAC_MAGSAC (MAGSAC++ with local optimisation: steadier on
    short baselines, where one match more or less moves plain RANSAC's translation direction by degrees)."""
    if len(matches) < 5:
        return None
    def normalise(points, K):
        return (points - K[[0, 1], [2, 2]]) / K[[0, 1], [0, 1]]
    p0 = normalise(xy0[matches[:, 0]].astype(np.float64), K0)
    p1 = normalise(xy1[matches[:, 1]].astype(np.float64), K1)
    threshold = pixel_threshold / np.mean([K0[0, 0], K0[1, 1], K1[0, 0], K1[1, 1]])
    cv2.setRNGSeed(0)
    E, mask = cv2.findEssentialMat(p0, p1, np.eye(3), method=method, prob=0.99999, threshold=threshold)
    if E is None:
        return None
    best, best_inliers = None, 0
    for candidate in np.split(E, len(E) // 3):
        inliers, R, t, _ = cv2.recoverPose(candidate, p0, p1, np.eye(3), 1e9, mask=mask.copy())
        if inliers > best_inliers:
            best, best_inliers = (R, t.ravel()), inliers
    return best


def pose_error(T_0to1, estimate):
    """max(rotation error, translation direction error) in degrees; inf when no estimate."""
    if estimate is None:
        return float("inf")
    R, t = estimate
    R_true, t_true = T_0to1[:3, :3], T_0to1[:3, 3]
    cos_r = np.clip((np.trace(R_true.T @ R) - 1) / 2, -1, 1)
    cos_t = np.clip(np.dot(t, t_true) / (np.linalg.norm(t) * np.linalg.norm(t_true) + 1e-12), -1, 1)
    error_t = np.degrees(np.arccos(cos_t))
    return float(max(np.degrees(np.arccos(cos_r)), min(error_t, 180 - error_t)))


def pose_auc(errors, thresholds=(5, 10, 20)):
    """Area under the recall-vs-error curve up to each threshold, normalised to [0,1]."""
    errors = np.sort(np.asarray(errors, np.float64))
    recall = np.arange(1, len(errors) + 1) / len(errors)
    errors = np.concatenate([[0.0], errors])
    recall = np.concatenate([[0.0], recall])
    aucs = []
    for threshold in thresholds:
        last = np.searchsorted(errors, threshold)
        x = np.concatenate([errors[:last], [threshold]])
        y = np.concatenate([recall[:last], [recall[last - 1]]])
        aucs.append(float(np.sum(np.diff(x) * (y[1:] + y[:-1]) / 2) / threshold))   # trapezoid rule (np.trapz is gone in NumPy 2)
    return aucs
