"""The simulated omni-directional camera: the image one robot sees through its convex mirror.

Requires: the match's ``WorldDescription`` (field markings, goals, ball radius, robot cylinder),
the camera's ``MirrorModel`` (omni_vision: pixel <-> body-frame ground point), ``OmniCameraParams``,
the true ``RobotState`` of the viewer and of the other robots and the ``BallState`` (world frame),
the simulation time [s] and the run's ``numpy.random.Generator`` (the only source of randomness).
Provides: ``OmniCameraRenderer.render`` -> ``RenderedFrame``: an RGB image (height x width x 3,
uint8) in the mirror model's image coordinates (robot front up, its left to the left) and, on
request, the per-pixel ``ColorClass`` truth (labels) for calibrating the colour lookup table: GREEN carpet,
WHITE lines, goal frames and posts, BALL, BLACK robots and the own body, UNKNOWN for everything else and
for pixels that blend classes (edges, and far lines narrower than a pixel's footprint).

What the image shows: the green carpet inside the lines and on the border, every white marking
(lines, arcs, spots) and the goals' ground frames, the darker ground inside each goal, the
surroundings beyond the arena; as 3-D bodies the goal posts (white cylinders), the other robots
(dark cylinders) and the ball (an orange sphere). A body rising above the mirror's viewpoint
hides everything radially behind it up to the rim; a lower one hides a finite shadow; a point
at height z appears where its ray meets the ground (``MirrorModel.ground_distance``), so a
lofted ball shows farther out, and a ball at or above the viewpoint is not seen. Inside
``r_min`` is the robot's own body, and the mirror holder's struts cross the ring; outside
``r_max`` the image is black. Not modelled: goal nets, the crossbar (above the viewpoint),
shadows, motion blur, lens blur.

Parameters (``OmniCameraParams``): lighting across the field (world-fixed: relative amplitude,
wavelength [m]), lighting over time (relative amplitude, period [s]), pixel noise [grey levels,
0-255], the ground texture's resolution [m/texel], the RGB colours of carpet, lines (and goal
frame), goal inside, ball, robots (and the own body) and surroundings, and the struts' bearings
[deg] and width [px].

How, for speed (a median of about 3 ms a frame at 480 x 480 with the ball and nine robots, one core): the
field with its world-fixed lighting is drawn once into a texture, in two resolutions (``FieldTexture``:
the far ring reads a coarser copy, so that thin far lines blend instead of aliasing); a frame is one
``cv2.remap`` of that texture through each pixel's ground point moved by the viewer's pose (one
``cv2.transform``), the bodies drawn over it as image polygons (their outlines sampled in polar
coordinates, farthest first), a constant overlay for the own body, and noise made of random bytes from
``rng`` through a table of normal quantiles.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from statistics import NormalDist

import cv2
import numpy as np

from nubot_common.color_class import ColorClass
from nubot_common.field import FieldGeometry
from nubot_common.mirror import MirrorModel
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import RGB, OmniCameraParams
from sim_visual.world import BallState, RobotState

MIP_FACTOR = 4  # level 1 of the field texture is this many times coarser than level 0
_SHIFT = 4  # sub-pixel bits of the polygon coordinates given to OpenCV
_SCALE = float(1 << _SHIFT)
_PURE = 191  # coverage (of 255) from which a pixel is labelled with a class
_RIM_PAD = 3.0  # bodies reaching past the rim are drawn out to r_max + this [px] (the rim is masked later)
_CYLINDER_OUTLINE_POINTS = 16  # samples across a cylinder's near (and far) edge
_BALL_OUTLINE_POINTS = 32


@dataclass
class RenderedFrame:
    image: np.ndarray  # height x width x 3, uint8, RGB
    labels: np.ndarray | None  # height x width, uint8 ColorClass values; None unless asked for


@dataclass(frozen=True)
class _Body:
    """A body to draw: its outline in the image, its colour and class, its distance for depth order."""

    distance: float  # [m] horizontal, from the viewer
    outline: np.ndarray  # N x 2 int32 pixel coordinates scaled by 2**_SHIFT
    rgb: tuple[float, float, float]
    label: ColorClass


class FieldTexture:
    """The arena's ground (lines plus border), world-fixed and lit, as one RGB atlas with the coverage of its
    areas (arena, goal inside, white markings: what the labels are made from), each at two
    resolutions side by side: level 0 at ``texture_resolution``, level 1 (``MIP_FACTOR`` times coarser, the
    average of level 0) for pixels farther than ``split_distance`` [m], where one image pixel spans many
    level-0 texels radially and sampling level 0 would alias the lines. Beyond the arena: the surroundings.
    Level-0 texel (row i, column j) shows the world point (x_min + (j + 0.5) res, y_min + (i + 0.5) res)."""

    def __init__(self, field: FieldGeometry, params: OmniCameraParams, split_distance: float, reach: float):
        res, f = params.texture_resolution, MIP_FACTOR
        self.resolution = res
        self.x_min = -(field.half_length + field.border)
        self.y_min = -(field.half_width + field.border)
        cols = f * math.ceil(-2.0 * self.x_min / (f * res))
        rows = f * math.ceil(-2.0 * self.y_min / (f * res))
        arena, inside, white = (np.zeros((rows, cols), np.uint8) for _ in range(3))  # anti-aliased coverage
        hl, hw = field.half_length + field.border, field.half_width + field.border
        cv2.fillPoly(arena, [self._texels(np.array([(-hl, -hw), (hl, -hw), (hl, hw), (-hl, hw)]))], 255,
                     cv2.LINE_AA, _SHIFT)
        for mask, polygons in ((inside, _goal_insides(field)), (white, _white_markings(field, res))):
            for polygon in polygons:  # one at a time: OpenCV fills the overlap of polygons drawn together as a hole
                cv2.fillPoly(mask, [self._texels(polygon)], 255, cv2.LINE_AA, _SHIFT)
        i, j = np.mgrid[0:rows, 0:cols].astype(np.float32)
        light = params.field_lighting(self.x_min + (j + 0.5) * res, self.y_min + (i + 0.5) * res)
        a_arena, a_inside, a_white = ((m.astype(np.float32) / 255.0)[..., None] for m in (arena, inside, white))
        carpet, goal_inside, line, surround = (np.array(c, np.float32) for c in (
            params.carpet_rgb, params.goal_inside_rgb, params.line_rgb, params.surround_rgb))
        ground = (1.0 - a_inside) * carpet + a_inside * goal_inside
        lit = ((1.0 - a_white) * ground + a_white * line) * light[..., None]
        colour = np.clip((1.0 - a_arena) * surround + a_arena * lit + 0.5, 0, 255).astype(np.uint8)
        small = (cols // f, rows // f)
        coverage = np.dstack([arena, inside, white])
        # The gap between the levels keeps each level's look past the arena's edge off the other level.
        self.level1_offset = cols + math.ceil(max(min(split_distance, reach) / res, reach / (f * res))) + 2
        shape = (rows, self.level1_offset + small[0])
        self.image = np.empty(shape + (3,), np.uint8)
        self.image[:] = params.surround_rgb
        self.coverage = np.zeros(shape + (3,), np.uint8)  # arena, goal inside, white markings
        for atlas, level0 in ((self.image, colour), (self.coverage, coverage)):
            atlas[:, :cols] = level0
            atlas[:small[1], self.level1_offset:] = cv2.resize(level0, small, interpolation=cv2.INTER_AREA)

    def _texels(self, polygon: np.ndarray) -> np.ndarray:
        """World points (N x 2) [m] as fixed-point level-0 texel coordinates (column, row)."""
        j = (polygon[:, 0] - self.x_min) / self.resolution - 0.5
        i = (polygon[:, 1] - self.y_min) / self.resolution - 0.5
        return np.round(np.stack([j, i], axis=1) * _SCALE).astype(np.int32)

    def texel_transform(self, x: float, y: float, theta: float) -> np.ndarray:
        """The 2 x 3 affine map from the body frame [m] of the robot at (x, y) [m] with the heading ``theta``
        [rad] to level-0 texel coordinates (column, row)."""
        c, s, res = math.cos(theta) / self.resolution, math.sin(theta) / self.resolution, self.resolution
        return np.array([[c, -s, (x - self.x_min) / res - 0.5], [s, c, (y - self.y_min) / res - 0.5]], np.float64)

    @property
    def level1_shift(self) -> tuple[float, float]:
        """Level-1 atlas coordinates are level-0 coordinates / MIP_FACTOR + this (column, row)."""
        shift = 0.5 / MIP_FACTOR - 0.5
        return self.level1_offset + shift, shift


def _classes(coverage: np.ndarray) -> np.ndarray:
    """Pixel labels from the coverage (0-255) of arena, goal inside and white markings: a class where it covers
    at least three quarters of the pixel and the others at most a quarter; mixed pixels are UNKNOWN."""
    arena, inside, white = coverage[..., 0], coverage[..., 1], coverage[..., 2]
    labels = np.full(coverage.shape[:2], ColorClass.UNKNOWN, np.uint8)
    labels[(arena >= _PURE) & (inside <= 255 - _PURE) & (white <= 255 - _PURE)] = ColorClass.GREEN
    labels[white >= _PURE] = ColorClass.WHITE
    return labels


def _band(p0: tuple[float, float], p1: tuple[float, float], width: float) -> np.ndarray:
    """The rectangle of ``width`` [m] centred on the segment p0-p1, grown by width / 2 past each end so that
    lines meeting at a corner close it."""
    (x0, y0), (x1, y1) = p0, p1
    length = math.hypot(x1 - x0, y1 - y0)
    ux, uy = (x1 - x0) / length, (y1 - y0) / length
    h = width / 2.0
    ex, ey, nx, ny = ux * h, uy * h, -uy * h, ux * h
    return np.array([(x0 - ex + nx, y0 - ey + ny), (x1 + ex + nx, y1 + ey + ny),
                     (x1 + ex - nx, y1 + ey - ny), (x0 - ex - nx, y0 - ey - ny)])


def _arc_band(cx: float, cy: float, radius: float, start: float, end: float, width: float,
              res: float) -> np.ndarray:
    """The ring sector ``width`` [m] wide centred on an arc, as a polygon sampled finer than a texel."""
    n = max(8, math.ceil((end - start) * (radius + width) / res))
    a = np.linspace(start, end, n + 1)
    outer, inner = radius + width / 2.0, max(radius - width / 2.0, 0.0)
    xs = np.concatenate([cx + outer * np.cos(a), cx + inner * np.cos(a[::-1])])
    ys = np.concatenate([cy + outer * np.sin(a), cy + inner * np.sin(a[::-1])])
    return np.stack([xs, ys], axis=1)


def _white_markings(field: FieldGeometry, res: float) -> list[np.ndarray]:
    """Every white marking on the ground as a world polygon [m]: lines, arcs, spots, goals' ground frames."""
    w = field.line_width
    polygons = [_band(p0, p1, w) for p0, p1 in field.line_segments()]
    polygons += [_arc_band(a.x, a.y, a.radius, a.start, a.end, w, res) for a in field.arcs()]
    r_spot = field.spot_diameter / 2.0
    polygons += [_arc_band(x, y, r_spot / 2.0, -math.pi, math.pi, r_spot, res) for x, y in field.spots()]
    # The goal's frame lies on the ground along its sides and back, as wide as a post.
    hl, frame = field.half_length, 2.0 * field.post_radius
    inner_y, depth = field.goal_width / 2.0, field.goal_depth
    for side in (-1, 1):
        for y0, y1 in ((inner_y, inner_y + frame), (-inner_y - frame, -inner_y)):
            polygons.append(np.array([(side * hl, y0), (side * (hl + depth), y0),
                                      (side * (hl + depth), y1), (side * hl, y1)]))
        back = side * (hl + depth - frame), side * (hl + depth)
        polygons.append(np.array([(back[0], -inner_y - frame), (back[1], -inner_y - frame),
                                  (back[1], inner_y + frame), (back[0], inner_y + frame)]))
    return polygons


