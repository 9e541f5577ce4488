"""Synthetic omni camera frames for omni_vision's unit tests (not a simulator: no physics, one frame).

Provides ``Scene`` (what the robot sees, in its body frame: white line segments and arcs, balls, robots, the
mirror holder's struts, lighting and noise), ``render(mirror, scene)`` -> (RGB image, ColorClass label image),
``field_scene`` (the field's lines seen from a pose), ``training_scenes`` (varied field scenes) and
``calibrated_table`` (a colour table calibrated on them, shared by the tests). Every pixel is traced through
the mirror model: its viewing ray leaves the single viewpoint (``viewpoint_height`` above the robot centre)
towards the ground point ``MirrorModel.pixel_grid`` gives, and shows the nearest of the ball spheres, the robot
cylinders (taller than the viewpoint, so a robot hides a wedge from its near edge outwards) and the carpet. Line
edges are anti-aliased over a pixel's ground footprint (a pixel partly line, partly carpet is labelled UNKNOWN);
lighting varies across the ground as a sinusoid of +-``light_amplitude``; noise is Gaussian per channel from
one seeded ``numpy.random.Generator`` (``Scene.seed``).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import lru_cache
from typing import Any

import cv2
import numpy as np

from nubot_common.color_class import ColorClass
from nubot_common.field import FieldGeometry
from nubot_common.mirror import MirrorModel
from omni_vision.colors import ColorTable

GREEN_RGB = (40.0, 140.0, 55.0)
WHITE_RGB = (235.0, 235.0, 230.0)
BALL_RGB = (245.0, 105.0, 20.0)
BLACK_RGB = (28.0, 28.0, 32.0)
BALL_RADIUS = 0.11  # [m]
ROBOT_RADIUS = 0.26  # [m]
MIXED = 0.25  # a pixel covered by a line to more than this and less than 1 - this is labelled UNKNOWN

Point = tuple[float, float]


@dataclass(frozen=True)
class ArcLine:
    """A white arc: centre (x, y) [m] in the body frame, radius [m], from ``start`` to ``end`` CCW [rad]."""

    x: float
    y: float
    radius: float
    start: float = -math.pi
    end: float = math.pi


@dataclass(frozen=True)
class Scene:
    segments: tuple[tuple[Point, Point], ...] = ()  # white lines, body frame [m]
    arcs: tuple[ArcLine, ...] = ()
    line_width: float = 0.125  # [m]
    balls: tuple[Point, ...] = ()  # ball centres on the ground, body frame [m]
    robots: tuple[Point, ...] = ()  # robot centres, body frame [m]
    struts: tuple[float, ...] = ()  # bearings [deg] of the mirror holder's struts (thin black, from r_min out)
    strut_width_deg: float = 1.5
    strut_reach_px: float = 25.0  # how far beyond r_min a strut shows [px]
    own_body: bool = True  # paint the robot's own body (black) inside r_min
    brightness: float = 1.0  # the whole frame's light (time of day, exposure)
    light_amplitude: float = 0.25  # +- relative variation across the ground
    light_direction: float = 0.4  # [rad] direction of the variation over the ground
    light_period: float = 10.0  # [m]
    light_phase: float = 0.0  # [rad]
    noise_std: float = 4.0  # [grey levels] per channel
    blur_sigma: float = 0.0  # [px] optical blur before the noise
    seed: int = 0


@lru_cache(maxsize=4)
def _geometry(mirror: MirrorModel) -> tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """Per pixel: ground x, y [m], image radius [px], bearing [rad] and the ground footprint of a pixel [m]."""
    x, y, _ = mirror.pixel_grid()
    v, u = np.mgrid[0:mirror.height, 0:mirror.width].astype(np.float64)
    r = np.hypot(u - mirror.centre_u, v - mirror.centre_v)
    bearing = np.arctan2(-(u - mirror.centre_u), -(v - mirror.centre_v))
    footprint = mirror.distance(np.minimum(r + 0.5, mirror.r_max)) - mirror.distance(np.maximum(r - 0.5, 0.0))
    return x.astype(np.float64), y.astype(np.float64), r, bearing, np.maximum(footprint, 1e-4)


def _segment_distance(px: np.ndarray, py: np.ndarray, a: Point, b: Point) -> np.ndarray:
    ax, ay = a
    dx, dy = b[0] - ax, b[1] - ay
    length2 = dx * dx + dy * dy
    t = np.clip(((px - ax) * dx + (py - ay) * dy) / length2, 0.0, 1.0) if length2 > 0 else np.zeros_like(px)
    return np.hypot(px - ax - t * dx, py - ay - t * dy)


def _arc_distance(px: np.ndarray, py: np.ndarray, arc: ArcLine) -> np.ndarray:
    rx, ry = px - arc.x, py - arc.y
    on_circle = np.abs(np.hypot(rx, ry) - arc.radius)
    span = (arc.end - arc.start) % (2 * math.pi) or 2 * math.pi
    inside = (np.arctan2(ry, rx) - arc.start) % (2 * math.pi) <= span
    ends = [(arc.x + arc.radius * math.cos(a), arc.y + arc.radius * math.sin(a)) for a in (arc.start, arc.end)]
    to_end = np.minimum(*[np.hypot(px - ex, py - ey) for ex, ey in ends])
    return np.where(inside, on_circle, to_end)


def _light(scene: Scene, x: np.ndarray | float, y: np.ndarray | float) -> np.ndarray:
    along = np.asarray(x) * math.cos(scene.light_direction) + np.asarray(y) * math.sin(scene.light_direction)
    wave = np.sin(2 * math.pi * along / scene.light_period + scene.light_phase)
    return scene.brightness * (1.0 + scene.light_amplitude * wave)


def render(mirror: MirrorModel, scene: Scene) -> tuple[np.ndarray, np.ndarray]:
    """The RGB frame (uint8, H x W x 3) the omni camera sees of ``scene``, and its ColorClass labels (uint8)."""
    gx, gy, r, bearing, footprint = _geometry(mirror)
    h = mirror.viewpoint_height
    colour = np.empty(gx.shape + (3,), np.float64)
    labels = np.full(gx.shape, ColorClass.GREEN, np.uint8)

    # the carpet and its white lines
    distance = np.full(gx.shape, np.inf)
    for a, b in scene.segments:
        distance = np.minimum(distance, _segment_distance(gx, gy, a, b))
    for arc in scene.arcs:
        distance = np.minimum(distance, _arc_distance(gx, gy, arc))
    coverage = np.clip((scene.line_width / 2 - distance) / footprint + 0.5, 0.0, 1.0)
    base = np.asarray(GREEN_RGB) + coverage[..., None] * (np.asarray(WHITE_RGB) - np.asarray(GREEN_RGB))
    colour[:] = base * _light(scene, gx, gy)[..., None]
    labels[coverage >= 1.0 - MIXED] = ColorClass.WHITE
    labels[(coverage > MIXED) & (coverage < 1.0 - MIXED)] = ColorClass.UNKNOWN  # mixed pixels: no class

    # objects along each viewing ray P(t) = V + t (G - V), V = (0, 0, h), G = (gx, gy, 0): the nearest wins
    nearest = np.full(gx.shape, np.inf)
    for bx, by in scene.balls:
        # |V + t D - C|^2 = R^2 with D = G - V, C = (bx, by, R)
        a2 = gx * gx + gy * gy + h * h
        half_b = -gx * bx - gy * by - h * (h - BALL_RADIUS)
        c = bx * bx + by * by + (h - BALL_RADIUS) ** 2 - BALL_RADIUS ** 2
        disc = half_b * half_b - a2 * c
        with np.errstate(invalid="ignore"):
            t = (-half_b - np.sqrt(disc)) / a2
        hit = (disc >= 0) & (t >= 0) & (t <= 1) & (t < nearest)
        z = h * (1 - t)  # the hit point's height: the ball's top is lit, its bottom in shadow
        shade = 0.8 + 0.35 * np.clip(z / (2 * BALL_RADIUS), 0.0, 1.0)
        colour[hit] = np.asarray(BALL_RGB) * (shade[hit] * _light(scene, bx, by))[:, None]
        labels[hit] = ColorClass.BALL
        nearest = np.where(hit, t, nearest)
    for rx, ry in scene.robots:
        # the horizontal projection t (gx, gy) enters the disc of radius R around (rx, ry)
        g2 = np.maximum(gx * gx + gy * gy, 1e-12)
        gc = gx * rx + gy * ry
        disc = gc * gc - g2 * (rx * rx + ry * ry - ROBOT_RADIUS ** 2)
        with np.errstate(invalid="ignore"):
            t = (gc - np.sqrt(disc)) / g2
        hit = (disc >= 0) & (t >= 0) & (t <= 1) & (t < nearest)
        colour[hit] = np.asarray(BLACK_RGB) * _light(scene, rx, ry)
        labels[hit] = ColorClass.BLACK
        nearest = np.where(hit, t, nearest)

    # the robot's own body, the holder's struts and the dark surroundings of the mirror
    black = np.asarray(BLACK_RGB) * scene.brightness
    for strut in scene.struts:
        off = np.abs((bearing - math.radians(strut) + math.pi) % (2 * math.pi) - math.pi)
        at = (off <= math.radians(scene.strut_width_deg) / 2) & (r <= mirror.r_min + scene.strut_reach_px)
        colour[at] = black
        labels[at] = ColorClass.BLACK
    if scene.own_body:
        inner = r < mirror.r_min
        colour[inner] = black
        labels[inner] = ColorClass.BLACK
    outer = r > mirror.r_max
    colour[outer] = 0.5 * black
    labels[outer] = ColorClass.UNKNOWN

    if scene.blur_sigma > 0:
        colour = cv2.GaussianBlur(colour, (0, 0), scene.blur_sigma)
    rng = np.random.default_rng(scene.seed)
    colour = colour + rng.normal(0.0, scene.noise_std, colour.shape)
    return np.clip(np.rint(colour), 0, 255).astype(np.uint8), labels


def to_body(pose: tuple[float, float, float], x: float, y: float) -> Point:
    """The world point (x, y) [m] in the body frame of a robot at ``pose`` (x, y [m], heading [rad])."""
    c, s = math.cos(pose[2]), math.sin(pose[2])
    dx, dy = x - pose[0], y - pose[1]
    return c * dx + s * dy, -s * dx + c * dy


def field_scene(pose: tuple[float, float, float], field_geometry: FieldGeometry | None = None,
                balls: tuple[Point, ...] = (), robots: tuple[Point, ...] = (), **options: Any) -> Scene:
    """The scene a robot at ``pose`` (world frame) sees: the field's lines, and balls and robots at world positions."""
    field_geometry = field_geometry if field_geometry is not None else FieldGeometry()
    segments = tuple((to_body(pose, *a), to_body(pose, *b)) for a, b in field_geometry.line_segments())
    arcs = tuple(ArcLine(*to_body(pose, arc.x, arc.y), arc.radius, arc.start - pose[2], arc.end - pose[2])
                 for arc in field_geometry.arcs())
    return Scene(segments=segments, arcs=arcs, line_width=field_geometry.line_width,
                 balls=tuple(to_body(pose, *b) for b in balls), robots=tuple(to_body(pose, *p) for p in robots),
                 **options)


