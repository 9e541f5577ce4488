"""The omni-directional camera's mirror model: image radius <-> distance on the ground (chapter 4.1).

A convex mirror above an upward-looking camera shows the field around the robot as a disc. Image
pixel (u, v) [px] lies at radius r from the mirror centre (``centre_u``, ``centre_v``) and at the
angle phi; the ground point it shows lies at the distance d(r) = a tan(b r) [m] from the robot
centre, in the direction phi in the robot's body frame (x forward, y left). Only radii between
``r_min`` (inside: the robot's own body) and ``r_max`` (outside: the mirror's rim) are usable.
A calibrated mirror can give ``table``, (radius [px], distance [m]) pairs increasing in both, which
replaces the formula (linear interpolation).

The image's axes: u to the right, v down, pixel (u, v) at row v, column u (OpenCV's convention: a pixel's
coordinates are those of its centre); the robot's front (body +x) points up the image (-v)
and its left (body +y) to the left (-u), as on the real robot's camera.

Points above the ground: the mirror acts as a single viewpoint at ``viewpoint_height`` [m] above
the ground; a point at height z < viewpoint_height and horizontal distance s appears where its ray
meets the ground, at s h / (h - z) (``ground_distance``). Above the viewpoint it is not seen.

Provides ``MirrorModel`` (frozen, validated) with scalar and numpy-vectorised conversions. The
simulator renders with it; omni_vision measures with it (one home for the model).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.arrays import FloatArray


@dataclass(frozen=True)
class MirrorModel:
    width: int = 480  # image size [px]
    height: int = 480
    centre_u: float = 240.0  # mirror centre in the image [px]
    centre_v: float = 240.0
    r_min: float = 37.0  # usable radii [px]: inside is the robot's own body, outside the mirror's rim
    r_max: float = 230.0
    a: float = 1.1926  # d(r) = a tan(b r): d(37 px) = 0.28 m (a held ball shows), d(200 px) = 3.6 m, d(230 px) = 9 m
    b: float = 0.0062567
    viewpoint_height: float = 0.75  # [m] above the ground
    table: tuple[tuple[float, float], ...] = ()  # calibrated (radius [px], distance [m]) pairs; replaces a, b

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            if not (isinstance(getattr(self, name), int) and 16 <= getattr(self, name) <= 4096):
                raise ValueError(f"{name} must be an integer number of pixels in [16, 4096], got {getattr(self, name)}")
        for name in ("centre_u", "centre_v", "r_min", "r_max", "a", "b", "viewpoint_height"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"{name} must be finite, got {getattr(self, name)}")
        if not 0.0 <= self.r_min < self.r_max:
            raise ValueError(f"need 0 <= r_min < r_max, got r_min {self.r_min}, r_max {self.r_max}")
        if not (self.r_max <= self.centre_u <= self.width - self.r_max
                and self.r_max <= self.centre_v <= self.height - self.r_max):
            raise ValueError(f"the usable disc (radius r_max {self.r_max} px around ({self.centre_u}, "
                             f"{self.centre_v})) must lie inside the {self.width} x {self.height} image")
        if self.viewpoint_height <= 0.0:
            raise ValueError(f"viewpoint_height must be positive, got {self.viewpoint_height}")
        if self.table:
            radii = np.array([p[0] for p in self.table], dtype=float)
            dists = np.array([p[1] for p in self.table], dtype=float)
            if len(self.table) < 2 or not (np.all(np.isfinite(radii)) and np.all(np.isfinite(dists))):
                raise ValueError("table needs at least two finite (radius, distance) pairs")
            if np.any(np.diff(radii) <= 0) or np.any(np.diff(dists) <= 0) or dists[0] < 0.0:
                raise ValueError("table's radii and distances must both increase (distances from 0 up)")
            if radii[0] > self.r_min or radii[-1] < self.r_max:
                raise ValueError(f"table must cover the usable radii {self.r_min}-{self.r_max} px")
        else:
            if self.a <= 0.0 or self.b <= 0.0:
                raise ValueError(f"a and b must be positive, got a {self.a}, b {self.b}")
            if self.b * self.r_max >= math.pi / 2:
                raise ValueError(f"b r_max must stay below pi/2 (the horizon), got {self.b * self.r_max:.3f}")

    # --- radius <-> distance -----------------------------------------------------------------
    def distance(self, r: FloatArray | float) -> FloatArray:
        """Ground distance [m] shown at image radius ``r`` [px] (any radius in [0, r_max])."""
        r = np.asarray(r, dtype=float)
        if self.table:
            radii, dists = zip(*self.table)
            return np.interp(r, radii, dists)
        distance: FloatArray = self.a * np.tan(self.b * np.clip(r, 0.0, self.r_max))
        return distance

    def radius(self, d: FloatArray | float) -> FloatArray:
        """Image radius [px] showing the ground at distance ``d`` [m]; beyond the rim: r_max."""
        d = np.asarray(d, dtype=float)
        if self.table:
            radii, dists = zip(*self.table)
            return np.interp(d, dists, radii)
        radius: FloatArray = np.minimum(np.arctan(np.maximum(d, 0.0) / self.a) / self.b, self.r_max)
        return radius

    @property
    def min_distance(self) -> float:
        """The nearest ground distance the mirror shows [m] (at r_min)."""
        return float(self.distance(self.r_min))

    @property
    def max_distance(self) -> float:
        """The farthest ground distance the mirror shows [m] (at r_max)."""
        return float(self.distance(self.r_max))

    def ground_distance(self, s: FloatArray | float, z: FloatArray | float) -> FloatArray:
        """Where a point at horizontal distance ``s`` [m] and height ``z`` [m] appears on the ground [m];
        inf for points at or above the viewpoint (not seen)."""
        s, z = np.asarray(s, dtype=float), np.asarray(z, dtype=float)
        below = z < self.viewpoint_height
        with np.errstate(divide="ignore", invalid="ignore"):
            return np.where(below, s * self.viewpoint_height / np.where(below, self.viewpoint_height - z, 1.0),
                            np.inf)

    # --- pixels <-> body frame ------------------------------------------------------------------
    def pixel_to_body(self, u: FloatArray | float, v: FloatArray | float) -> tuple[FloatArray, FloatArray]:
        """The ground point (x forward, y left) [m] in the robot's body frame shown at pixel (u, v)."""
        du = np.asarray(u, dtype=float) - self.centre_u
        dv = np.asarray(v, dtype=float) - self.centre_v
        r = np.hypot(du, dv)
        d = self.distance(r)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(r > 0.0, d / np.where(r > 0.0, r, 1.0), 0.0)
        return -dv * scale, -du * scale

    def body_to_pixel(self, x: FloatArray | float, y: FloatArray | float) -> tuple[FloatArray, FloatArray]:
        """The pixel (u, v) showing the ground point (x, y) [m] of the body frame (clamped to the rim)."""
        x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
        d = np.hypot(x, y)
        r = self.radius(d)
        with np.errstate(divide="ignore", invalid="ignore"):
            scale = np.where(d > 0.0, r / np.where(d > 0.0, d, 1.0), 0.0)
        return self.centre_u - y * scale, self.centre_v - x * scale

    def pixel_grid(self) -> tuple[FloatArray, FloatArray, FloatArray]:
        """For every pixel of the image: body-frame ground (x, y) [m] (float32, height x width) and a mask
        of the usable ring (r_min <= r <= r_max)."""
        v, u = np.mgrid[0:self.height, 0:self.width].astype(float)
        x, y = self.pixel_to_body(u, v)
        r = np.hypot(u - self.centre_u, v - self.centre_v)
        usable = (r >= self.r_min) & (r <= self.r_max)
        return x.astype(np.float32), y.astype(np.float32), usable