def _goal_insides(field: FieldGeometry) -> list[np.ndarray]:
    """The ground inside each goal [m] (behind the goal line, between the frame's sides)."""
    hl, y = field.half_length, field.goal_width / 2.0
    return [np.array([(s * hl, -y), (s * (hl + field.goal_depth), -y), (s * (hl + field.goal_depth), y),
                      (s * hl, y)]) for s in (-1, 1)]


def own_body_mask(mirror: MirrorModel, params: OmniCameraParams) -> np.ndarray:
    """The pixels (height x width, uint8 0/1) that show the robot itself: the disc inside ``r_min`` and the mirror
    holder's struts across the ring (the struts hide what lies behind them)."""
    v, u = np.mgrid[0:mirror.height, 0:mirror.width].astype(np.float64)
    r = np.hypot(u - mirror.centre_u, v - mirror.centre_v)
    mask = (r < mirror.r_min).astype(np.uint8)
    h = params.strut_width / 2.0
    for angle in params.strut_angles_deg if h > 0.0 else ():
        ru, rv = -math.sin(math.radians(angle)), -math.cos(math.radians(angle))  # outwards in the image
        corners = [(mirror.centre_u + r * ru - s * h * rv, mirror.centre_v + r * rv + s * h * ru)
                   for r, s in ((mirror.r_min - 1.0, -1), (mirror.r_max + _RIM_PAD, -1),
                                (mirror.r_max + _RIM_PAD, 1), (mirror.r_min - 1.0, 1))]
        cv2.fillPoly(mask, [np.round(np.array(corners) * _SCALE).astype(np.int32)], 1, cv2.LINE_8, _SHIFT)
    mask[r > mirror.r_max] = 0
    return mask