def training_scenes(count: int, seed: int, **options: Any) -> list[Scene]:
    """``count`` varied field scenes for calibrating a colour table: random poses, balls and robots around the
    robot, light levels and directions, noise seeds (all from ``seed``)."""
    rng = np.random.default_rng(seed)
    scenes = []
    for _ in range(count):
        pose = (float(rng.uniform(-7, 7)), float(rng.uniform(-4, 4)), float(rng.uniform(-math.pi, math.pi)))
        near = [(pose[0] + float(d * math.cos(a)), pose[1] + float(d * math.sin(a)))
                for d, a in zip(rng.uniform(0.8, 5.0, 4), rng.uniform(-math.pi, math.pi, 4))]
        scenes.append(field_scene(pose, balls=tuple(near[:2]), robots=tuple(near[2:]),
                                  brightness=float(rng.uniform(0.85, 1.15)),
                                  light_direction=float(rng.uniform(-math.pi, math.pi)),
                                  light_phase=float(rng.uniform(-math.pi, math.pi)),
                                  seed=int(rng.integers(1 << 31)), **options))
    return scenes


@lru_cache(maxsize=2)
def calibrated_table(mirror: MirrorModel) -> ColorTable:
    """A colour table calibrated on 8 training scenes (seed 1); cached, the tests share it."""
    return ColorTable.calibrate(render(mirror, scene) for scene in training_scenes(8, seed=1))
