"""Synthetic RGB-D frames for kinect_ball's unit tests (not the simulator: one camera, a sphere and a floor).

Provides ``render(balls, ...)`` -> ``Cloud``: an organised cloud of a pinhole camera at the origin of its frame (x
along the optical axis, y left, z up), ``height`` above a green floor, seeing orange spheres of ``RADIUS``, with
Gaussian range noise and random missing returns from one seeded ``numpy.random.Generator``; and ``cap_points``
(points of a sphere's visible cap, with noise and outliers, for the fit alone).
"""

from __future__ import annotations

import math

import numpy as np

from nubot_common.clouds import Cloud

RADIUS = 0.11  # [m]
ORANGE = (245, 110, 20)
GREEN = (40, 130, 50)


def rays(width: int, height: int, hfov_deg: float = 70.6, vfov_deg: float = 60.0) -> np.ndarray:
    ty, tz = math.tan(math.radians(hfov_deg) / 2), math.tan(math.radians(vfov_deg) / 2)
    yy, zz = np.meshgrid(ty * (1 - 2 * (np.arange(width) + 0.5) / width),
                         tz * (1 - 2 * (np.arange(height) + 0.5) / height))
    r = np.stack([np.ones_like(yy), yy, zz], axis=-1).reshape(-1, 3)
    return r / np.linalg.norm(r, axis=1, keepdims=True)


def render(balls: list[tuple[float, float, float]], width: int = 128, height: int = 106, camera_height: float = 0.6,
           noise: float = 0.005, dropout: float = 0.0, seed: int = 0) -> Cloud:
    """The camera frame's cloud of orange balls centred at ``balls`` (camera frame [m]) over the floor."""
    rng = np.random.default_rng(seed)
    d = rays(width, height)
    with np.errstate(divide="ignore"):
        t = np.where(d[:, 2] < 0, -camera_height / d[:, 2], np.inf)
    color = np.tile(np.array(GREEN, float), (len(d), 1))
    for centre in balls:
        c = np.asarray(centre, float)
        b = -(d @ c)
        disc = b * b - (c @ c - RADIUS * RADIUS)
        with np.errstate(invalid="ignore"):
            ts = -b - np.sqrt(disc)
        hit = (disc >= 0) & (ts > 0) & (ts < t)
        t[hit] = ts[hit]
        color[hit] = ORANGE
    valid = np.isfinite(t) & (t * d[:, 0] <= 8.0) & (rng.random(len(d)) >= dropout)
    points = np.full((len(d), 3), np.nan)
    points[valid] = d[valid] * (t[valid] + rng.normal(0, noise, valid.sum()))[:, None]
    rgb = np.zeros((len(d), 3), np.uint8)
    rgb[valid] = np.clip(color[valid] + rng.normal(0, 4, (valid.sum(), 3)), 0, 255).astype(np.uint8)
    return Cloud.from_arrays(points.reshape(height, width, 3), rgb.reshape(height, width, 3))


def cap_points(centre: np.ndarray, n: int, noise: float, rng: np.random.Generator,
               half_angle_deg: float = 70.0) -> np.ndarray:
    """``n`` points of the cap of the sphere at ``centre`` that faces the origin, within ``half_angle_deg`` of the
    direction to the origin, with Gaussian noise ``noise`` [m]."""
    towards = -centre / np.linalg.norm(centre)
    out = []
    while len(out) < n:
        v = rng.normal(size=3)
        v /= np.linalg.norm(v)
        if v @ towards >= math.cos(math.radians(half_angle_deg)):
            out.append(centre + RADIUS * v)
    return np.array(out) + rng.normal(0, noise, (n, 3))