def _split_distance(mirror: MirrorModel, texel: float) -> float:
    """The ground distance [m] from which one image pixel spans at least ``texel`` [m] radially (inf: nowhere)."""
    r = np.linspace(mirror.r_min, mirror.r_max, 4096)
    d = mirror.distance(r)
    coarse = np.flatnonzero(np.gradient(d, r) >= texel)
    return float(d[coarse[0]]) if coarse.size else math.inf


def _scaled(rgb: RGB, light: float) -> tuple[float, float, float]:
    return rgb[0] * light, rgb[1] * light, rgb[2] * light


def _noise_table(std: float) -> np.ndarray:
    """256 grey levels 128 + std z, z the normal quantiles of the 256 equally likely bytes, rescaled to
    unit standard deviation: a uniform random byte through this table is normal noise (offset 128)."""
    z = np.array([NormalDist().inv_cdf((k + 0.5) / 256.0) for k in range(256)])
    z /= z.std()
    return np.clip(np.round(128.0 + std * z), 0, 255).astype(np.uint8)


class OmniCameraRenderer:
    """Renders the omni camera's image of any robot on one field through one mirror; holds the field texture and
    the mirror's constant maps, and keeps nothing from frame to frame."""

    def __init__(self, world: WorldDescription, mirror: MirrorModel, params: OmniCameraParams):
        self.world = world
        self.mirror = mirror
        self.params = params
        self._reach = mirror.max_distance
        self.split_distance = _split_distance(mirror, MIP_FACTOR * params.texture_resolution)
        self.texture = FieldTexture(world.field, params, self.split_distance, self._reach)
        bx, by, _ = mirror.pixel_grid()
        self._ground = np.dstack([bx, by])  # each pixel's body-frame ground point [m], float32
        # Far pixels read level 1: their level-0 texel coordinates scaled and shifted (one pass each a frame).
        far = np.repeat((np.hypot(bx, by) >= self.split_distance)[..., None], 2, axis=2)
        self._level_scale = np.where(far, 1.0 / MIP_FACTOR, 1.0).astype(np.float32)
        self._level_shift = np.where(far, np.array(self.texture.level1_shift), 0.0).astype(np.float32)
        v, u = np.mgrid[0:mirror.height, 0:mirror.width].astype(np.float64)
        self._outside = np.hypot(u - mirror.centre_u, v - mirror.centre_v) > mirror.r_max
        self._keep = np.repeat(~self._outside[..., None], 3, axis=2).astype(np.uint8) * 255
        self._own_mask = own_body_mask(mirror, params)
        self._own_image = np.zeros((mirror.height, mirror.width, 3), np.uint8)
        self._own_image[self._own_mask > 0] = params.robot_rgb
        self._own_labels = (self._own_mask > 0).astype(np.uint8) * np.uint8(ColorClass.BLACK)
        self._noise = _noise_table(params.noise_std)
        self._noise_words = math.ceil(mirror.height * mirror.width * 3 / 8)  # random 64-bit words a frame
        self._surround = tuple(float(c) for c in params.surround_rgb)
        self._posts = [p for side in (-1, 1) for p in world.field.goal_posts(side)]
        self._cylinder_steps = np.linspace(-1.0, 1.0, _CYLINDER_OUTLINE_POINTS)
        psi = np.linspace(0.0, 2.0 * math.pi, _BALL_OUTLINE_POINTS, endpoint=False)
        self._ball_cos, self._ball_sin = np.cos(psi), np.sin(psi)

    # --- rendering ------------------------------------------------------------------------------
    def render(self, me: RobotState, ball: BallState, others: Sequence[RobotState], t: float,
               rng: np.random.Generator, labels: bool = False) -> RenderedFrame:
        """The image robot ``me`` sees at time ``t`` [s]; ``labels``: also the per-pixel ColorClass truth."""
        tex = self.texture
        maps = cv2.transform(self._ground, tex.texel_transform(me.x, me.y, me.theta))
        cv2.multiply(maps, self._level_scale, dst=maps)
        cv2.add(maps, self._level_shift, dst=maps)
        image = cv2.remap(tex.image, maps, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                          borderValue=self._surround)
        truth = None
        if labels:
            truth = _classes(cv2.remap(tex.coverage, maps, None, cv2.INTER_LINEAR, borderMode=cv2.BORDER_CONSTANT,
                                       borderValue=0))
        for body in self._bodies(me, ball, others):
            cv2.fillPoly(image, [body.outline], body.rgb, cv2.LINE_AA, _SHIFT)
            if truth is not None:  # the body, without the pixels its anti-aliased edge blends (about 1 px each side)
                cv2.fillPoly(truth, [body.outline], int(body.label), cv2.LINE_8, _SHIFT)
                cv2.polylines(truth, [body.outline], True, int(ColorClass.UNKNOWN), 2, cv2.LINE_8, _SHIFT)
        cv2.copyTo(self._own_image, self._own_mask, image)
        light = self.params.time_lighting(t)
        if self.params.noise_std > 0.0:
            raw = rng.bit_generator.random_raw(self._noise_words).view(np.uint8)[:image.size].reshape(image.shape)
            cv2.addWeighted(image, light, cv2.LUT(raw, self._noise), 1.0, -128.0, dst=image)
        else:
            cv2.convertScaleAbs(image, dst=image, alpha=light)
        cv2.bitwise_and(image, self._keep, dst=image)
        if truth is not None:
            cv2.copyTo(self._own_labels, self._own_mask, truth)
            truth[self._outside] = int(ColorClass.UNKNOWN)
        return RenderedFrame(image, truth)

    def _bodies(self, me: RobotState, ball: BallState, others: Sequence[RobotState]) -> list[_Body]:
        """Every body in view (robots, goal posts, ball) as an image outline, nearest last."""
        robot, field, p = self.world.robot, self.world.field, self.params
        n_robots = len(others)
        wx = np.array([o.x for o in others] + [x for x, _ in self._posts] + [ball.x])
        wy = np.array([o.y for o in others] + [y for _, y in self._posts] + [ball.y])
        c, s = math.cos(me.theta), math.sin(me.theta)
        bx = c * (wx - me.x) + s * (wy - me.y)
        by = -s * (wx - me.x) + c * (wy - me.y)
        light = p.field_lighting(wx, wy)  # bodies are lit where they stand (OpenCV saturates colours)
        distance = np.hypot(bx, by)
        radius = np.where(np.arange(len(wx) - 1) < n_robots, robot.radius, field.post_radius)
        height = np.where(np.arange(len(wx) - 1) < n_robots, robot.height, field.goal_height)
        bodies = []
        visible, outlines = self._cylinder_outlines(bx[:-1], by[:-1], radius, height)
        for k in np.flatnonzero(visible):
            rgb, label = (p.robot_rgb, ColorClass.BLACK) if k < n_robots else (p.line_rgb, ColorClass.WHITE)
            bodies.append(_Body(float(distance[k]), outlines[k], _scaled(rgb, float(light[k])), label))
        outline = self._sphere_outline(float(bx[-1]), float(by[-1]), ball.z, self.world.ball.radius)
        if outline is not None:
            bodies.append(_Body(float(distance[-1]), outline, _scaled(p.ball_rgb, float(light[-1])), ColorClass.BALL))
        bodies.sort(key=lambda b: -b.distance)
        return bodies

    def _cylinder_outlines(self, cx: np.ndarray, cy: np.ndarray, radius: np.ndarray,
                           height: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """The image regions of upright cylinders standing at the body-frame points (cx, cy) [m]: for each
        bearing through one, from where its ray meets the near side to where it clears the far top edge (past
        the rim when the cylinder rises above the viewpoint). Returns which are in view, and the outlines."""
        d = np.hypot(cx, cy)
        visible = (d > radius * 1.001) & (d - radius < self._reach)
        half = np.arcsin(np.minimum(radius / np.maximum(d, 1e-9), 1.0))
        alpha = half[:, None] * self._cylinder_steps[None, :]
        along = d[:, None] * np.cos(alpha)
        across = np.sqrt(np.maximum(radius[:, None] ** 2 - (d[:, None] * np.sin(alpha)) ** 2, 0.0))
        far = self.mirror.ground_distance(along + across, height[:, None])
        bearing = np.arctan2(cy, cx)[:, None] + np.concatenate([alpha, alpha[:, ::-1]], axis=1)
        return visible, self._outline(bearing, np.concatenate([along - across, far[:, ::-1]], axis=1))

    def _sphere_outline(self, cx: float, cy: float, cz: float, radius: float) -> np.ndarray | None:
        """The image region of a sphere centred at (cx, cy) [m] of the body frame, height ``cz`` [m]: the ground
        points of the cone of rays from the viewpoint that touch it (none at or above the viewpoint)."""
        h = self.mirror.viewpoint_height
        if cz >= h:
            return None
        centre = np.array([cx, cy, cz - h])
        dist = math.sqrt(cx * cx + cy * cy + (cz - h) ** 2)
        if dist <= radius:
            return None
        axis = centre / dist
        horizontal = math.hypot(cx, cy)
        # Two unit vectors across the cone's axis: one horizontal, one in the vertical plane through the axis.
        side = np.array([-cy / horizontal, cx / horizontal, 0.0]) if horizontal > 1e-9 else np.array([0.0, 1.0, 0.0])
        up = np.cross(axis, side)
        spread = radius / dist
        rays = math.sqrt(1.0 - spread * spread) * axis[None, :] + spread * (
            self._ball_cos[:, None] * side[None, :] + self._ball_sin[:, None] * up[None, :])
        down = rays[:, 2] < -1e-9
        reach = np.where(down, -h / np.where(down, rays[:, 2], -1.0), np.inf)  # rays that never come down: past the rim
        ground = reach * np.hypot(rays[:, 0], rays[:, 1])
        if not np.min(ground) < self._reach:
            return None
        return self._outline(np.arctan2(rays[:, 1], rays[:, 0]), ground)

    def _outline(self, bearing: np.ndarray, distance: np.ndarray) -> np.ndarray:
        """Body-frame polar points (bearing [rad], ground distance [m]) as fixed-point image points (same shape
        plus a last axis (u, v)); points past the mirror's reach go just outside the rim."""
        m = self.mirror
        r = np.where(distance < self._reach, m.radius(np.minimum(distance, self._reach)), m.r_max + _RIM_PAD)
        u = m.centre_u - r * np.sin(bearing)
        v = m.centre_v - r * np.cos(bearing)
        return np.round(np.stack([u, v], axis=-1) * _SCALE).astype(np.int32)
