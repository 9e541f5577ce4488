"""The ball in the front camera's image and where it lies relative to the robot (chapter 4.2).

Requires: an RGB frame (uint8, the camera's size), omni_vision's calibrated ``ColorTable`` (one colour concept
for every camera) and the calibrated ``PinholeCamera``. Provides ``BallLocator.locate(rgb) -> BallSighting``
and ``BallParams`` (frozen, validated).

Colour segmentation: the pixels of a grid every ``seed_step`` px are classified with the table; 8-connected
groups of BALL cells are candidates (the ``max_candidates`` largest). Region growing (OpenCV's flood fill)
starts at each candidate's seed pixel nearest its centre, in a window around the candidate (its seed cells' box
plus ``window_margin``), and takes the 8-connected neighbours whose colour differs by at most
``grow_tolerance`` grey levels per channel from the pixel it grows from, never pixels the table calls carpet,
line or robot: so the ball's shaded underside, which the table may not know (UNKNOWN), joins the region.
A region touching the image border (within ``border_margin``) is a ball partly out of view: its position is
not known. The region's boundary pixels, undistorted into rays, are the rim of the cone of rays tangent to
the sphere: the least-squares solution w of r_i . w = 1 gives the cone's axis w/|w| (the ray through the
ball's centre, free of the perspective shift a blob's centroid has) and its half-angle acos(1/|w|). The
centre's ray meets the plane z = the ball's radius (the world description's; a ball on the ground) at the ball's
position in the body frame. Checks: the region's boundary against the cone's rim (``max_rim_error``: a round
region), its area against the cone's (``area_ratio_range``), and the height of the centre the
cone's angle gives (distance = radius / sin(half-angle)) against the radius (``max_height_error``): a ball in
the air would be projected to a wrong place, so it is reported as not known.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import Enum

import cv2
import numpy as np

from front_vision import FrontVisionError
from nubot_common.camera_model import PinholeCamera
from nubot_common.color_class import ColorClass
from nubot_common.world_description import WorldDescription
from omni_vision.colors import ColorTable

_REGION = 2  # the flood fill's mark of the grown region (1: pixels that stop it)


class Sighting(Enum):
    SEEN = "seen"  # on the ground, wholly in view: the position is known
    NOT_SEEN = "not seen"  # no ball-coloured region
    OUT_OF_VIEW = "partly out of view"  # the region touches the image border
    IMPLAUSIBLE = "implausible"  # a region whose shape or height is no ball on the ground


@dataclass(frozen=True)
class BallParams:
    seed_step: int = 2  # [px] the grid of pixels classified for seeds
    max_candidates: int = 3  # the largest seed groups grown
    min_pixels: int = 20  # a smaller region is noise
    window_margin: int = 4  # [px] beyond a candidate's seed cells, where its region may grow
    grow_tolerance: int = 16  # [grey levels] per channel between neighbouring pixels of a region
    border_margin: int = 1  # [px] a region this near the image border is partly out of view
    area_ratio_range: tuple[float, float] = (0.6, 1.5)  # region's area / the area of the fitted cone's image
    max_height_error: float = 0.15  # [m] the cone's centre height minus the radius, at most
    max_rim_error: float = 1.5  # [px] RMS distance of the region's boundary from the fitted cone's rim

    def __post_init__(self) -> None:
        for name, low, high in (("seed_step", 1, 16), ("max_candidates", 1, 20), ("min_pixels", 3, 100000),
                                ("window_margin", 0, 64), ("grow_tolerance", 0, 255), ("border_margin", 0, 50)):
            value = getattr(self, name)
            if not (isinstance(value, int) and low <= value <= high):
                raise FrontVisionError(f"{name} must be an integer in [{low}, {high}], got {value!r}")
        ratio_low, ratio_high = self.area_ratio_range
        if not (len(self.area_ratio_range) == 2 and 0.0 < ratio_low < 1.0 < ratio_high < 10.0):
            raise FrontVisionError(f"area_ratio_range must be (low < 1 < high), got {self.area_ratio_range}")
        for name in ("max_height_error", "max_rim_error"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0.0):
                raise FrontVisionError(f"{name} must be positive, got {getattr(self, name)}")


@dataclass(frozen=True)
class BallSighting:
    """What one frame says about the ball: ``sighting``; when SEEN, its centre (x, y) [m] in the robot's body
    frame; ``pixel``: the image point of its centre's ray (u, v) [px] when a region was fitted."""

    sighting: Sighting
    x: float = math.nan  # [m] body frame
    y: float = math.nan  # [m]
    pixel: tuple[float, float] | None = None
    pixels: int = 0  # the region's size [px]

    @property
    def known(self) -> bool:
        return self.sighting is Sighting.SEEN


