"""The simulated front camera: the image a regular robot's downward-looking pinhole camera sees.

Requires: the match's ``WorldDescription`` (field markings, goals, ball radius, robot cylinder),
``FrontCameraParams`` (the true ``PinholeCamera`` and its mount, noise, texture resolution, shading), the
scene's colours and lighting (``OmniCameraParams``: one palette for every camera), the true ``RobotState`` of
the viewer and of the other robots and the ``BallState`` (world frame), the simulation time [s] and the
run's ``numpy.random.Generator`` (the only source of randomness).
Provides: ``FrontCameraRenderer.render`` -> an RGB image (height x width x 3, uint8, the camera's pixels),
and ``render_board``: the same scene with a flat textured board (a calibration pattern) placed anywhere in
the body frame, for the offline calibration.

What the image shows: the lit green carpet with its white markings and the goals' ground frames (the omni
camera's ``FieldTexture``, at this camera's finer resolution), the surroundings beyond the arena and past
``max_range``; as 3-D bodies the other robots (dark cylinders, lit from above), the goal posts (white
cylinders) and the ball (an orange sphere shaded from its lit top to its darker underside, with an
anti-aliased edge). Every body is intersected exactly with each pixel's ray, so a ball in the air, close,
or partly out of the image shows as the camera would see it. Not modelled: the robot's own front (the
camera looks past it), shadows, motion blur, lens blur, vignetting.

How, for speed (about 1 ms a frame at 320 x 240 with the ball in view, one core): each pixel's ray (distortion
removed) and its ground point in the body frame are computed once; a frame is one ``cv2.transform`` of the
ground points by the viewer's pose and one ``cv2.remap`` of the field texture; bodies are drawn far to near
inside their projected bounding boxes only, the cylinders pixel by pixel by the compiled ``paint_cylinder``
(``cpp/cameras.cpp``); noise is random bytes from ``rng`` through a table of normal quantiles (as the omni
camera's).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace
from typing import TYPE_CHECKING

import cv2
import numpy as np

from nubot_common.kernels import load_kernels
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import RGB, OmniCameraParams
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.omni_camera import FieldTexture, _noise_table
from sim_visual.world import BallState, RobotState

if TYPE_CHECKING:
    from sim_visual import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("sim_visual")

_BOX_PAD = 2  # [px] around a body's projected bounding box
_MIN_DEPTH = 0.02  # [m] a body's box corner nearer the lens plane than this: the box is the whole image
_SPHERE_OUTLINE_POINTS = 24


class FrontCameraRenderer:
    """Renders the front camera's image of any robot on one field; holds the field texture and the camera's
    constant rays, and keeps nothing from frame to frame."""

    def __init__(self, world: WorldDescription, params: FrontCameraParams, scene: OmniCameraParams):
        self.world, self.params, self.scene = world, params, scene
        cam = self.camera = params.camera
        rays = cam.pixel_grid_rays()
        self._rays = rays.astype(np.float32)  # body-frame unit rays, height x width x 3
        self._origin = cam.origin
        ground = cam.ray_plane_points(rays.reshape(-1, 3), 0.0).reshape(cam.height, cam.width, 2)
        reach = np.hypot(ground[..., 0] - cam.origin[0], ground[..., 1] - cam.origin[1])
        far = ~(reach <= params.max_range)  # NaN (no ground) too
        ground[far] = 1.0e6  # off the texture: the surroundings' colour
        self._ground = ground.astype(np.float32)
        reach_max = params.max_range + float(np.hypot(*cam.origin[:2]))
        self.texture = FieldTexture(world.field, replace(scene, texture_resolution=params.texture_resolution),
                                    math.inf, reach_max)
        self._surround = tuple(float(c) for c in scene.surround_rgb)
        self._noise = _noise_table(params.noise_std)
        self._noise_words = math.ceil(cam.height * cam.width * 3 / 8)  # random 64-bit words a frame
        self._posts = [p for side in (-1, 1) for p in world.field.goal_posts(side)]
        psi = np.linspace(0.0, 2.0 * math.pi, _SPHERE_OUTLINE_POINTS, endpoint=False)
        self._circle = np.column_stack([np.cos(psi), np.sin(psi)])

    # --- rendering ------------------------------------------------------------------------------
    def render(self, me: RobotState, ball: BallState, others: Sequence[RobotState], t: float,
               rng: np.random.Generator) -> np.ndarray:
        """The image robot ``me``'s front camera sees at time ``t`` [s] (RGB uint8, height x width x 3)."""
        image = self._scene(me, ball, others)
        return self._finish(image, t, rng)

    def render_board(self, me: RobotState, ball: BallState, others: Sequence[RobotState], t: float,
                     rng: np.random.Generator, board: np.ndarray, size: tuple[float, float],
                     rotation: np.ndarray, position: np.ndarray) -> np.ndarray:
        """As ``render``, with the flat RGB image ``board`` (its top-left corner at the board frame's origin,
        columns along its x, rows along its y) of ``size`` (x, y) [m] placed in front of everything at the
        pose (``rotation``: body <- board, ``position`` [m]) in robot ``me``'s body frame."""
        image = self._scene(me, ball, others)
        rays = self._rays.reshape(-1, 3).astype(np.float64)
        normal = np.asarray(rotation, np.float64)[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            s = ((np.asarray(position) - self._origin) @ normal) / (rays @ normal)
        hit = np.isfinite(s) & (s > 0.0)
        local = (self._origin[None, :] + np.where(hit, s, 0.0)[:, None] * rays - position) @ rotation
        rows, cols = board.shape[:2]
        map_x = np.where(hit, local[:, 0] / size[0] * cols - 0.5, -10.0).astype(np.float32)
        map_y = np.where(hit, local[:, 1] / size[1] * rows - 0.5, -10.0).astype(np.float32)
        shape = (self.camera.height, self.camera.width)
        drawn = cv2.remap(board, map_x.reshape(shape), map_y.reshape(shape), cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_CONSTANT, borderValue=(0, 0, 0))
        weight = cv2.remap(np.full((rows, cols), 255, np.uint8), map_x.reshape(shape), map_y.reshape(shape),
                           cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        alpha = (weight.astype(np.float32) / 255.0)[..., None]
        image = np.clip(alpha * drawn + (1.0 - alpha) * image + 0.5, 0, 255).astype(np.uint8)
        return self._finish(image, t, rng)

    def _scene(self, me: RobotState, ball: BallState, others: Sequence[RobotState]) -> np.ndarray:
        tex = self.texture
        maps = cv2.transform(self._ground, tex.texel_transform(me.x, me.y, me.theta))
        image = cv2.remap(tex.image, maps, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                          borderValue=self._surround)
        c, s = math.cos(me.theta), math.sin(me.theta)

        def body(wx: float, wy: float) -> tuple[float, float]:
            return c * (wx - me.x) + s * (wy - me.y), -s * (wx - me.x) + c * (wy - me.y)

        robot, field, p = self.world.robot, self.world.field, self.scene
        bodies: list[tuple[float, str, tuple[float, float, float, float], float, RGB]] = []
        for o in others:
            bodies.append(self._entry("cylinder", *body(o.x, o.y), robot.height, robot.radius, o.x, o.y,
                                      p.robot_rgb))
        for x, y in self._posts:
            bodies.append(self._entry("cylinder", *body(x, y), field.goal_height, field.post_radius, x, y, p.line_rgb))
        bodies.append(self._entry("sphere", *body(ball.x, ball.y), ball.z, self.world.ball.radius, ball.x, ball.y,
                                  p.ball_rgb))
        reach = self.params.max_range + 1.0
        for distance, kind, geometry, light, rgb in sorted(bodies, key=lambda b: -b[0]):
            if distance > reach:
                continue
            if kind == "sphere":
                self._draw_sphere(image, geometry, _lit(rgb, light))
            else:
                self._draw_cylinder(image, geometry, _lit(rgb, light))
        return image

    def _entry(self, kind: str, bx: float, by: float, z: float, radius: float, wx: float, wy: float,
               rgb: RGB) -> tuple[float, str, tuple[float, float, float, float], float, RGB]:
        """A body to draw: its distance from the lens [m], kind, (x, y, z or height, radius) in the body frame,
        the field's lighting where it stands, its colour."""
        distance = math.hypot(bx - self._origin[0], by - self._origin[1])
        light = float(self.scene.field_lighting(wx, wy))
        return distance, kind, (bx, by, z, radius), light, rgb

    def _box(self, corners: np.ndarray) -> tuple[int, int, int, int] | None:
        """The image box (u0, v0, u1, v1), end exclusive, around body-frame points; None if all lie behind the
        lens or the box misses the image."""
        cam = self.camera
        depth = (corners - self._origin) @ cam.rotation[:, 2]
        if np.all(depth <= _MIN_DEPTH):
            return None
        if np.any(depth <= _MIN_DEPTH):
            return 0, 0, cam.width, cam.height
        uv, _ = cam.project(corners)
        u0 = max(int(math.floor(uv[:, 0].min())) - _BOX_PAD, 0)
        v0 = max(int(math.floor(uv[:, 1].min())) - _BOX_PAD, 0)
        u1 = min(int(math.ceil(uv[:, 0].max())) + _BOX_PAD + 1, cam.width)
        v1 = min(int(math.ceil(uv[:, 1].max())) + _BOX_PAD + 1, cam.height)
        return (u0, v0, u1, v1) if u0 < u1 and v0 < v1 else None

    def _draw_sphere(self, image: np.ndarray, geometry: tuple[float, float, float, float],
                     rgb: tuple[float, float, float]) -> None:
        """A sphere (centre x, y, z, radius [m], body frame), anti-aliased over one pixel's angle at its edge."""
        centre = np.array(geometry[:3])
        radius = geometry[3]
        rel = centre - self._origin
        dist = float(np.linalg.norm(rel))
        if dist <= radius * 1.001:
            return  # the lens is inside the ball
        axis = rel / dist
        spread = radius / dist
        side = np.cross(axis, [0.0, 0.0, 1.0])
        side = side / np.linalg.norm(side) if np.linalg.norm(side) > 1e-9 else np.array([0.0, 1.0, 0.0])
        up = np.cross(side, axis)
        # The tangent cone's rim, a little wider (one pixel's angle) for the anti-aliased edge.
        grow = spread + 2.0 * self.camera.angle_per_pixel
        rim = math.sqrt(max(1.0 - grow * grow, 0.0)) * axis[None, :] + grow * (
            self._circle[:, :1] * side[None, :] + self._circle[:, 1:] * up[None, :])
        box = self._box(self._origin[None, :] + rim)
        if box is None:
            return
        u0, v0, u1, v1 = box
        rays = self._rays[v0:v1, u0:u1]
        cos_angle = rays @ axis.astype(np.float32)
        angle = np.arccos(np.clip(cos_angle, -1.0, 1.0))
        coverage = np.clip((math.asin(spread) - angle) / self.camera.angle_per_pixel + 0.5, 0.0, 1.0)
        if not np.any(coverage > 0.0):
            return
        # The surface normal where each ray meets the sphere (or grazes it, at the edge): its upward part lights it.
        along = cos_angle * dist
        across2 = np.maximum(dist * dist - along * along, 0.0)
        t = along - np.sqrt(np.maximum(radius * radius - across2, 0.0))
        normal_z = (t * rays[..., 2] - rel[2]) / radius
        ambient = self.params.ball_ambient
        shade = ambient + (1.0 - ambient) * np.clip(0.5 + 0.5 * normal_z, 0.0, 1.0)
        colour = shade[..., None] * np.array(rgb, np.float32)
        crop = image[v0:v1, u0:u1].astype(np.float32)
        a = coverage[..., None].astype(np.float32)
        image[v0:v1, u0:u1] = np.clip(a * colour + (1.0 - a) * crop + 0.5, 0, 255).astype(np.uint8)

    def _draw_cylinder(self, image: np.ndarray, geometry: tuple[float, float, float, float],
                       rgb: tuple[float, float, float]) -> None:
        """An upright cylinder standing at (x, y) [m] of the body frame, ``height`` and ``radius`` [m]: its side and
        (seen from above) its top."""
        cx, cy, height, radius = geometry
        corners = np.array([(cx + sx * radius, cy + sy * radius, z) for sx in (-1, 1) for sy in (-1, 1)
                            for z in (0.0, height)])
        box = self._box(corners)
        if box is None:
            return
        side_rgb = np.clip(np.array(rgb) * self.params.robot_ambient, 0, 255).astype(np.uint8)
        self._paint_cylinder(image, box, geometry, side_rgb, np.clip(np.array(rgb), 0, 255).astype(np.uint8))

    def _paint_cylinder(self, image: np.ndarray, box: tuple[int, int, int, int],
                        geometry: tuple[float, float, float, float], side_rgb: np.ndarray,
                        top_rgb: np.ndarray) -> None:
        """Paints the pixels of ``box`` whose rays meet the cylinder's side (``side_rgb``) or, nearer, its top."""
        _kernels.paint_cylinder(image, self._rays, box, self._origin, geometry, side_rgb, top_rgb)

    def _finish(self, image: np.ndarray, t: float, rng: np.random.Generator) -> np.ndarray:
        light = self.scene.time_lighting(t)
        if self.params.noise_std > 0.0:
            raw = rng.bit_generator.random_raw(self._noise_words).view(np.uint8)[:image.size].reshape(image.shape)
            cv2.addWeighted(image, light, cv2.LUT(raw, self._noise), 1.0, -128.0, dst=image)
        else:
            cv2.convertScaleAbs(image, dst=image, alpha=light)
        return image


def _lit(rgb: RGB, light: float) -> tuple[float, float, float]:
    return rgb[0] * light, rgb[1] * light, rgb[2] * light

