"""White line points on the omni image's radial scan lines (chapter 4.1).

Requires: an RGB camera frame (``uint8``, H x W x 3, the ``MirrorModel``'s size), the ``MirrorModel`` and a
calibrated ``ColorTable``.
Provides:

- ``ScanRays``: the radial scan lines (``ray_count`` rays at 360 / ray_count deg, bearing 0 = body +x, counter-
  clockwise, samples every ``step`` px from r_min to r_max), precomputed once: each sample's pixel and its
  radius. ``ScanRays.sample(image, table)`` checks the frame (``colors.check_image``, the one entry
  check) and reads it along the rays into ``RaySamples`` (Y channel and ColorClass per sample), which the
  line scanner and the ball and obstacle detectors (``objects``) share.
- ``LineScanner``: white line points (body frame [m], and their pixels) from ``RaySamples``.
- ``LineParams`` (frozen, validated).

The method: on each ray a sample is bright when its Y exceeds the darkest non-BLACK Y nearby (the local
carpet; as far as half the widest accepted run plus a flank) by ``min_contrast``. A run of bright samples
is a line crossing when it is at most as wide as a line of ``line_width`` crossing the ray at up to
``width_tolerance`` times its width (from the mirror model, plus ``width_slack`` px) and at least
``min_width_fraction`` of its width; when ``flank`` samples on each side (beyond the one next to the run)
hold GREEN and neither BLACK nor BALL, the run's middle sample is not BALL (the ball's lit top is bright)
and its Y exceeds the mean Y of the GREEN flank samples on each side by ``min_contrast``.
The point lies at the run's brightness-weighted mean radius (over the run and the sample on each side, so
partly covered pixels count by their coverage: sub-pixel), through the mirror model, at the run's bearing;
at most ``max_points_per_ray`` points per ray (the nearest). Points come ordered by ray (bearing), then
distance.
Only the radial rays are scanned (the original's extra grid of horizontal and vertical lines is left out).
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
from omni_vision.colors import ColorTable, ImageCheckParams, check_image

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LineParams:
    ray_count: int = 360  # radial scan lines (1 deg apart)
    step: float = 1.0  # [px] between samples along a ray
    line_width: float = 0.125  # [m] the field's white lines (FieldGeometry.line_width)
    min_contrast: float = 30.0  # [grey levels of Y] a line's brightness over the carpet next to it
    flank: int = 4  # [samples] each side of a run: its contrast reference and where GREEN must appear
    width_tolerance: float = 2.5  # runs up to this many line widths (a line crossed at up to ~66 deg)
    width_slack: float = 2.0  # [px] added to the widest run, for blur and pixel rounding
    min_width_fraction: float = 0.5  # narrower runs (of a line's width there) are noise or a line's grazed edge
    max_points_per_ray: int = 5

    def __post_init__(self) -> None:
        if not (isinstance(self.ray_count, int) and 8 <= self.ray_count <= 3600):
            raise OmniVisionError(f"ray_count must be an integer in [8, 3600], got {self.ray_count!r}")
        for name in ("flank", "max_points_per_ray"):
            if not (isinstance(getattr(self, name), int) and getattr(self, name) >= 1):
                raise OmniVisionError(f"{name} must be an integer >= 1, got {getattr(self, name)!r}")
        for name, low, high in (("step", 0.25, 8.0), ("line_width", 0.01, 1.0), ("min_contrast", 1.0, 255.0),
                                ("width_tolerance", 1.0, 20.0), ("width_slack", 0.0, 50.0),
                                ("min_width_fraction", 0.0, 1.0)):
            value = getattr(self, name)
            if not (math.isfinite(value) and low <= value <= high):
                raise OmniVisionError(f"{name} must be in [{low}, {high}], got {value}")


@dataclass(frozen=True)
class RaySamples:
    """One frame read along the scan rays: ``y`` (Y channel) and ``classes`` (ColorClass), both uint8 of shape
    (ray_count, samples per ray); ``image`` is the checked RGB frame they come from."""

    rays: ScanRays
    image: np.ndarray
    y: npt.NDArray[np.uint8]
    classes: npt.NDArray[np.uint8]


class ScanRays:
    """The radial scan lines of ``mirror``'s usable ring, precomputed (see the module docstring)."""

    def __init__(self, mirror: MirrorModel, ray_count: int = 360, step: float = 1.0,
                 image_check: ImageCheckParams | None = None) -> None:
        if not (isinstance(ray_count, int) and ray_count >= 1) or not step > 0.0:
            raise OmniVisionError(f"need ray_count >= 1 and step > 0, got {ray_count!r}, {step!r}")
        self.mirror = mirror
        self.image_check = image_check if image_check is not None else ImageCheckParams()
        self.count = ray_count
        self.bearings: FloatArray = np.arange(ray_count) * (2 * math.pi / ray_count)  # [rad]
        self.radii: FloatArray = mirror.r_min + step * np.arange(int((mirror.r_max - mirror.r_min) / step) + 1)
        sin, cos = np.sin(self.bearings)[:, None], np.cos(self.bearings)[:, None]
        # body +x is image up (-v), body +y is image left (-u)
        u = np.clip(np.rint(mirror.centre_u - sin * self.radii), 0, mirror.width - 1).astype(np.intp)
        v = np.clip(np.rint(mirror.centre_v - cos * self.radii), 0, mirror.height - 1).astype(np.intp)
        self.u, self.v = u, v  # [px] each sample's pixel, (ray_count, samples)
        du, dv = u - mirror.centre_u, v - mirror.centre_v
        self.pixel_radius: FloatArray = np.hypot(du, dv)  # [px] each sample pixel's radius
        flat = v * mirror.width + u
        self._bytes = (3 * flat[..., None] + np.arange(3)).astype(np.intp)  # the samples' RGB bytes

    @property
    def samples_per_ray(self) -> int:
        return len(self.radii)

    def sample(self, image: np.ndarray, table: ColorTable) -> RaySamples:
        """Check ``image`` (``check_image``: OmniVisionError if unusable) and read it along the rays."""
        image = check_image(image, self.mirror, self.image_check)
        rgb = np.take(image.reshape(-1), self._bytes)
        yuv = cv2.cvtColor(rgb, cv2.COLOR_RGB2YUV)
        return RaySamples(self, image, np.ascontiguousarray(yuv[..., 0]), table.classify(yuv))


