"""Online path planning for the omnidirectional robot: subtargets round obstacles, then a cubic B-spline.

Requires: the robot's position and velocity, waypoints ending at the goal, obstacles as discs (other robots,
goal posts) and the bounds the robot centre must stay in, all in one 2-D field frame.
Provides: ``subtargets`` (via-points so that the straight route keeps every obstacle's clearance) and
``plan`` -> ``Trajectory`` (time-stamped positions and velocities along a smooth path that keeps the
clearances and bounds, within the speed, acceleration and curvature limits).
Units SI throughout: m, s, m/s, m/s^2. Pure core: no ROS, safe to call every 30 ms control cycle.

``plan`` works in four steps:
1. subtargets between consecutive route points (iterative; obstacles too close together to pass between
   form a cluster passed as one, the subtarget sitting where the tangents from both segment ends meet);
2. a cubic interpolating B-spline through the route, parameterised by chord length; segments longer than
   1.5 m get points along them first, so that the spline stays near the (clear) straight route;
3. the spline is sampled and, wherever a sample is inside a clearance or well out of bounds, a via-point is
   added (or a subtarget moved) outward and the spline refitted, a bounded number of times;
4. the samples are spaced evenly in arc length and given a speed profile: at most max_speed, at most
   sqrt(max_lateral_accel / curvature), speeding up and braking so that the whole acceleration (along the
   path and towards the curve's centre) stays within max_accel.
Everything is vectorised over obstacles and samples; only the subtarget and refit iterations loop.
"""

from __future__ import annotations

import bisect
import dataclasses
import functools
import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import BSpline, make_interp_spline

from nubot_common.params import require_non_negative, require_positive

Point = tuple[float, float]

_SAME_POINT = 0.01  # route points closer than this are one point; a goal this near the start is no move [m]
_DIRECTION_SPEED = 0.1  # a start velocity faster than this sets the spline's initial direction [m/s]
_MAX_REFITS = 6  # spline refits per plan to restore clearances and bounds
_TOLERANCE = 0.005  # clearance violations smaller than this are left alone [m]
_BOUNDS_TOLERANCE = 0.05  # bounds violations up to this are only clipped, larger ones corrected [m]
_MIN_VIA_GAP = 0.1  # a corrective via-point nearer than this to a route point moves that point instead [m]
_MIN_TURN_SIN = 0.05  # tangents round a cluster meeting at a sharper angle than this count as parallel
_MAX_SPAN = 1.5  # longer route segments get points along them before the spline is fitted [m]
_MIN_SPEED = 1e-3  # floor of the curvature speed limit, so that a cusp does not stall the time scale [m/s]


def _require_finite(obj: object) -> None:
    """Raise ValueError naming the first float field of the dataclass ``obj`` that is NaN or infinite."""
    for f in dataclasses.fields(obj):
        value = getattr(obj, f.name)
        if isinstance(value, float) and not math.isfinite(value):
            raise ValueError(f"{f.name} must be finite, got {value}")


@dataclass(frozen=True)
class Disc:
    """An obstacle: centre [m] and radius of its own footprint [m] (a robot: 0.26)."""

    x: float
    y: float
    radius: float

    def __post_init__(self) -> None:
        for name in ("x", "y", "radius"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"obstacle {name} must be finite, got {getattr(self, name)}")
        require_non_negative(self, "radius")


@dataclass(frozen=True)
class Bounds:
    """Where the robot centre may go [m]."""

    x_min: float
    x_max: float
    y_min: float
    y_max: float

    def __post_init__(self) -> None:
        for name in ("x_min", "x_max", "y_min", "y_max"):
            if not math.isfinite(getattr(self, name)):
                raise ValueError(f"bounds {name} must be finite, got {getattr(self, name)}")
        if not (self.x_min < self.x_max and self.y_min < self.y_max):
            raise ValueError(f"bounds must have x_min < x_max and y_min < y_max, got {self}")

    def clamp(self, p: Point) -> Point:
        return (min(max(float(p[0]), self.x_min), self.x_max), min(max(float(p[1]), self.y_min), self.y_max))

    def contains(self, p: Point) -> bool:
        return self.x_min <= p[0] <= self.x_max and self.y_min <= p[1] <= self.y_max


