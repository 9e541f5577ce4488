"""The ball and the obstacles (robots) in the omni image (chapter 4.1).

Requires: a frame read along the radial scan rays (``lines.RaySamples`` of ``lines.ScanRays``), the calibrated
``ColorTable`` (for the ball's full-resolution region), the ``MirrorModel`` (the rays carry it).
Provides:

- ``BallDetector.detect(samples, table) -> BallDetection | None``: the ball on the ground, body frame [m].
- ``ObstacleDetector.detect(samples) -> list[ObstacleDetection]``: robots (black), body frame [m].
- ``BallParams``, ``ObstacleParams`` (frozen, validated).

Ball: BALL samples on the rays are the seeds; 8-connected groups of them (in ray x radius, across the
0/360 deg seam) are candidates, of which the ``max_candidates`` largest grow at full resolution: the
window around the seeds is classified and the BALL region connected to the seeds is the blob. The blob's
pixel nearest the image centre shows where the ball nears the ground along its bearing: its ground distance
d_n (half a pixel inwards) gives the centre's horizontal distance D of a sphere of radius R on the ground
whose near tangent ray from the mirror's viewpoint (height h) meets the ground at d_n:
D = d_n (1 - R/h) + R sqrt(h^2 + d_n^2) / h; the bearing is the blob's angular centre. A blob is plausible
when its angular width and radial extent are within ``width_ratio_range`` / ``depth_ratio_range`` of those
a ball at D shows (2 asin(R/D); near to far tangent ray); confidence = the product of min(ratio, 1/ratio)
of both; the most confident plausible blob is the ball.

Obstacles: on each ray outside ``excluded_bearings`` (where the robot's own body, e.g. the mirror holder's
struts, reaches into the ring) the first BLACK run of at least ``min_run`` samples is a robot's near edge
(a robot is taller than the viewpoint: it blacks out a wedge from its near edge to the rim). Neighbouring
usable rays (excluded rays are skipped, not gaps) whose near edges differ by at most ``join_gap`` +
``join_gap_fraction`` x distance form one obstacle of at least ``min_rays`` rays; a group wider than
``split_factor`` robot widths is split into robot-wide parts.
Each obstacle lies at its nearest edge's distance plus ``robot_radius`` along its angular centre.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import cv2
import numpy as np
import numpy.typing as npt

from nubot_common.color_class import ColorClass
from nubot_common.mirror import MirrorModel
from omni_vision import OmniVisionError
from omni_vision.colors import ColorTable
from omni_vision.lines import RaySamples, ScanRays

_HALF_PIXEL = 0.5  # an edge lies half a pixel (sample) inwards of the first pixel (sample) past it
_MIN_EXTENT = 1.0  # [px] the least radial extent a blob can have (one pixel)


def _check_range(name: str, value: tuple[float, float], low: float, high: float) -> None:
    if not (len(value) == 2 and all(math.isfinite(v) for v in value) and low <= value[0] < value[1] <= high):
        raise OmniVisionError(f"{name} must be an increasing pair within [{low}, {high}], got {value}")


@dataclass(frozen=True)
class BallParams:
    ball_radius: float = 0.11  # [m]
    min_seed_samples: int = 1  # BALL ray samples a candidate needs (a ball at 9 m spans one or two rays)
    max_candidates: int = 4  # the largest candidates grown at full resolution
    window_margin: float = 3.0  # [px] around a candidate's seeds, beyond the rays' spacing there
    min_pixels: int = 6  # a smaller blob is noise
    width_ratio_range: tuple[float, float] = (0.4, 2.0)  # blob's angular width / a ball's at its distance
    depth_ratio_range: tuple[float, float] = (0.3, 2.0)  # blob's radial extent / a ball's at its distance

    def __post_init__(self) -> None:
        if not (math.isfinite(self.ball_radius) and 0.01 <= self.ball_radius <= 1.0):
            raise OmniVisionError(f"ball_radius must be in [0.01, 1] m, got {self.ball_radius}")
        for name in ("min_seed_samples", "max_candidates", "min_pixels"):
            if not (isinstance(getattr(self, name), int) and getattr(self, name) >= 1):
                raise OmniVisionError(f"{name} must be an integer >= 1, got {getattr(self, name)!r}")
        if not (math.isfinite(self.window_margin) and 0.0 <= self.window_margin <= 100.0):
            raise OmniVisionError(f"window_margin must be in [0, 100] px, got {self.window_margin}")
        _check_range("width_ratio_range", self.width_ratio_range, 0.0, 100.0)
        _check_range("depth_ratio_range", self.depth_ratio_range, 0.0, 100.0)


@dataclass(frozen=True)
class ObstacleParams:
    robot_radius: float = 0.26  # [m] obstacles are robots of this radius
    min_run: int = 4  # [samples] a shorter BLACK run is noise (a robot at 8 m shows ~4 samples before the rim)
    min_rays: int = 2  # a robot at 8 m spans 3-4 rays of 1 deg
    # [deg] (from, to) counter-clockwise: bearings where the own body reaches into the ring (set per robot: e.g.
    # sim_visual draws the mirror holder's struts 4 px wide at 60, 180, 300 deg: ((56, 64), (176, 184), (296, 304)))
    excluded_bearings: tuple[tuple[float, float], ...] = ()
    join_gap: float = 0.35  # [m] adjacent rays' near edges this close (plus the fraction) are one obstacle
    join_gap_fraction: float = 0.1  # of the near edge's distance (one pixel is ~3 % of it at 5 m)
    split_factor: float = 1.6  # a group wider than this many robot widths is split into robot-wide parts

    def __post_init__(self) -> None:
        if not (math.isfinite(self.robot_radius) and 0.01 <= self.robot_radius <= 2.0):
            raise OmniVisionError(f"robot_radius must be in [0.01, 2] m, got {self.robot_radius}")
        for name in ("min_run", "min_rays"):
            if not (isinstance(getattr(self, name), int) and getattr(self, name) >= 1):
                raise OmniVisionError(f"{name} must be an integer >= 1, got {getattr(self, name)!r}")
        for pair in self.excluded_bearings:
            if not (len(pair) == 2 and all(math.isfinite(a) and -360.0 <= a <= 360.0 for a in pair)):
                raise OmniVisionError(f"excluded_bearings holds (from, to) pairs in [-360, 360] deg, got {pair}")
        for name, low, high in (("join_gap", 0.0, 10.0), ("join_gap_fraction", 0.0, 1.0),
                                ("split_factor", 1.0, 100.0)):
            value = getattr(self, name)
            if not (math.isfinite(value) and low <= value <= high):
                raise OmniVisionError(f"{name} must be in [{low}, {high}], got {value}")


@dataclass(frozen=True)
class BallDetection:
    """The ball: centre x, y [m] in the body frame (on the ground), ``pixel`` (u, v) [px] the blob's centroid,
    ``size_px`` its pixels, ``confidence`` in (0, 1] (how well its size fits a ball at that distance)."""

    x: float
    y: float
    pixel: tuple[float, float]
    size_px: int
    confidence: float


@dataclass(frozen=True)
class ObstacleDetection:
    """An obstacle (robot): centre x, y [m] in the body frame, ``angular_width`` [rad] it covers,
    ``near_distance`` [m] of its nearest edge."""

    x: float
    y: float
    angular_width: float
    near_distance: float


def ball_centre_distance(near_distance: np.ndarray | float, ball_radius: float,
                         viewpoint_height: float) -> np.ndarray:
    """Horizontal distance [m] of a ball's centre whose near tangent ray from the viewpoint meets the ground at
    ``near_distance`` [m]."""
    d = np.asarray(near_distance, dtype=float)
    h, r = viewpoint_height, ball_radius
    return d * (1.0 - r / h) + r * np.sqrt(h * h + d * d) / h


def ball_far_distance(centre_distance: float, ball_radius: float, viewpoint_height: float) -> float:
    """Where [m] the far tangent ray from the viewpoint past a ball centred at ``centre_distance`` meets the
    ground (inf if it never does: a ball reaching the viewpoint's height)."""
    h, r, big_d = viewpoint_height, ball_radius, centre_distance
    a, b = 1.0 - r / h, r / h
    # D = a d - b sqrt(h^2 + d^2) solved for d (the root with a d >= D)
    quadratic = a * a - b * b
    if quadratic <= 0.0:
        return math.inf
    disc = (a * big_d) ** 2 - quadratic * (big_d * big_d - (b * h) ** 2)
    return (a * big_d + math.sqrt(max(disc, 0.0))) / quadratic


def _wrap(angle: np.ndarray) -> np.ndarray:
    return (angle + math.pi) % (2 * math.pi) - math.pi


class BallDetector:
    """Finds the ball (see the module docstring)."""

    def __init__(self, rays: ScanRays, params: BallParams | None = None) -> None:
        params = params if params is not None else BallParams()
        self.rays = rays
        self.mirror: MirrorModel = rays.mirror
        self.params = params
        self._spacing = 2 * math.pi / rays.count  # [rad] between rays

    def detect(self, samples: RaySamples, table: ColorTable) -> BallDetection | None:
        """The most plausible ball of the frame, or None."""
        if samples.rays is not self.rays:
            raise OmniVisionError("the samples were read along other rays than this detector's")
        n = self.rays.samples_per_ray
        seeds = np.flatnonzero(samples.classes.ravel() == ColorClass.BALL)
        if len(seeds) == 0:
            return None
        seed_ray, seed_k = np.divmod(seeds, n)
        # roll an empty ray to the top so that no candidate is cut at the 0/360 deg seam, and label the seeds'
        # bounding box only
        seeded = np.zeros(self.rays.count, np.bool_)
        seeded[seed_ray] = True
        empty = np.flatnonzero(~seeded)
        offset = int(empty[0]) if len(empty) else 0
        row = (seed_ray - offset) % self.rays.count
        top, left = int(row.min()), int(seed_k.min())
        box = np.zeros((int(row.max()) + 1 - top, int(seed_k.max()) + 1 - left), np.uint8)
        box[row - top, seed_k - left] = 1
        _, labels, stats, _ = cv2.connectedComponentsWithStats(box, connectivity=8)
        seed_label = labels[row - top, seed_k - left]
        area = stats[1:, cv2.CC_STAT_AREA]
        best: BallDetection | None = None
        for label in np.argsort(-area, kind="stable")[:self.params.max_candidates] + 1:
            if stats[label, cv2.CC_STAT_AREA] < self.params.min_seed_samples:
                break
            mine = seed_label == label
            found = self._grow(samples, table, self.rays.u[seed_ray[mine], seed_k[mine]],
                               self.rays.v[seed_ray[mine], seed_k[mine]])
            if found is not None and (best is None or found.confidence > best.confidence):
                best = found
        return best

    def _grow(self, samples: RaySamples, table: ColorTable, seed_u: np.ndarray,
              seed_v: np.ndarray) -> BallDetection | None:
        """The ball region grown from the seed pixels at full resolution, if it is plausibly a ball."""
        mirror, p = self.mirror, self.params
        seed_r = np.hypot(seed_u - mirror.centre_u, seed_v - mirror.centre_v)
        margin = p.window_margin + self._spacing * float(seed_r.max())
        u0 = max(int(seed_u.min() - margin), 0)
        u1 = min(int(seed_u.max() + margin) + 1, mirror.width)
        v0 = max(int(seed_v.min() - margin), 0)
        v1 = min(int(seed_v.max() + margin) + 1, mirror.height)
        du = np.arange(u0, u1) - mirror.centre_u
        dv = np.arange(v0, v1)[:, None] - mirror.centre_v
        radius = np.hypot(du, dv)
        ball = (table.classify_rgb(samples.image[v0:v1, u0:u1]) == ColorClass.BALL)
        ball &= (radius >= mirror.r_min) & (radius <= mirror.r_max)
        count, labels = cv2.connectedComponents(ball.view(np.uint8), connectivity=8)
        grown = np.unique(labels[seed_v - v0, seed_u - u0])
        grown = grown[grown > 0]
        if len(grown) == 0:
            return None
        member = np.zeros(count, np.bool_)
        member[grown] = True
        pv, pu = np.nonzero(member[labels])
        if len(pu) < p.min_pixels:
            return None
        pu, pv = pu + u0, pv + v0
        r = radius[pv - v0, pu - u0]
        bearing = np.arctan2(-(pu - mirror.centre_u), -(pv - mirror.centre_v))
        reference = float(bearing[np.argmin(r)])
        relative = _wrap(bearing - reference)
        centre = reference + 0.5 * float(relative.min() + relative.max())
        near_radius = float(r.min()) - _HALF_PIXEL
        near = float(mirror.distance(near_radius))
        distance = float(ball_centre_distance(near, p.ball_radius, mirror.viewpoint_height))

        # plausibility: the angular width and radial extent a ball at this distance shows
        pixel_angle = 1.0 / float(r.mean())
        width = float(relative.max() - relative.min()) + pixel_angle
        expected_width = 2.0 * math.asin(min(1.0, p.ball_radius / max(distance, p.ball_radius)))
        far = ball_far_distance(distance, p.ball_radius, mirror.viewpoint_height)
        depth = float(r.max()) + _HALF_PIXEL - near_radius
        expected_depth = float(mirror.radius(far)) - near_radius if math.isfinite(far) else mirror.r_max - near_radius
        width_ratio = width / expected_width
        depth_ratio = depth / max(expected_depth, _MIN_EXTENT)
        if not (p.width_ratio_range[0] <= width_ratio <= p.width_ratio_range[1]
                and p.depth_ratio_range[0] <= depth_ratio <= p.depth_ratio_range[1]):
            return None
        confidence = min(width_ratio, 1.0 / width_ratio) * min(depth_ratio, 1.0 / depth_ratio)
        return BallDetection(x=distance * math.cos(centre), y=distance * math.sin(centre),
                             pixel=(float(pu.mean()), float(pv.mean())), size_px=len(pu), confidence=confidence)


class ObstacleDetector:
    """Finds obstacles (robots) on the scan rays (see the module docstring)."""

    def __init__(self, rays: ScanRays, params: ObstacleParams | None = None) -> None:
        params = params if params is not None else ObstacleParams()
        self.rays = rays
        self.mirror: MirrorModel = rays.mirror
        self.params = params
        self._step = 2 * math.pi / rays.count  # [rad] between rays
        bearing = np.degrees(rays.bearings)
        excluded = np.zeros(rays.count, np.bool_)
        for start, end in params.excluded_bearings:
            span = (end - start) % 360.0
            excluded |= (bearing - start) % 360.0 <= span
        self._usable: npt.NDArray[np.bool_] = ~excluded
        self._usable_rays = np.flatnonzero(self._usable)
        # each sample's edge: half a sample inwards of it, as a ground distance [m]
        inner = np.empty_like(rays.pixel_radius)
        inner[:, 1:] = 0.5 * (rays.pixel_radius[:, 1:] + rays.pixel_radius[:, :-1])
        inner[:, 0] = rays.pixel_radius[:, 0] - _HALF_PIXEL
        self._edge_distance = self.mirror.distance(np.maximum(inner, 0.0))
        self._run_kernel = np.ones((1, params.min_run), np.uint8)

    def detect(self, samples: RaySamples) -> list[ObstacleDetection]:
        """The obstacles of the frame, ordered by bearing from 0 (body +x) counter-clockwise."""
        if samples.rays is not self.rays:
            raise OmniVisionError("the samples were read along other rays than this detector's")
        p = self.params
        black = cv2.compare(samples.classes, int(ColorClass.BLACK), cv2.CMP_EQ)
        # a sample begins a run of >= min_run black samples where the minimum over it and the next ones is black
        run = cv2.erode(black, self._run_kernel, anchor=(0, 0), borderType=cv2.BORDER_CONSTANT, borderValue=0)
        first = np.argmax(run, axis=1)  # the first such sample of each ray (0 where none)
        found = (run[np.arange(self.rays.count), first] > 0) & self._usable
        near = np.where(found, self._edge_distance[np.arange(self.rays.count), first], np.nan)
        # group along the usable rays only: an excluded bearing does not cut a robot seen on both sides of it
        usable = self._usable_rays
        count, kept = self.rays.count, len(usable)
        seen = near[usable]
        detected = np.isfinite(seen)
        if not detected.any():
            return []
        following = np.concatenate((seen[1:], seen[:1]))
        with np.errstate(invalid="ignore"):
            joined = detected & np.isfinite(following) & (
                np.abs(seen - following) <= p.join_gap + p.join_gap_fraction * np.fmin(seen, following))
        starts = np.flatnonzero(detected & ~np.concatenate((joined[-1:], joined[:-1]))).tolist()
        ends = np.flatnonzero(detected & ~joined).tolist()
        if not starts:  # every usable ray sees one obstacle all around
            starts, ends = [0], [kept - 1]
        elif ends[0] < starts[0]:  # the first group ends after the seam: it belongs to the last start
            ends = ends[1:] + [ends[0] + kept]
        unwrapped = np.concatenate((usable, usable + count))  # ray index of the i-th usable ray, twice around
        around = np.concatenate((near, near))  # rays a..b of a group across the seam are around[a:b + 1]
        obstacles = []
        for start, end in zip(starts, ends):
            if end + 1 - start < p.min_rays:
                continue
            first_ray, last_ray = int(unwrapped[start]), int(unwrapped[end])
            nearest = float(np.nanmin(around[first_ray:last_ray + 1]))
            rays = last_ray + 1 - first_ray
            robot_rays = 2.0 * math.asin(min(1.0, p.robot_radius / (nearest + p.robot_radius))) / self._step
            parts = max(1, round(rays / robot_rays)) if rays > p.split_factor * robot_rays else 1
            bounds = [first_ray + (rays * i) // parts for i in range(parts + 1)]
            for a, b in zip(bounds[:-1], bounds[1:]):
                part = around[a:b]
                part = part[np.isfinite(part)]  # a part may lie wholly on excluded rays
                obstacles.append(self._obstacle(a, b - 1, float(part.min()) if len(part) else nearest))
        return sorted(obstacles, key=lambda o: math.atan2(o.y, o.x) % (2 * math.pi))

    def _obstacle(self, first_ray: int, last_ray: int, nearest: float) -> ObstacleDetection:
        centre = 0.5 * (first_ray + last_ray) * self._step
        distance = nearest + self.params.robot_radius
        return ObstacleDetection(x=distance * math.cos(centre), y=distance * math.sin(centre),
                                 angular_width=(last_ray + 1 - first_ray) * self._step, near_distance=nearest)
