"""The goalie's two simulated RGB-D cameras (Kinect 2 like): coloured point clouds by ray casting.

Requires: the match's ``WorldDescription`` (field, goals, ball and robot bodies), ``RgbdCameraParams`` (the
cameras' resolution, field of view, range, noise, missing returns, colours and their mounts on the robot,
``nubot_common.kinect_mount``) and, per frame, the true states of the robot, the ball and the other robots, the sim time
and the sensors' generator. Provides: ``RgbdCameraRenderer.render`` -> one ``RgbdFrame`` per camera: an organised
cloud (height x width x 3 float32 [m] in the camera's frame: x along the optical axis, y left, z up; NaN where
there is no return) and its colours (height x width x 3 uint8 RGB).

What is drawn: the ground (green carpet, white lines), the ball (an orange sphere, on the ground or in the air),
the other robots (dark cylinders of the world's robot body) and the goals' posts and bars (white). Nets,
arena walls and the own body are not drawn (no return). Ray casting uses rays precomputed per pixel (a pinhole
grid), turned and cast against the ground, its lines and the bodies in one compiled call a frame
(``RgbdRayCaster``, ``cpp/cameras.cpp``).

The sensor: range limits on the depth along the optical axis (Kinect 2: 0.5-8 m); range noise along each ray
with standard deviation ``depth_noise_constant + depth_noise_quadratic * depth^2`` (a few mm at 1 m, 2 cm at
8 m); missing returns at random (``dropout``) and, more often, at depth edges (``edge_dropout`` where the depth
jumps by more than ``edge_jump`` to a neighbour showing another surface or none: mixed pixels at an object's
silhouette); colour noise per
channel. Resolution: 128 x 106 by default, the Kinect 2's 512 x 424 depth image binned 4 x 4. A full-size cloud
(217 k points, 3.5 MB at 30 Hz per camera) would cost the simulator node and kinect_ball 16 times as much per
frame for little gain: the ball still spans about 4 x 4 points at 6 m and 8 x 8 at 3 m, enough for a sphere fit of
the known radius.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.kernels import load_kernels
from nubot_common.kinect_mount import CAMERAS, GOALIE_MOUNTS, CameraMount, RgbdMounts
from nubot_common.params import require_non_negative, require_positive
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import RGB
from sim_visual.world import BallState, RobotState

if TYPE_CHECKING:
    from sim_visual import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("sim_visual")

NONE, GROUND, LINE, BALL, ROBOT, GOAL = range(6)  # what a pixel's ray hit first
CYLINDER, BAR, SPHERE = range(3)  # the bodies' shapes, for RgbdCameraRenderer.cast (as cpp/cameras.cpp's)
_FAR = 1e3  # [m] stands in for "no return" where depths are compared


@dataclass(frozen=True)
class RgbdCameraParams:
    width: int = 128  # [px]
    height: int = 106  # [px]
    horizontal_fov_deg: float = 70.6  # [deg] (Kinect 2 depth camera)
    vertical_fov_deg: float = 60.0  # [deg]
    min_range: float = 0.5  # [m] depth along the optical axis
    max_range: float = 8.0  # [m]
    depth_noise_constant: float = 0.002  # [m] range noise std at zero depth
    depth_noise_quadratic: float = 0.0003  # [1/m] ... growing with depth^2
    dropout: float = 0.02  # share of returns missing at random
    edge_jump: float = 0.15  # [m] a depth step at least this large to a neighbour on another surface: an edge
    edge_dropout: float = 0.3  # share of edge pixels without a return
    color_noise_std: float = 5.0  # [levels 0-255] per channel
    carpet_rgb: RGB = (40, 130, 50)
    line_rgb: RGB = (235, 235, 235)  # lines, posts and bars
    ball_rgb: RGB = (245, 110, 20)
    robot_rgb: RGB = (30, 30, 30)
    mounts: RgbdMounts = dc_field(default_factory=lambda: GOALIE_MOUNTS)

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            if not 8 <= getattr(self, name) <= 1024:
                raise ValueError(f"{name} must lie in [8, 1024] px, got {getattr(self, name)}")
        for name in ("horizontal_fov_deg", "vertical_fov_deg"):
            if not 1.0 <= getattr(self, name) <= 150.0:
                raise ValueError(f"{name} must lie in [1, 150] deg, got {getattr(self, name)}")
        require_positive(self, "max_range")
        require_non_negative(self, "min_range", "depth_noise_constant", "depth_noise_quadratic", "color_noise_std")
        if not self.min_range < self.max_range:
            raise ValueError(f"min_range {self.min_range} must be below max_range {self.max_range}")
        for name in ("dropout", "edge_dropout"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must lie in [0, 1], got {getattr(self, name)}")
        require_positive(self, "edge_jump")
        for name in ("carpet_rgb", "line_rgb", "ball_rgb", "robot_rgb"):
            value = getattr(self, name)
            if len(value) != 3 or not all(isinstance(c, int) and 0 <= c <= 255 for c in value):
                raise ValueError(f"{name} must be three integers in [0, 255], got {value}")

    def depth_noise(self, depth: np.ndarray | float) -> np.ndarray:
        """Range noise std [m] at ``depth`` [m]."""
        d = np.asarray(depth, dtype=float)
        return self.depth_noise_constant + self.depth_noise_quadratic * d * d


@dataclass(frozen=True)
class RgbdFrame:
    stamp: float  # sim time [s]
    camera: str  # left or right
    points: np.ndarray  # height x width x 3 float32 [m], camera frame; NaN: no return
    rgb: np.ndarray  # height x width x 3 uint8
    labels: np.ndarray  # height x width uint8: what each return shows (GROUND, LINE, BALL, ROBOT, GOAL; NONE: none)


def pixel_rays(params: RgbdCameraParams) -> np.ndarray:
    """Unit rays (height*width x 3) of a pinhole camera in its frame, row by row from the top left pixel."""
    ty = math.tan(math.radians(params.horizontal_fov_deg) / 2.0)
    tz = math.tan(math.radians(params.vertical_fov_deg) / 2.0)
    u = (np.arange(params.width) + 0.5) / params.width
    v = (np.arange(params.height) + 0.5) / params.height
    yy, zz = np.meshgrid(ty * (1.0 - 2.0 * u), tz * (1.0 - 2.0 * v))
    rays = np.stack([np.ones_like(yy), yy, zz], axis=-1).reshape(-1, 3)
    return rays / np.linalg.norm(rays, axis=1, keepdims=True)


class RgbdCameraRenderer:
    """Renders both cameras of a robot; built once per simulator (the rays and the field's lines)."""

    def __init__(self, world: WorldDescription, params: RgbdCameraParams):
        self.world, self.params = world, params
        self.rays = pixel_rays(params)
        f = world.field
        segments = np.array(f.line_segments(), dtype=float).reshape(-1, 2, 2)
        arcs = np.array([(a.x, a.y, a.radius, a.start, a.end) for a in f.arcs()], dtype=float).reshape(-1, 5)
        self._caster = _kernels.RgbdRayCaster(self.rays, segments, arcs, f.line_width / 2.0, params.max_range)
        self.colors = np.zeros((6, 3), dtype=float)
        for kind, rgb in ((GROUND, params.carpet_rgb), (LINE, params.line_rgb), (BALL, params.ball_rgb),
                          (ROBOT, params.robot_rgb), (GOAL, params.line_rgb)):
            self.colors[kind] = rgb

    def render(self, me: RobotState, ball: BallState, others: Sequence[RobotState], t: float,
               rng: np.random.Generator) -> tuple[RgbdFrame, RgbdFrame]:
        """Both cameras' frames (left, right) of robot ``me`` at sim time ``t`` [s]."""
        left, right = (self.render_camera(name, self.params.mounts.by_name(name), me, ball, others, t, rng)
                       for name in CAMERAS)
        return left, right

    def render_camera(self, name: str, mount: CameraMount, me: RobotState, ball: BallState,
                      others: Sequence[RobotState], t: float, rng: np.random.Generator) -> RgbdFrame:
        o, rotation = self.pose(mount, me)
        rng_t, kind = self.cast(o, rotation, self.shapes(o, ball, others))
        return self._sense(name, t, rng_t, kind, rng)

    def pose(self, mount: CameraMount, me: RobotState) -> tuple[np.ndarray, np.ndarray]:
        """The camera's position [m] and rotation (world <- camera) on robot ``me``."""
        c, s = math.cos(me.theta), math.sin(me.theta)
        heading = np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])
        return np.array([me.x, me.y, 0.0]) + heading @ mount.offset, heading @ mount.rotation()

    def shapes(self, o: np.ndarray, ball: BallState, others: Sequence[RobotState]) -> np.ndarray:
        """The bodies within the cameras' reach of the viewpoint ``o`` [m], in the order they are cast, one row
        each (shape, what, four numbers): upright cylinders (CYLINDER: x, y, radius, top) for the other robots and the
        goal posts, the goals' bars (BAR: x, z, radius, half length along y) and the ball (SPHERE: x, y, z,
        radius)."""
        world = self.world
        reach = self.params.max_range / max(float(self.rays[:, 0].min()), 1e-6)  # the farthest range of a return
        body = world.robot
        out: list[tuple] = [(CYLINDER, ROBOT, other.x, other.y, body.radius, body.height) for other in others
                            if math.hypot(other.x - o[0], other.y - o[1]) <= reach + body.radius]
        f = world.field
        for side in (-1, 1):
            posts = f.goal_posts(side)
            if math.hypot(posts[0][0] - o[0], o[1]) > reach + f.goal_width:
                continue
            out += [(CYLINDER, GOAL, px, py, f.post_radius, f.goal_height) for px, py in posts]
            out.append((BAR, GOAL, side * (f.half_length + f.post_radius), f.goal_height + f.post_radius,
                        f.post_radius, f.goal_outer_half_width))
        if np.linalg.norm(np.array([ball.x, ball.y, ball.z]) - o) <= reach + world.ball.radius:
            out.append((SPHERE, BALL, ball.x, ball.y, ball.z, world.ball.radius))
        return np.array(out, dtype=float).reshape(-1, 6)

    def cast(self, o: np.ndarray, rotation: np.ndarray, shapes: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The range [m] along each ray, turned into the world by ``rotation`` (world <- camera), from ``o`` to what
        it meets first (inf: nothing), and what that is (GROUND, LINE, ``shapes``' labels; NONE)."""
        return self._caster.cast(o, rotation, shapes)

    def _sense(self, name: str, t: float, rng_t: np.ndarray, kind: np.ndarray,
               rng: np.random.Generator) -> RgbdFrame:
        p = self.params
        depth = rng_t * self.rays[:, 0]
        valid = (depth >= p.min_range) & (depth <= p.max_range)
        image = np.where(valid, depth, _FAR).reshape(p.height, p.width)
        surface = np.where(valid & (kind != LINE), kind, np.where(valid, GROUND, NONE)).reshape(image.shape)
        edge = np.zeros(image.shape, dtype=bool)
        # An edge: the neighbour shows another surface (or none) at a clearly different depth; the far ground's
        # steep depth gradient at grazing angles is no edge
        jump_x = (np.abs(np.diff(image, axis=1)) > p.edge_jump) & (np.diff(surface, axis=1) != 0)
        jump_y = (np.abs(np.diff(image, axis=0)) > p.edge_jump) & (np.diff(surface, axis=0) != 0)
        edge[:, 1:] |= jump_x
        edge[:, :-1] |= jump_x
        edge[1:, :] |= jump_y
        edge[:-1, :] |= jump_y
        draws = rng.random(len(depth))
        missing = (draws < p.dropout) | (edge.reshape(-1) & (draws < p.dropout + p.edge_dropout))
        valid &= ~missing
        idx = np.flatnonzero(valid)
        noisy = rng_t[idx] + rng.normal(0.0, 1.0, len(idx)) * p.depth_noise(depth[idx])
        points = np.full((len(depth), 3), np.nan, dtype=np.float32)
        points[idx] = self.rays[idx] * noisy[:, None]
        rgb = np.zeros((len(depth), 3), dtype=np.uint8)
        colors = self.colors[kind[idx]] + rng.normal(0.0, p.color_noise_std, (len(idx), 3))
        rgb[idx] = np.clip(np.rint(colors), 0, 255).astype(np.uint8)
        shape = (p.height, p.width)
        return RgbdFrame(t, name, points.reshape(*shape, 3), rgb.reshape(*shape, 3),
                         np.where(valid, kind, NONE).reshape(shape).astype(np.uint8))