@dataclass(frozen=True)
class PlannerParams:
    """Robot size, kept gaps and motion limits of the planner."""

    robot_radius: float = 0.26  # [m]
    safety_margin: float = 0.15  # gap kept between hulls [m]
    max_speed: float = 3.25  # [m/s]
    max_accel: float = 2.5  # the robot's acceleration: along the path and towards the curve's centre [m/s^2]
    max_lateral_accel: float = 1.75  # curvature limit v <= sqrt(a_lat / kappa) [m/s^2], below max_accel
    sample_step: float = 0.05  # arc-length spacing of the samples [m]
    max_subtargets: int = 8  # per plan() call
    detour_factor: float = 1.15  # a subtarget sits this many clearances from the obstacle centre

    def __post_init__(self) -> None:
        _require_finite(self)
        require_positive(self, "robot_radius", "max_speed", "max_accel", "max_lateral_accel", "sample_step",
                         "detour_factor")
        require_non_negative(self, "safety_margin", "max_subtargets")
        if not isinstance(self.max_subtargets, int) or isinstance(self.max_subtargets, bool):
            raise ValueError(f"max_subtargets must be an integer, got {self.max_subtargets!r}")
        if self.detour_factor < 1.0:
            raise ValueError(f"detour_factor must be at least 1, got {self.detour_factor}")


def clearance(obstacle: Disc, params: PlannerParams) -> float:
    """Least centre distance kept from the obstacle: robot_radius + obstacle.radius + safety_margin."""
    return params.robot_radius + obstacle.radius + params.safety_margin


class _Scene:
    """The obstacles as arrays: centres (k, 2), clearances, their squares and detour radii (k,), clusters (k,)."""

    __slots__ = ("centres", "clear", "clear2", "detour", "labels")

    def __init__(self, obstacles: Sequence[Disc], params: PlannerParams):
        table = np.array([(o.x, o.y, o.radius) for o in obstacles], dtype=float).reshape(-1, 3)
        self.centres = table[:, :2]
        self.clear = params.robot_radius + params.safety_margin + table[:, 2]
        self.clear2 = self.clear**2
        self.detour = params.detour_factor * self.clear
        self.labels = _clusters(self.centres, self.detour)

    def __len__(self) -> int:
        return len(self.clear)

    def inside(self, points: np.ndarray) -> np.ndarray:
        """(m, k) mask: points[i] lies within the clearance of obstacle j."""
        rel = points[:, None, :] - self.centres[None, :, :]
        return np.einsum("mkj,mkj->mk", rel, rel) < self.clear2


def _clusters(centres: np.ndarray, radius: np.ndarray) -> np.ndarray:
    """Label of each obstacle's cluster: obstacles closer than the sum of their two ``radius`` (the detour
    radius: no way between them, or one too narrow for a subtarget) are connected, transitively."""
    if len(radius) == 0:
        return np.zeros(0, dtype=int)
    diff = centres[:, None, :] - centres[None, :, :]
    reach = np.einsum("ijk,ijk->ij", diff, diff) < (radius[:, None] + radius[None, :]) ** 2
    while True:  # transitive closure by squaring, at most log2(k) rounds
        wider = reach @ reach
        if np.array_equal(wider, reach):
            return reach.argmax(axis=1)  # lowest index in the cluster
        reach = wider