def find_runs(mask: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Runs of nonzero values along each row of the 2-D ``mask`` (uint8 or bool): (row, start, end) arrays, end
    exclusive, in row-major order."""
    rows, width = mask.shape
    padded = np.zeros((rows, width + 2), np.uint8)
    padded[:, 1:-1] = mask.view(np.uint8)
    flat = padded.ravel()
    # every row begins and ends with 0, so the changes alternate: a run's start, its end, the next start, ...
    change = np.flatnonzero(flat[1:] != flat[:-1])
    first, after = change[0::2] + 1, change[1::2] + 1
    row = first // (width + 2)
    offset = row * (width + 2) + 1
    return row, first - offset, after - offset


@dataclass(frozen=True)
class LinePoints:
    """White line points of one frame: ``points`` (N x 2, body-frame x, y [m]) and ``pixels`` (N x 2, the image
    position u, v [px] of each point, for the debug image), ordered by ray (bearing), then distance."""

    points: FloatArray
    pixels: FloatArray

    def __len__(self) -> int:
        return len(self.points)


class LineScanner:
    """Finds white line points on the radial scan rays (see the module docstring)."""

    def __init__(self, mirror: MirrorModel, params: LineParams | None = None,
                 image_check: ImageCheckParams | None = None) -> None:
        params = params if params is not None else LineParams()
        self.mirror = mirror
        self.params = params
        self.rays = ScanRays(mirror, params.ray_count, params.step, image_check)
        # the widest run [samples] a line may give, by sample index (radius): its width through the mirror model
        distance = mirror.distance(self.rays.radii)
        half = params.line_width / 2
        across = mirror.radius(distance + half) - mirror.radius(np.maximum(distance - half, 0.0))
        self._max_width = ((params.width_tolerance * across + params.width_slack) / params.step).astype(np.int64)
        self._min_width = np.maximum(params.min_width_fraction * across / params.step, 1.0).astype(np.int64)
        # The carpet next to the middle of the widest run at a radius lies within half its width plus a flank.
        # Farther out runs are narrower and a sample spans more ground (with more change of light), so the rays
        # are cut into zones, each eroded with the reach its nearest radius needs (halving from zone to zone).
        reach = self._max_width // 2 + params.flank
        self._zones: list[tuple[int, int, np.ndarray]] = []  # (first sample, end sample, erosion kernel)
        first = 0
        while first < len(reach):
            end = first + 1 + int(np.count_nonzero(reach[first + 1:] > reach[first] // 2))
            self._zones.append((first, end, np.ones((1, 2 * int(reach[first]) + 1), np.uint8)))
            first = end
        self._contrast = int(math.ceil(params.min_contrast))

    def scan_image(self, image: np.ndarray, table: ColorTable) -> LinePoints:
        """Line points of an RGB frame (checked; ``OmniVisionError`` if unusable)."""
        return self.scan(self.rays.sample(image, table))

    def scan(self, samples: RaySamples) -> LinePoints:
        """Line points of a frame read along the rays (``ScanRays.sample`` of this scanner's ``rays``)."""
        if samples.rays is not self.rays:
            raise OmniVisionError("the samples were read along other rays than this scanner's")
        p = self.params
        y, classes = samples.y, samples.classes
        n = y.shape[1]
        # the local carpet level: the darkest Y nearby, black (robots) left out, as it would make grass look bright
        carpet = cv2.max(y, cv2.compare(classes, int(ColorClass.BLACK), cv2.CMP_EQ))
        background = np.empty_like(carpet)
        for zone_start, zone_end, kernel in self._zones:
            reach = kernel.shape[1] // 2
            low, high = max(zone_start - reach, 0), min(zone_end + reach, n)
            zone = cv2.erode(carpet[:, low:high], kernel, borderType=cv2.BORDER_REPLICATE)
            background[:, zone_start:zone_end] = zone[:, zone_start - low:zone_end - low]
        bright = cv2.compare(cv2.subtract(y, background), self._contrast, cv2.CMP_GE)
        ray, start, end = find_runs(bright)
        width = end - start
        middle_sample = (start + end - 1) // 2
        keep = ((start > p.flank) & (end + p.flank < n) & (width <= self._max_width[middle_sample])
                & (width >= self._min_width[middle_sample]))
        ray, start, end, middle_sample = ray[keep], start[keep], end[keep], middle_sample[keep]
        if len(ray) == 0:
            return _no_points()

        # each flank: the sample next to the run may be partly line; the carpet is looked at beyond it
        flat_y, flat_classes = y.ravel(), classes.ravel()
        base = ray * n
        flank = np.arange(1, p.flank + 1)
        before = (base + start - 1)[:, None] - flank  # flat sample indices
        after = (base + end)[:, None] + flank
        class_before, class_after = np.take(flat_classes, before), np.take(flat_classes, after)
        green_before, green_after = class_before == ColorClass.GREEN, class_after == ColorClass.GREEN
        middle = base + middle_sample
        # green on both sides, and no robot (a line at a robot's edge is cut, or a robot's ragged side edge
        # lets grass look bright) and no ball (its lit top is bright) next to the run or at its middle
        keep = (green_before.any(axis=1) & green_after.any(axis=1)
                & (np.take(flat_classes, middle) != ColorClass.BALL)
                & ((class_before != ColorClass.BALL) & (class_before != ColorClass.BLACK)).all(axis=1)
                & ((class_after != ColorClass.BALL) & (class_after != ColorClass.BLACK)).all(axis=1))
        ray, start, end, before, after = ray[keep], start[keep], end[keep], before[keep], after[keep]
        green_before, green_after = green_before[keep], green_after[keep]
        # the carpet's level on each side: the mean Y of its GREEN flank samples
        level_before = (np.take(flat_y, before) * green_before).sum(axis=1) / green_before.sum(axis=1)
        level_after = (np.take(flat_y, after) * green_after).sum(axis=1) / green_after.sum(axis=1)
        level = np.take(flat_y, middle[keep])  # the run's level: its middle lies wholly on the line
        keep = (level - level_before >= p.min_contrast) & (level - level_after >= p.min_contrast)
        ray, start, end = ray[keep], start[keep], end[keep]
        carpet_level = 0.5 * (level_before[keep] + level_after[keep])

        # at most max_points_per_ray per ray, the nearest (runs come sorted by ray, then start)
        first = np.r_[True, ray[1:] != ray[:-1]]
        group_start = np.maximum.accumulate(np.where(first, np.arange(len(ray)), 0))
        keep = np.arange(len(ray)) - group_start < p.max_points_per_ray
        ray, start, end, carpet_level = ray[keep], start[keep], end[keep], carpet_level[keep]
        if len(ray) == 0:
            return _no_points()

        # the line's centre: the brightness-weighted mean radius over the run and its two neighbours (sub-pixel),
        # the runs padded to the longest
        width = end - start
        span = np.arange(int(width.max()) + 2)
        index = np.minimum((ray * n + start - 1)[:, None] + span, y.size - 1)
        weight = np.maximum(np.take(flat_y, index) - carpet_level[:, None], 0.0)
        weight[span[None, :] > (width + 1)[:, None]] = 0.0
        rays = self.rays
        radius = (weight * np.take(rays.pixel_radius, index)).sum(axis=1) / weight.sum(axis=1)
        distance = self.mirror.distance(radius)
        first_sample, last_sample = ray * n + start, ray * n + end - 1
        u = 0.5 * (np.take(rays.u, first_sample) + np.take(rays.u, last_sample))
        v = 0.5 * (np.take(rays.v, first_sample) + np.take(rays.v, last_sample))
        bearing = np.arctan2(-(u - self.mirror.centre_u), -(v - self.mirror.centre_v))
        points = np.column_stack((distance * np.cos(bearing), distance * np.sin(bearing)))
        pixels = np.column_stack((self.mirror.centre_u - radius * np.sin(bearing),
                                  self.mirror.centre_v - radius * np.cos(bearing)))
        return LinePoints(points, pixels)


def _no_points() -> LinePoints:
    return LinePoints(np.zeros((0, 2)), np.zeros((0, 2)))
