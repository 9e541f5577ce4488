"""Online path planning for the omnidirectional robot: subtargets round obstacles, then a cubic B-spline.

Requires: the robot's position and velocity, waypoints ending at the goal, obstacles as discs (other robots,
goal posts) and the bounds the robot centre must stay in, all in one 2-D field frame.
Provides: ``subtargets`` (via-points so that the straight route keeps every obstacle's clearance) and
``plan`` -> ``Trajectory`` (time-stamped positions and velocities along a smooth path that keeps the
clearances and bounds, within the speed, acceleration and curvature limits).
Units SI throughout: m, s, m/s, m/s^2. Pure core: no ROS, safe to call every 30 ms control cycle. The computation
is compiled (``nubot_control._kernels``, C++ with Eigen, built by catkin_make from ``cpp/path_planning.cpp``); this
module holds the planner's parameters, its inputs' types, the ``Trajectory`` it returns and its Python API.

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
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.arrays import FloatArray
from nubot_common.kernels import load_kernels
from nubot_common.params import require_non_negative, require_positive

if TYPE_CHECKING:
    from nubot_control import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("nubot_control")

Point = tuple[float, float]
ACCEL_ROUNDING = 1e-9  # a plan's acceleration may exceed the limit it was made under by this share (rounding)



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


def _disc_table(obstacles: Sequence[Disc] | FloatArray) -> FloatArray:
    """The obstacles as (k, 3) rows (x, y, radius) [m]; a table of such rows is taken as it is (the compiled planner
    checks its rows as Disc does)."""
    if isinstance(obstacles, np.ndarray):
        return obstacles
    return np.array([(o.x, o.y, o.radius) for o in obstacles], dtype=float).reshape(-1, 3)


def keeps_clear(path: FloatArray, ends: Sequence[Point], obstacles: Sequence[tuple[float, float, float]] | FloatArray,
                margin: float, tolerance: float) -> bool:
    """Whether every point of ``path`` ((n, 2) [m]) stays ``margin`` + radius - ``tolerance`` [m] or farther from
    the centre of each obstacle ((x, y, radius) [m]) whose margin + radius holds none of ``ends`` (the robot and its
    waypoints: as the planner does, an obstacle holding one is not avoided). Compiled (``cpp/path_planning.cpp``)."""
    if len(obstacles) == 0:
        return True
    return bool(_kernels.keeps_clear(path, ends, np.asarray(obstacles, dtype=float).reshape(-1, 3), float(margin),
                                     float(tolerance)))


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
    return _kernels.subtargets(start, goal, _disc_table(obstacles), params, bounds)


@dataclass(frozen=True, eq=False)
class Trajectory:
    """Samples of a planned path about sample_step apart in arc length (arrays read-only)."""

    t: FloatArray  # (n,) time from the plan's start [s], t[0] == 0, increasing
    s: FloatArray  # (n,) arc length [m]
    xy: FloatArray  # (n, 2) positions [m]
    v: FloatArray  # (n, 2) velocities [m/s]
    via: tuple[Point, ...]  # the route the spline was fitted through (start, subtargets, waypoints, goal, and
    # the points added along long segments and by the adjustment)

    @property
    def duration(self) -> float:
        return float(self.t[-1])

    @property
    def length(self) -> float:
        return float(self.s[-1])

    def states_at(self, times: FloatArray) -> tuple[FloatArray, FloatArray]:
        """Positions (..., 2) and velocities (..., 2) at the given times; before 0 the start state, after the end
        the end state (standing still when end_speed was 0).

        Between two samples the velocity is interpolated linearly in time (the profile's constant acceleration)
        and the position along the step by the distance covered at that acceleration, so that positions and
        velocities agree even where the samples are far apart in time (starting from rest). Compiled
        (``cpp/trajectory.cpp``)."""
        times = np.asarray(times, dtype=float)
        xy, v = _kernels.trajectory_states(self.t, self.xy, self.v, times.reshape(-1))
        shape = times.shape + (2,)
        return xy.reshape(shape), v.reshape(shape)

    def state_at(self, time: float) -> tuple[FloatArray, FloatArray]:
        """Position (2,) and velocity (2,) at ``time`` [s]: ``states_at`` for one time."""
        xy, v = _kernels.trajectory_states(self.t, self.xy, self.v, np.array((time,), dtype=float))
        return xy[0], v[0]

    def followable(self, until: float, accel: float) -> bool:
        """Whether a robot can follow the trajectory up to the first sample after ``until`` [s]: its velocity
        changes no faster than ``accel`` [m/s^2] (a plan made at that limit reaches it to within rounding, which
        counts as within it). Compiled (``cpp/trajectory.cpp``)."""
        return bool(_kernels.within_accel(self.t, self.v, float(until), float(accel), ACCEL_ROUNDING))

    def min_clearance(self, obstacles: Sequence[Disc]) -> float:
        """Smallest distance from any sample to any obstacle centre minus that obstacle's radius (inf if none)."""
        if not obstacles:
            return math.inf
        table = np.array([(o.x, o.y, o.radius) for o in obstacles], dtype=float)
        diff = self.xy[:, None, :] - table[None, :, :2]
        return float((np.hypot(diff[..., 0], diff[..., 1]) - table[:, 2]).min())


def _trajectory(t: FloatArray, s: FloatArray, xy: FloatArray, v: FloatArray, via: tuple[Point, ...]) -> Trajectory:
    for array in (t, s, xy, v):
        array.setflags(write=False)
    return Trajectory(t, s, xy, v, via)


def plan(start: Point, waypoints: Sequence[Point], obstacles: Sequence[Disc] | FloatArray, params: PlannerParams,
         bounds: Bounds, start_velocity: Point = (0.0, 0.0), end_speed: float = 0.0) -> Trajectory:
    """Route start -> (subtargets) -> waypoints[0] -> (subtargets) -> ... -> waypoints[-1] (the goal), cubic
    B-spline through it, adjusted to keep clearances and bounds, time-parameterised from |start_velocity|
    (capped at max_speed) to end_speed (capped at max_speed).

    When start_velocity is faster than 0.1 m/s, its direction is the spline's direction at the start, so that
    replanning every cycle from a moving state stays smooth. When every waypoint lies within 1 cm of the start
    (e.g. goal == start), the trajectory is one sample standing still. Waypoints outside the bounds are clamped
    into them; samples are kept inside the bounds (widened to include the start, if the robot is outside).
    Obstacles whose clearance contains the start or a waypoint are not avoided (the robot must leave or reach
    them). ``obstacles``: Discs, or their (k, 3) table of (x, y, radius) rows.
    """
    t, s, xy, v, via = _kernels.plan(start, waypoints, _disc_table(obstacles), params, bounds, start_velocity,
                                     float(end_speed))
    return _trajectory(t, s, xy, v, tuple(via))