def _first_blocking(a: Point, b: Point, scene: _Scene) -> tuple[int, np.ndarray]:
    """The obstacle whose clearance segment a-b enters first (-1 if none), and the mask of the obstacles that
    count for this segment (those whose clearance contains neither a nor b)."""
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    rel = scene.centres - a
    ra2 = np.einsum("ij,ij->i", rel, rel)
    rd = rel @ (dx, dy)
    clear2 = scene.clear2
    active = (ra2 >= clear2) & (ra2 - 2.0 * rd + length2 >= clear2)  # |c - a|^2 and |c - b|^2
    if length2 < 1e-12:
        return -1, active
    # with both ends outside, the segment enters a clearance iff its closest point to the centre is inside
    perp2 = ra2 - rd * rd / length2
    blocked = active & (perp2 < clear2 * (1.0 - 1e-9)) & (rd > 0.0) & (rd < length2)
    if not blocked.any():
        return -1, active
    entry = rd - np.sqrt(np.maximum(clear2 - perp2, 0.0) * length2)  # along the segment, times its length
    return int(np.where(blocked, entry, np.inf).argmin()), active


def _turn(lo: list[float], hi: list[float]) -> float:
    """Sweep from angle 0 (inside the shadow) upwards across the overlapping angular intervals [lo, hi]
    (also taken one turn later); the first angle outside them, or >= pi."""
    lo2, hi2 = lo + [x + 2.0 * math.pi for x in lo], hi + [x + 2.0 * math.pi for x in hi]
    theta, moved = 0.0, True
    while moved and theta < math.pi:
        moved = False
        for a, b in zip(lo2, hi2):
            if a <= theta < b:
                theta, moved = b, True
    return theta


def _detour_point(a: Point, b: Point, k: int, active: np.ndarray, scene: _Scene, bounds: Bounds) -> Point:
    """A subtarget beside obstacle k, and the rest of its cluster, on the better side of the segment a-b."""
    ax, ay = a
    length = math.hypot(b[0] - ax, b[1] - ay)
    ux, uy = (b[0] - ax) / length, (b[1] - ay) / length
    nx, ny = -uy, ux
    members = active & (scene.labels == scene.labels[k])
    centres, clear, detour = scene.centres[members], scene.clear[members], scene.detour[members]
    # the cluster's angular shadow seen from a (row 0, looking at b) and from b (row 1, looking at a)
    rel = centres[None, :, :] - np.array((a, b))[:, None, :]
    along = rel @ (ux, uy)
    along[1] *= -1.0
    side = rel @ (nx, ny)
    dist = np.hypot(along, side)
    # an end between clearance and detour radius: the tangent only keeps halfway between them
    half = np.arcsin(np.minimum(np.where(dist > detour, detour, 0.5 * (clear + dist)) / dist, 1.0))
    centre = np.arctan2(side, along)
    lo, hi = centre - half, centre + half
    if hi.max() < math.pi and lo.min() > -math.pi:
        # the shadow is one arc round 0 that stays in front of both ends: its edges are the extremes
        (left_a, left_b), (right_a, right_b) = hi.max(axis=1).tolist(), (-lo.min(axis=1)).tolist()
    else:
        left_a, left_b = (_turn(l_, h_) for l_, h_ in zip(lo.tolist(), hi.tolist()))
        right_a, right_b = (_turn(l_, h_) for l_, h_ in zip((-hi).tolist(), (-lo).tolist()))
    points = []
    for sign, turn_a, turn_b in ((1.0, left_a, left_b), (-1.0, right_a, right_b)):
        apex = math.sin(turn_a + turn_b)
        if turn_a + turn_b < math.pi and apex > _MIN_TURN_SIN:
            # where the tangent from a meets the tangent from b: both new segments clear the cluster
            reach = length * math.sin(turn_b) / apex
            fwd, lat = reach * math.cos(turn_a), sign * reach * math.sin(turn_a)
            points.append((ax + fwd * ux + lat * nx, ay + fwd * uy + lat * ny))
        else:
            # the tangents do not meet: perpendicular to the segment, outside the whole cluster on that side
            kx, ky = scene.centres[k].tolist()
            spread = (centres[:, 0] - kx) * nx + (centres[:, 1] - ky) * ny
            offset = sign * float(np.max(sign * spread + detour))
            points.append((kx + offset * nx, ky + offset * ny))
    taken = scene.inside(np.array(points)).any(axis=1).tolist()
    best = min((not bounds.contains(p), taken[i], math.dist(a, p) + math.dist(p, b), i) for i, p in enumerate(points))
    return bounds.clamp(points[best[3]])


