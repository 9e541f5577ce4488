"""The ball in one camera's cloud: orange candidates, their clusters, a RANSAC sphere fit of the known radius.

Requires: a ``Cloud`` (camera frame, the camera at the origin), the ball's radius [m], ``DetectionParams`` and a
``numpy.random.Generator`` (the RANSAC samples). Provides ``detect_ball`` -> ``Detection`` (the best fitted
sphere's centre in the camera frame with its inliers and its standard error) or ``None`` with the reason in
``DetectionReport``; ``fit_sphere`` (the RANSAC on its own) and ``orange_mask``.

The fit: the radius is known, so three points of the ball's visible cap fix a centre: their circumcircle's
centre, pushed along the circle's normal by sqrt(R^2 - r^2), to the side where the camera can see the three points
(the surface there faces it). All hypotheses are drawn and scored at once (an iterations x points residual matrix, MSAC
scores: truncated squared residuals), plus one from the cluster's centroid pushed back by 2R/3 (the mean depth of
a hemisphere seen from afar), which holds when only a handful of points see the ball. The best is refined by a
few Gauss-Newton steps on its inliers. The inlier band grows with the depth noise at the ball's distance.

Parameters (``DetectionParams``): the orange test on RGB, the farthest range, the clusters' link distance, least
points and largest extent, the RANSAC's iterations, inlier band (a base plus a multiple of the sensor's depth
noise std: ``noise_constant + noise_quadratic * d^2`` [m] at d [m]), least inlier share and the Gauss-Newton steps.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from scipy.sparse import coo_matrix
from scipy.sparse.csgraph import connected_components
from scipy.spatial import cKDTree

from nubot_common.clouds import Cloud
from nubot_common.params import require_non_negative, require_positive

_LIMB_SLACK = 0.3  # a noisy point near the ball's outline may seem to face slightly away: this share of R allowed


@dataclass(frozen=True)
class DetectionParams:
    min_red: int = 140  # [0-255] an orange point's red at least this
    min_red_minus_green: int = 60  # ... and its red this much above its green
    min_red_minus_blue: int = 110  # ... and above its blue
    max_range: float = 9.0  # [m] farther points are ignored
    link_distance: float = 0.12  # [m] orange points this close belong to one cluster
    min_points: int = 4  # a cluster needs this many points to be fitted
    max_extent: float = 0.40  # [m] a cluster wider than this is no ball (bounding-box diagonal)
    max_clusters: int = 3  # the largest clusters fitted per frame
    iterations: int = 48  # RANSAC hypotheses per cluster
    inlier_base: float = 0.012  # [m] inlier band at zero depth noise
    inlier_noise_factor: float = 2.5  # ... plus this many depth-noise stds
    noise_constant: float = 0.002  # [m] the sensor's depth noise std at zero depth
    noise_quadratic: float = 0.0003  # [1/m] ... growing with depth^2
    min_inlier_share: float = 0.6  # a fit keeps at least this share of its cluster
    refine_steps: int = 4  # Gauss-Newton steps on the inliers

    def __post_init__(self) -> None:
        for name in ("min_red", "min_red_minus_green", "min_red_minus_blue"):
            if not 0 <= getattr(self, name) <= 255:
                raise ValueError(f"{name} must lie in [0, 255], got {getattr(self, name)}")
        require_positive(self, "max_range", "link_distance", "max_extent", "inlier_base")
        require_non_negative(self, "inlier_noise_factor", "noise_constant", "noise_quadratic")
        for name, low in (("min_points", 3), ("max_clusters", 1), ("iterations", 1)):
            if getattr(self, name) < low:
                raise ValueError(f"{name} must be at least {low}, got {getattr(self, name)}")
        if not 0.0 < self.min_inlier_share <= 1.0:
            raise ValueError(f"min_inlier_share must lie in (0, 1], got {self.min_inlier_share}")
        if not 0 <= self.refine_steps <= 50:
            raise ValueError(f"refine_steps must lie in [0, 50], got {self.refine_steps}")

    def depth_noise(self, distance: float) -> float:
        return self.noise_constant + self.noise_quadratic * distance * distance

    def inlier_band(self, distance: float) -> float:
        return self.inlier_base + self.inlier_noise_factor * self.depth_noise(distance)


@dataclass(frozen=True)
class SphereFit:
    centre: np.ndarray  # (3,) [m]
    inliers: int
    points: int  # points the fit was offered
    rms: float  # [m] inliers' residual rms


@dataclass(frozen=True)
class Detection:
    centre: np.ndarray  # (3,) [m], camera frame
    sigma: float  # [m] standard error of the centre (depth noise over the inliers)
    inliers: int
    points: int  # the cluster's size
    touches_border: bool  # the cluster reaches the image's border: the ball may be partly out of view


@dataclass(frozen=True)
class DetectionReport:
    detection: Detection | None
    reason: str  # why there is none ("" with a detection)
    orange: int  # orange points in range
    clusters: int


def orange_mask(rgb: np.ndarray, p: DetectionParams) -> np.ndarray:
    c = rgb.astype(np.int16)
    r, g, b = c[:, 0], c[:, 1], c[:, 2]
    return (r >= p.min_red) & (r - g >= p.min_red_minus_green) & (r - b >= p.min_red_minus_blue)


def _clusters(points: np.ndarray, link: float) -> list[np.ndarray]:
    """Indices of each connected group of points (single linkage at ``link``), largest first."""
    pairs = cKDTree(points).query_pairs(link, output_type="ndarray")
    n = len(points)
    graph = coo_matrix((np.ones(len(pairs)), (pairs[:, 0], pairs[:, 1])), shape=(n, n))
    count, labels = connected_components(graph, directed=False)
    groups = [np.flatnonzero(labels == k) for k in range(count)]
    return sorted(groups, key=len, reverse=True)


def sphere_hypotheses(points: np.ndarray, radius: float, samples: np.ndarray) -> np.ndarray:
    """Centres (2K x 3) of the spheres of ``radius`` through the K point triples ``samples`` (K x 3 indices), both
    sides of each triple's plane; NaN rows where no such sphere passes through the triple or where the camera (the
    origin) could not see the three points on it (its surface there faces away)."""
    a, b, c = points[samples[:, 0]], points[samples[:, 1]], points[samples[:, 2]]
    ab, ac = b - a, c - a
    normal = np.cross(ab, ac)
    n2 = (normal * normal).sum(axis=1)
    with np.errstate(invalid="ignore", divide="ignore"):
        offset = (np.cross(normal, ab) * (ac * ac).sum(axis=1, keepdims=True)
                  + np.cross(ac, normal) * (ab * ab).sum(axis=1, keepdims=True)) / (2.0 * n2[:, None])
        circle = a + offset
        r2 = (offset * offset).sum(axis=1)
        lift = normal / np.sqrt(n2)[:, None] * np.sqrt(radius * radius - r2)[:, None]
        centres = np.concatenate([circle + lift, circle - lift])
    bad = np.tile((n2 < 1e-12) | (r2 > radius * radius), 2)
    for p in (a, b, c):  # a visible point's outward normal (p - centre) has no large part along the view ray
        q = np.concatenate([p, p])
        facing = ((q - centres) * q).sum(axis=1) / np.maximum(np.linalg.norm(q, axis=1), 1e-9)
        bad |= ~(facing < _LIMB_SLACK * radius)
    centres[bad] = np.nan
    return centres


def fit_sphere(points: np.ndarray, radius: float, band: float, iterations: int, refine_steps: int,
               rng: np.random.Generator) -> SphereFit | None:
    """The sphere of ``radius`` that best explains ``points`` (N x 3, camera at the origin), or None for fewer
    than three points."""
    n = len(points)
    if n < 3:
        return None
    centroid = points.mean(axis=0)
    guesses = [centroid + (2.0 / 3.0) * radius * centroid / max(float(np.linalg.norm(centroid)), 1e-9)]
    samples = rng.integers(0, n, size=(iterations, 3))
    keep = (samples[:, 0] != samples[:, 1]) & (samples[:, 1] != samples[:, 2]) & (samples[:, 0] != samples[:, 2])
    hyps = np.vstack([np.array(guesses), sphere_hypotheses(points, radius, samples[keep])])
    hyps = hyps[np.isfinite(hyps).all(axis=1)]
    diff = points[None, :, :] - hyps[:, None, :]
    residual = np.abs(np.sqrt((diff * diff).sum(axis=2)) - radius)
    scores = (np.minimum(residual, band) ** 2).sum(axis=1)
    centre = hyps[int(np.argmin(scores))]
    inliers = points[np.abs(np.linalg.norm(points - centre, axis=1) - radius) < band]
    for _ in range(refine_steps):
        if len(inliers) < 3:
            break
        d = inliers - centre
        dist = np.linalg.norm(d, axis=1)
        jac = -d / np.maximum(dist, 1e-9)[:, None]
        step, *_ = np.linalg.lstsq(jac, -(dist - radius), rcond=None)
        centre = centre + step
        if float(np.linalg.norm(step)) < 1e-5:
            break
    res = np.abs(np.linalg.norm(points - centre, axis=1) - radius)
    inside = res < band
    rms = float(np.sqrt(np.mean(res[inside] ** 2))) if inside.any() else math.inf
    return SphereFit(centre, int(inside.sum()), n, rms)


def _touches_border(indices: np.ndarray, shape: tuple[int, int]) -> bool:
    h, w = shape
    if h <= 1:
        return False
    rows, cols = np.divmod(indices, w)
    return bool((rows.min() == 0) | (rows.max() == h - 1) | (cols.min() == 0) | (cols.max() == w - 1))


def detect_ball(cloud: Cloud, radius: float, p: DetectionParams, rng: np.random.Generator) -> DetectionReport:
    """The ball in ``cloud`` (camera frame), or the reason there is none."""
    if len(cloud) == 0:
        return DetectionReport(None, "empty cloud", 0, 0)
    finite = np.isfinite(cloud.points).all(axis=1)
    dist2 = np.where(finite, (np.nan_to_num(cloud.points) ** 2).sum(axis=1), np.inf)
    candidates = np.flatnonzero(finite & (dist2 <= p.max_range ** 2) & orange_mask(cloud.rgb, p))
    if len(candidates) < p.min_points:
        reason = "no finite points" if not finite.any() else f"{len(candidates)} orange points in range"
        return DetectionReport(None, reason, len(candidates), 0)
    points = cloud.points[candidates]
    groups = _clusters(points, p.link_distance)
    best: Detection | None = None
    reasons = []
    for group in groups[:p.max_clusters]:
        if len(group) < p.min_points:
            reasons.append(f"cluster of {len(group)} points")
            break
        cluster = points[group]
        extent = float(np.linalg.norm(cluster.max(axis=0) - cluster.min(axis=0)))
        if extent > max(p.max_extent, 2.0 * radius):
            reasons.append(f"cluster {extent:.2f} m wide")
            continue
        distance = float(np.linalg.norm(cluster.mean(axis=0)))
        band = p.inlier_band(distance)
        fit = fit_sphere(cluster, radius, band, p.iterations, p.refine_steps, rng)
        if fit is None or fit.inliers < max(p.min_points - 1, p.min_inlier_share * len(cluster)):
            reasons.append(f"sphere fit kept {0 if fit is None else fit.inliers} of {len(cluster)} points")
            continue
        sigma = p.depth_noise(distance) / math.sqrt(fit.inliers) + 0.25 * fit.rms
        found = Detection(fit.centre, sigma, fit.inliers, len(cluster),
                          _touches_border(candidates[group], cloud.shape))
        if best is None or found.inliers > best.inliers:
            best = found
    if best is None:
        return DetectionReport(None, "; ".join(reasons) or "no cluster", len(candidates), len(groups))
    return DetectionReport(best, "", len(candidates), len(groups))