@dataclass(frozen=True)
class ConeFit:
    """The cone of rays tangent to a sphere, from its rim's rays (camera frame)."""

    axis: np.ndarray  # unit vector, camera frame
    half_angle: float  # [rad]


def fit_tangent_cone(rays: np.ndarray) -> ConeFit | None:
    """The cone whose rim passes closest to the unit ``rays`` (N x 3): r . w = 1 in least squares; None when
    the rays do not span one (fewer than 3, degenerate)."""
    if len(rays) < 3:
        return None
    w, *_ = np.linalg.lstsq(rays, np.ones(len(rays)), rcond=None)
    norm = float(np.linalg.norm(w))
    if not (math.isfinite(norm) and norm > 1.0):
        return None
    return ConeFit(w / norm, math.acos(1.0 / norm))


class BallLocator:
    """Finds the ball in front-camera frames of one camera."""

    def __init__(self, camera: PinholeCamera, table: ColorTable, params: BallParams | None = None,
                 ball_radius: float = WorldDescription().ball.radius):
        self.camera, self.table = camera, table
        self.params = params if params is not None else BallParams()
        self.ball_radius = ball_radius  # [m] the world's ball (WorldDescription.ball.radius)

    def locate(self, rgb: np.ndarray) -> BallSighting:
        """The ball in ``rgb`` (uint8, camera.height x camera.width x 3; checked by the caller)."""
        p = self.params
        step = p.seed_step
        seeds = (self.table.classify_rgb(rgb[::step, ::step]) == ColorClass.BALL).astype(np.uint8)
        count, labels, stats, centroids = cv2.connectedComponentsWithStats(seeds, connectivity=8)
        if count <= 1:
            return BallSighting(Sighting.NOT_SEEN)
        order = 1 + np.argsort(-stats[1:, cv2.CC_STAT_AREA], kind="stable")[:p.max_candidates]
        best: BallSighting | None = None
        for k in order:
            sighting = self._grow(rgb, labels == k, stats[k], centroids[k])
            if sighting is None:
                continue
            if best is None or _rank(sighting) > _rank(best):
                best = sighting
        return best if best is not None else BallSighting(Sighting.NOT_SEEN)

    def _flood(self, rgb: np.ndarray, window_box: tuple[int, int, int, int],
               seed: tuple[int, int]) -> tuple[int, tuple[int, int, int, int], np.ndarray] | None:
        """Region growing from ``seed`` (u, v) inside ``window_box`` (u0, v0, u1, v1): (area, its box in the
        window (x, y, w, h), its mask (uint8 0/1) in that box); None when the seed is no BALL pixel."""
        u0, v0, u1, v1 = window_box
        window = np.ascontiguousarray(rgb[v0:v1, u0:u1])
        classes = self.table.classify_rgb(window)
        if classes[seed[1] - v0, seed[0] - u0] != ColorClass.BALL:
            return None
        # Pixels of the carpet, the lines and the robots stop the growth (mask 1); the region is marked 2.
        mask = np.ones((v1 - v0 + 2, u1 - u0 + 2), np.uint8)
        mask[1:-1, 1:-1] = (classes == ColorClass.GREEN) | (classes == ColorClass.WHITE) | (classes == ColorClass.BLACK)
        tol = (self.params.grow_tolerance,) * 3
        area, _, _, rect = cv2.floodFill(window, mask, (seed[0] - u0, seed[1] - v0), (0, 0, 0), tol, tol,
                                         8 | cv2.FLOODFILL_MASK_ONLY | (_REGION << 8))
        x0, y0, w, h = rect
        return int(area), (x0, y0, w, h), (mask[1 + y0:1 + y0 + h, 1 + x0:1 + x0 + w] == _REGION).astype(np.uint8)

    def _grow(self, rgb: np.ndarray, cells: np.ndarray, stats: np.ndarray, centroid: np.ndarray) -> BallSighting | None:
        """The region grown from one candidate's seed ``cells`` (bool, seed grid), their box ``stats`` and centre."""
        p, cam, step = self.params, self.camera, self.params.seed_step
        rows, cols = np.nonzero(cells)
        nearest = int(np.argmin((rows - centroid[1]) ** 2 + (cols - centroid[0]) ** 2))
        seed = (int(cols[nearest]) * step, int(rows[nearest]) * step)
        # The window the candidate's region can reach: its seed cells' box grown by its own size (the shaded
        # underside the table does not know can be as tall as the lit part it knows) and the margin; a region
        # that reaches the window's edge inside the image is grown again over the whole image.
        x, y, w, h = (int(v) for v in stats[:4])
        pad = step * (max(w, h) + 1) + p.window_margin
        box = (max(x * step - pad, 0), max(y * step - pad, 0), min((x + w) * step + pad, cam.width),
               min((y + h) * step + pad, cam.height))
        for u0, v0, u1, v1 in (box, (0, 0, cam.width, cam.height)):
            grown = self._flood(rgb, (u0, v0, u1, v1), seed)
            if grown is None:
                return None
            area, (x0, y0, w, h), region = grown
            inside = (x0 > 0 or u0 == 0) and (y0 > 0 or v0 == 0) and (x0 + w < u1 - u0 or u1 == cam.width) \
                and (y0 + h < v1 - v0 or v1 == cam.height)
            if inside:
                break
        x0, y0 = x0 + u0, y0 + v0
        if area < p.min_pixels:
            return None
        m = p.border_margin
        if x0 < m or y0 < m or x0 + w > cam.width - m or y0 + h > cam.height - m:
            return BallSighting(Sighting.OUT_OF_VIEW, pixels=int(area))
        contours, _ = cv2.findContours(region, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        rim = np.concatenate([c.reshape(-1, 2) for c in contours]).astype(np.float64) + (x0, y0)
        xy = cam.normalized(rim)
        rays = np.column_stack([xy, np.ones(len(xy))])
        rays /= np.linalg.norm(rays, axis=1, keepdims=True)
        cone = fit_tangent_cone(rays)
        if cone is None:
            return BallSighting(Sighting.IMPLAUSIBLE, pixels=int(area))
        axis_body = cam.rotation @ cone.axis
        centre_pixel, _ = cam.project(cam.origin + axis_body)
        pixel = (float(centre_pixel[0, 0]), float(centre_pixel[0, 1]))
        # The region's area against the cone's image (its solid angle in pixels near the centre's ray).
        cone_area = math.pi * math.tan(cone.half_angle) ** 2 / (cone.axis[2] ** 3) / cam.angle_per_pixel ** 2
        low, high = p.area_ratio_range
        rim_error = np.sqrt(np.mean((np.arccos(np.clip(rays @ cone.axis, -1.0, 1.0)) - cone.half_angle) ** 2))
        if not low <= area / max(cone_area, 1e-9) <= high or rim_error > p.max_rim_error * cam.angle_per_pixel:
            return BallSighting(Sighting.IMPLAUSIBLE, pixel=pixel, pixels=int(area))
        radius = self.ball_radius
        height = cam.origin[2] + axis_body[2] * radius / max(math.sin(cone.half_angle), 1e-9)
        ground = cam.ray_plane_points(axis_body[None, :], radius)[0]
        if abs(height - radius) > p.max_height_error or not np.all(np.isfinite(ground)):
            return BallSighting(Sighting.IMPLAUSIBLE, pixel=pixel, pixels=int(area))
        return BallSighting(Sighting.SEEN, float(ground[0]), float(ground[1]), pixel, int(area))


def _rank(s: BallSighting) -> tuple[int, int]:
    """Better sightings first: a known ball, then one partly out of view, then the larger region."""
    order = {Sighting.SEEN: 3, Sighting.OUT_OF_VIEW: 2, Sighting.IMPLAUSIBLE: 1, Sighting.NOT_SEEN: 0}
    return order[s.sighting], s.pixels