def _leg(a: Point, goal: Point, scene: _Scene, bounds: Bounds, budget: int) -> list[Point]:
    """Subtargets from a to goal (both excluded), at most ``budget``.

    A stack of pending targets: the segment to the top one is checked; when clear, the robot "moves" there;
    when blocked, a subtarget for the first obstacle on it is pushed, so the segment to that is checked next.
    """
    route: list[Point] = []
    stack = [goal]
    while stack and len(scene):
        k, active = _first_blocking(a, stack[-1], scene)
        if k < 0:
            reached = stack.pop()
            if stack:
                route.append(reached)
                a = reached
            continue
        if len(route) + len(stack) - 1 >= budget:
            break  # out of subtargets: keep what is pending, best effort
        stack.append(_detour_point(a, stack[-1], k, active, scene, bounds))
    return route + stack[:0:-1]


def _finite_point(p: Sequence[float], name: str) -> Point:
    try:
        x, y = (float(c) for c in p)
    except (TypeError, ValueError) as exc:
        raise ValueError(f"{name} must be a point (x, y), got {p!r}") from exc
    if not (math.isfinite(x) and math.isfinite(y)):
        raise ValueError(f"{name} must be finite, got {p!r}")
    return x, y


def subtargets(start: Point, goal: Point, obstacles: Sequence[Disc], params: PlannerParams,
               bounds: Bounds) -> list[Point]:
    """Via-points between start and goal (both excluded) so that each segment of start -> via... -> goal keeps
    every obstacle's clearance, when that is possible.

    Iterative: the first obstacle (nearest along the segment) whose clearance the segment enters gets a
    subtarget beside it on the better side (inside bounds, outside other clearances, shorter detour first).
    Obstacles closer than their two detour radii (detour_factor * clearance) form a cluster passed as one. The
    subtarget sits where the tangents from the segment's two ends to the cluster's detour circles meet, so both
    new segments clear the cluster; when the tangents do not meet, perpendicular to the segment outside the
    cluster. A new segment that is blocked itself gets a subtarget the same way. Obstacles whose clearance
    contains a segment's start or end are ignored for that segment. At most max_subtargets points.
    """
    a, b = _finite_point(start, "start"), _finite_point(goal, "goal")
    return _leg(a, b, _Scene(obstacles, params), bounds, params.max_subtargets)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Samples of a planned path about sample_step apart in arc length (arrays read-only)."""

    t: np.ndarray  # (n,) time from the plan's start [s], t[0] == 0, increasing
    s: np.ndarray  # (n,) arc length [m]
    xy: np.ndarray  # (n, 2) positions [m]
    v: np.ndarray  # (n, 2) velocities [m/s]
    via: tuple[Point, ...]  # the route the spline was fitted through (start, subtargets, waypoints, goal, and
    # the points added along long segments and by the adjustment)

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def length(self) -> float:
        return float(self.s[-1])

    @functools.cached_property
    def speed(self) -> np.ndarray:
        """(n,) speed at each sample [m/s] (computed once: the trajectory is read every cycle it is tracked)."""
        speed = np.hypot(self.v[:, 0], self.v[:, 1])
        speed.setflags(write=False)
        return speed

    def states_at(self, times: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """Positions (m, 2) and velocities (m, 2) at the given times; before 0 the start state, after the end the
        end state (standing still when end_speed was 0).

        Between two samples the velocity is interpolated linearly in time (the profile's constant acceleration)
        and the position along the step by the distance covered at that acceleration, so that positions and
        velocities agree even where the samples are far apart in time (starting from rest)."""
        times = np.asarray(times, dtype=float)
        if len(self.t) == 1:
            shape = times.shape + (2,)
            return np.broadcast_to(self.xy[0], shape).copy(), np.broadcast_to(self.v[0], shape).copy()
        # minimum/maximum instead of np.clip: the same numbers at a fraction of np.clip's call overhead
        clipped = np.minimum(np.maximum(times, 0.0), self.t[-1])
        i = np.minimum(np.maximum(np.searchsorted(self.t, clipped, side="right") - 1, 0), len(self.t) - 2)
        frac = (clipped - self.t[i]) / (self.t[i + 1] - self.t[i])
        speed = self.speed
        v0, v1 = speed[i], speed[i + 1]
        along = frac * (2.0 * v0 + (v1 - v0) * frac) / np.maximum(v0 + v1, 1e-12)  # share of the step covered
        xy = self.xy[i] + along[..., None] * (self.xy[i + 1] - self.xy[i])
        v = self.v[i] + frac[..., None] * (self.v[i + 1] - self.v[i])
        return xy, v

    @functools.cached_property
    def _rows(self) -> tuple[list[float], list[list[float]], list[list[float]], list[float]]:
        """t, xy, v and speed as Python lists, for ``state_at``."""
        return self.t.tolist(), self.xy.tolist(), self.v.tolist(), self.speed.tolist()

    def state_at(self, time: float) -> tuple[np.ndarray, np.ndarray]:
        """Position (2,) and velocity (2,) at ``time`` [s]: ``states_at`` for one time, in plain floats (it runs
        several times a cycle, where numpy's per-call overhead outweighs the arithmetic)."""
        t, xy, v, speed = self._rows
        if len(t) == 1:
            return np.array(xy[0]), np.array(v[0])
        clipped = min(max(float(time), 0.0), t[-1])
        i = min(max(bisect.bisect_right(t, clipped) - 1, 0), len(t) - 2)
        frac = (clipped - t[i]) / (t[i + 1] - t[i])
        v0, v1 = speed[i], speed[i + 1]
        along = frac * (2.0 * v0 + (v1 - v0) * frac) / max(v0 + v1, 1e-12)
        (x0, y0), (x1, y1), (vx0, vy0), (vx1, vy1) = xy[i], xy[i + 1], v[i], v[i + 1]
        return (np.array((x0 + along * (x1 - x0), y0 + along * (y1 - y0))),
                np.array((vx0 + frac * (vx1 - vx0), vy0 + frac * (vy1 - vy0))))

    def min_clearance(self, obstacles: Sequence[Disc]) -> float:
        """Smallest distance from any sample to any obstacle centre minus that obstacle's radius (inf if none)."""
        if not obstacles:
            return math.inf
        table = np.array([(o.x, o.y, o.radius) for o in obstacles], dtype=float)
        diff = self.xy[:, None, :] - table[None, :, :2]
        return float((np.hypot(diff[..., 0], diff[..., 1]) - table[:, 2]).min())


def _chord_params(route: np.ndarray) -> np.ndarray:
    steps = np.diff(route, axis=0)
    return np.concatenate(([0.0], np.cumsum(np.hypot(steps[:, 0], steps[:, 1]))))


def _prepare_route(points: list[Point], movable: list[bool]) -> tuple[list[Point], list[bool]]:
    """Drop points within _SAME_POINT of the previous one (a waypoint wins over a subtarget), make sure there
    are at least four so that a cubic is defined, and add points along segments longer than _MAX_SPAN so that
    the spline follows the route (and its clearances) closely."""
    route, free = [points[0]], [movable[0]]
    last = len(points) - 1
    for i, p, m in zip(range(1, last + 1), points[1:], movable[1:]):
        if math.dist(p, route[-1]) >= _SAME_POINT:
            route.append(p)
            free.append(m)
        elif len(route) > 1 and (free[-1] or i == last):  # the goal, or a waypoint, wins over its neighbour
            route[-1], free[-1] = p, m
    if len(route) == 3:  # the longer segment gets its midpoint
        i = 0 if math.dist(route[0], route[1]) >= math.dist(route[1], route[2]) else 1
        route.insert(i + 1, ((route[i][0] + route[i + 1][0]) / 2.0, (route[i][1] + route[i + 1][1]) / 2.0))
        free.insert(i + 1, True)
    dense, dense_free = [route[0]], [free[0]]
    for (ax, ay), (bx, by), m in zip(route, route[1:], free[1:]):
        pieces = max(int(math.ceil(math.hypot(bx - ax, by - ay) / _MAX_SPAN)), 3 if len(route) == 2 else 1)
        dense += [(ax + (bx - ax) * i / pieces, ay + (by - ay) * i / pieces) for i in range(1, pieces)]
        dense.append((bx, by))
        dense_free += [True] * (pieces - 1) + [m]
    return dense, dense_free


def _fit(route: np.ndarray, direction: Point | None) -> tuple[BSpline, np.ndarray]:
    """Cubic interpolating B-spline through ``route`` by chord length: natural at the end, and at the start
    too unless ``direction`` (a unit vector, matching the unit speed of the chord parameter) is given."""
    u = _chord_params(route)
    natural = [(2, (0.0, 0.0))]
    first = natural if direction is None else [(1, direction)]
    # The knots make_interp_spline would choose for these end conditions (the ends repeated k + 1 times),
    # given: it builds them with np.r_, which costs a third of the fit.
    knots = np.empty(len(u) + 6)
    knots[:3], knots[3:-3], knots[-3:] = u[0], u, u[-1]
    return make_interp_spline(u, route, k=3, t=knots, bc_type=(first, natural), check_finite=False), u


def _corrections(samples: np.ndarray, at: np.ndarray, route: np.ndarray, u: np.ndarray, scene: _Scene,
                 counted: np.ndarray, bounds: Bounds) -> list[tuple[float, Point]]:
    """Corrective via-points (spline parameter, position) for the deepest violation of each counted obstacle's
    clearance and of the bounds: the sample pushed out to the detour radius, or else the straight route there
    (clear of obstacles, inside bounds)."""
    lo = np.array((bounds.x_min, bounds.y_min))
    hi = np.array((bounds.x_max, bounds.y_max))

    def on_route(i: int) -> Point:
        j = min(max(int(np.searchsorted(u, at[i], side="right")) - 1, 0), len(u) - 2)
        frac = (at[i] - u[j]) / (u[j + 1] - u[j])
        x, y = route[j] + frac * (route[j + 1] - route[j])
        return float(x), float(y)

    fixes: list[tuple[float, Point]] = []
    candidates: list[tuple[int, np.ndarray, int]] = []  # (sample, proposed point, obstacle or -1)
    if counted.any():
        rel = samples[:, None, :] - scene.centres[None, :, :]
        dist = np.sqrt(np.einsum("mkj,mkj->mk", rel, rel))
        excess = np.where(counted, scene.clear - dist, -np.inf)
        deepest = excess.argmax(axis=0)
        for j in np.flatnonzero(excess[deepest, np.arange(len(scene))] > _TOLERANCE).tolist():
            i = int(deepest[j])
            away = max(float(dist[i, j]), 1e-9)
            candidates.append((i, scene.centres[j] + rel[i, j] * (scene.detour[j] / away), j))
    outside = (np.maximum(lo - samples, 0.0) + np.maximum(samples - hi, 0.0)).max(axis=1)
    i = int(outside.argmax())
    if outside[i] > _BOUNDS_TOLERANCE:
        inset = np.minimum(0.1, 0.25 * (hi - lo))
        candidates.append((i, np.clip(samples[i], lo + inset, hi - inset), -1))
    if not candidates:
        return fixes
    proposed = np.array([c[1] for c in candidates])
    blocked = scene.inside(proposed) & counted
    strayed = ((proposed < lo) | (proposed > hi)).any(axis=1)
    for (i, p, j), row, out in zip(candidates, blocked.tolist(), strayed.tolist()):
        if j >= 0:
            row[j] = False
        ok = not (out or any(row))
        fixes.append((float(at[i]), (float(p[0]), float(p[1])) if ok else on_route(i)))
    return fixes


def _apply(route: list[Point], movable: list[bool], u: np.ndarray, fixes: list[tuple[float, Point]]) -> bool:
    """Insert the corrective via-points into their spline segments, or move a movable route point that is too
    near instead; True when the route changed."""
    changed = False
    for param, p in sorted(fixes, reverse=True):  # from the end, so that indices stay valid
        j = min(max(int(np.searchsorted(u, param, side="right")) - 1, 0), len(u) - 2)
        near = j if math.dist(route[j], p) <= math.dist(route[j + 1], p) else j + 1
        if math.dist(route[near], p) < _MIN_VIA_GAP:
            if movable[near]:
                route[near] = p
                changed = True
            continue
        route.insert(j + 1, p)
        movable.insert(j + 1, True)
        changed = True
    return changed


_MIN_ALONG = 0.2  # the share of max_accel always left for speeding up and braking on a curve


def _speed_profile(limit: np.ndarray, ds: float, v_start: float, v_end: float, accel: np.ndarray) -> np.ndarray:
    """Speeds at samples ds apart: from v_start, within ``limit``, speeding up and braking by at most ``accel``
    (per sample) along the path, ending at v_end when reachable. A start too fast to brake in time brakes as hard
    as allowed from the start.

    The passes run on w = v^2, which may change by at most 2 accel[i] ds from sample i-1 to i. With R the running
    sum of those steps, the forward pass w[i] = min(w[i], w[i-1] + step[i]) unrolls to R[i] + min over j <= i of
    (w[j] - R[j]), a running minimum; the backward and the braking passes likewise.
    """
    n = len(limit)
    ramp = np.concatenate(([0.0], np.cumsum(2.0 * ds * accel[1:])))
    w = limit * limit
    w[0] = v_start * v_start
    w = ramp + np.minimum.accumulate(w - ramp)  # forward: speed up
    w[-1] = min(w[-1], v_end * v_end)
    w[1:] = np.minimum.accumulate((w + ramp)[:0:-1])[::-1] - ramp[1:]  # backward: brake in time (start fixed)
    w = np.maximum.accumulate(w + ramp) - ramp  # no harder braking than allowed after a too fast start
    return np.sqrt(np.maximum(w, 0.0)[:n])


def _trajectory(t: np.ndarray, s: np.ndarray, xy: np.ndarray, v: np.ndarray, via: tuple[Point, ...]) -> Trajectory:
    for array in (t, s, xy, v):
        array.setflags(write=False)
    return Trajectory(t, s, xy, v, via)


def plan(start: Point, waypoints: Sequence[Point], obstacles: Sequence[Disc], params: PlannerParams,
         bounds: Bounds, start_velocity: Point = (0.0, 0.0), end_speed: float = 0.0) -> Trajectory:
    """Route start -> (subtargets) -> waypoints[0] -> (subtargets) -> ... -> waypoints[-1] (the goal), cubic
    B-spline through it, adjusted to keep clearances and bounds, time-parameterised from |start_velocity|
    (capped at max_speed) to end_speed (capped at max_speed).

    When start_velocity is faster than 0.1 m/s, its direction is the spline's direction at the start, so that
    replanning every cycle from a moving state stays smooth. When every waypoint lies within 1 cm of the start
    (e.g. goal == start), the trajectory is one sample standing still. Waypoints outside the bounds are clamped
    into them; samples are kept inside the bounds (widened to include the start, if the robot is outside).
    Obstacles whose clearance contains the start or a waypoint are not avoided (the robot must leave or reach
    them).
    """
    p0 = _finite_point(start, "start")
    if len(waypoints) == 0:
        raise ValueError("waypoints must not be empty: the last one is the goal")
    points = [bounds.clamp(_finite_point(w, f"waypoints[{i}]")) for i, w in enumerate(waypoints)]
    v0 = _finite_point(start_velocity, "start_velocity")
    if not (math.isfinite(end_speed) and end_speed >= 0.0):
        raise ValueError(f"end_speed must be finite and not negative, got {end_speed}")
    if all(math.dist(p, p0) <= _SAME_POINT for p in points):
        xy = np.array([p0])
        return _trajectory(np.zeros(1), np.zeros(1), xy, np.zeros((1, 2)), (p0,))
    scene = _Scene(obstacles, params)

    # 1. the route; only subtargets and added points may move
    route, movable = [p0], [False]
    budget = params.max_subtargets
    for p in points:
        leg = _leg(route[-1], p, scene, bounds, budget)
        budget -= len(leg)
        route += leg + [p]
        movable += [True] * len(leg) + [False]
    counted = ~scene.inside(np.array([p0] + points)).any(axis=0)  # obstacles not holding a user point
    route, movable = _prepare_route(route, movable)
    if len(route) < 4:  # only within a centimetre steps of the start
        return _trajectory(np.zeros(1), np.zeros(1), np.array([p0]), np.zeros((1, 2)), (p0,))

    # 2-3. fit; correct clearance and bounds violations and refit
    speed0 = math.hypot(*v0)
    direction = (v0[0] / speed0, v0[1] / speed0) if speed0 > _DIRECTION_SPEED else None
    for attempt in range(_MAX_REFITS + 1):
        route_xy = np.array(route)
        spline, u = _fit(route_xy, direction)
        count = max(int(math.ceil(u[-1] / params.sample_step)), 3)
        at = np.arange(count + 1) * (u[-1] / count)
        samples = spline(at)
        if attempt == _MAX_REFITS:
            break
        fixes = _corrections(samples, at, route_xy, u, scene, counted, bounds)
        if not fixes or not _apply(route, movable, u, fixes):
            break

    # 4. samples evenly spaced in arc length, and the speed profile
    steps = np.diff(samples, axis=0)
    s_dense = np.concatenate(([0.0], np.cumsum(np.hypot(steps[:, 0], steps[:, 1]))))
    total = float(s_dense[-1])
    count = max(int(math.ceil(total / params.sample_step)), 1)
    ds = total / count
    s = np.arange(count + 1) * ds
    at = np.interp(s, s_dense, at)
    xy, d1, d2 = spline(at), spline(at, 1), spline(at, 2)
    # minimum/maximum: np.clip's numbers without its call overhead
    xy = np.minimum(np.maximum(xy, (min(bounds.x_min, p0[0]), min(bounds.y_min, p0[1]))),
                    (max(bounds.x_max, p0[0]), max(bounds.y_max, p0[1])))
    norm = np.maximum(np.hypot(d1[:, 0], d1[:, 1]), 1e-9)
    curvature = np.abs(d1[:, 0] * d2[:, 1] - d1[:, 1] * d2[:, 0]) / norm**3
    limit = np.sqrt(params.max_lateral_accel / np.maximum(curvature, 1e-12))
    limit = np.minimum(np.maximum(limit, _MIN_SPEED), params.max_speed)
    # What the curve leaves of max_accel for speeding up and braking (at the speed limit, the most it can take).
    lateral = np.minimum(limit * limit * curvature, params.max_lateral_accel)
    along = np.sqrt(np.maximum(params.max_accel ** 2 - lateral ** 2, (_MIN_ALONG * params.max_accel) ** 2))
    speed = _speed_profile(limit, ds, min(speed0, params.max_speed), min(end_speed, params.max_speed), along)
    t = np.concatenate(([0.0], np.cumsum(2.0 * ds / np.maximum(speed[:-1] + speed[1:], 1e-9))))
    v = d1 * (speed / norm)[:, None]
    return _trajectory(t, s, xy, v, tuple(route))
