"""The motion layer: every behaviour's target pose becomes a body-frame velocity command here.

Requires: own pose, a target pose (or waypoints), obstacles (team frame, m), the cycle time.
Provides: ``MotionController.command`` / ``follow`` -> body-frame (Vx, Vy, w) for
``nubot_common/VelCmd``, ``MotionController.reference`` (where the robot should be now) and the plan
being followed (``trajectory``, ``plan_age``, ``waypoints``, ``position``: what ``planned_path`` draws).
Two trackers, chosen by ``MotionParams.tracker``:

- ``mpc``: the path is planned (``path_planning``: subtargets around the obstacles, the goal
  posts and inside the field limits, a cubic B-spline through them, time-parameterised under the
  speed, acceleration and curvature limits) and tracked by the Laguerre-parameterised MPC
  (``mpc.LaguerreMpc``), whose command keeps the velocity and acceleration limits. The plan is
  kept while it holds (``MotionParams.keep_plan_*``: one the robot can follow, the robot near its
  reference, the waypoints where they were, the same limits, no obstacle inside the clearance of
  the path ahead, not too old); else it is replanned from where the robot should be now (from the
  robot when far off);
- ``baseline``: heads for the first sub-target around the obstacles at a speed limited by the
  distance to go and by an acceleration limit (the tracker team play started with).

A robot holding the ball moves under the tighter ``dribble_speed`` and ``dribble_accel``, and its
command is scaled down to what the ball handler keeps (forwards ``dribble_speed``, backwards
``dribble_back_speed``, sideways ``dribble_side_speed``, turning ``dribble_rot_speed``). The
heading is a rate-limited proportional loop in both. An obstacle is (x, y), a robot, or
(x, y, clearance): keep the centre that far away. After either tracker the contact guard
(``keep_clear``) takes out of the command what would bring the robot into contact with another
robot: the speed towards each is at most what lets it stop ``contact_margin`` short of that robot's
hull, so robots press and block but never drive into each other; a velocity whose line keeps the planner's
``clearance`` from a robot is left alone. Before it, the areas the rules keep the robot out of (``no_go``) are
walls it does not cross (``areas.stay_out``).

The cycle is compiled (``nubot_control._kernels.MotionCore``, C++ with Eigen, from ``cpp/motion.cpp``: both trackers,
keeping or making the plan, the guards, the ball handler's limits and the heading loop); this module holds its Python
API, and ``trajectory`` is made into a ``Trajectory`` only when read.
"""

from __future__ import annotations

import time
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.arrays import FloatArray
from nubot_common.geometry import Pose2D
from nubot_common.kernels import load_kernels
from nubot_common.world_description import WorldDescription
from nubot_control.areas import Rect
from nubot_control.mpc import LaguerreMpc, MpcParams
from nubot_control.params import MotionParams
from nubot_control.path_planning import ACCEL_ROUNDING, Bounds, PlannerParams, Trajectory, _trajectory

if TYPE_CHECKING:
    from nubot_control import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("nubot_control")

# A plan whose remaining path enters an obstacle's clearance by more than this is replaced [m]; the planner
# itself leaves violations of a few millimetres (kTolerance in cpp/path_planning.cpp), which must not force a replan.
_INTRUSION_TOLERANCE = 0.01


def sub_target(start: tuple[float, float], goal: tuple[float, float], obstacles: Sequence[tuple[float, ...]],
               clearance: float) -> tuple[float, float]:
    """The first point to head for on the way from ``start`` to ``goal`` around ``obstacles`` (the baseline's).

    An obstacle is (x, y) kept ``clearance`` away, or (x, y, own_clearance). The nearest one the straight way passes
    within its clearance gets a point beside it, 1.2 clearances from its centre on the side the robot is, and the way
    to that point is checked again, at most three times. Compiled (``cpp/motion.cpp``)."""
    return _kernels.sub_target(start, goal, obstacles, float(clearance))


def keep_clear(position: tuple[float, float], velocity: tuple[float, float], robots: Sequence[tuple[float, ...]],
               min_distance: float, brake: float, latency: float, in_the_way: float) -> tuple[float, float]:
    """``velocity`` [m/s] without what would bring the robot at ``position`` within ``min_distance`` [m] (centre to
    centre) of a robot in ``robots`` (x, y): for each robot that the straight line of the velocity would pass closer
    than ``min_distance`` plus ``in_the_way`` [m] (a margin: the other may move into it), the speed towards it is at
    most the speed from which it stops in the room left, braking at ``brake`` [m/s^2] after ``latency`` [s]; in that
    margin less of the limit applies the wider the line passes. A robot the line passes wide of, or one behind, is
    left alone; sideways the velocity is kept. Two robots coming at each other so both brake, at twice ``brake``
    together. Compiled (``cpp/motion.cpp``)."""
    return _kernels.keep_clear(position, velocity, robots, float(min_distance), float(brake), float(latency),
                               float(in_the_way))


def obstacle_table(position: tuple[float, float], obstacles: Sequence[tuple[float, ...]], goals: FloatArray,
                   robot_radius: float, clearance: float, planning_range: float) -> FloatArray:
    """The planner's obstacles this cycle as (k, 3) rows (x, y, radius) [m]: the ``goals``' rows, then each obstacle
    (a robot's (x, y): the robot radius; an (x, y, keep) whose centre must stay ``keep`` from the robot's: the disc
    that leaves that, max(0, keep - robot_radius - clearance)), only the rows within ``planning_range`` of
    ``position``. A NaN or infinite obstacle raises ValueError naming the field. Compiled (``cpp/motion.cpp``)."""
    return _kernels.obstacle_table(float(position[0]), float(position[1]), goals, obstacles, float(robot_radius),
                                   float(clearance), float(planning_range))


def dribble_scale(bx: float, by: float, p: MotionParams) -> float:
    """The factor (at most 1) that brings the body velocity (bx ahead, by left [m/s]) within what the ball handler
    keeps: ``dribble_speed`` forwards, ``dribble_back_speed`` backwards, ``dribble_side_speed`` sideways."""
    return _kernels.dribble_scale(float(bx), float(by), p)


class MotionController:
    """Turns target poses into body-frame velocity commands, one control cycle at a time."""

    def __init__(self, params: MotionParams, world: WorldDescription, dt: float = 1.0 / 33.0):
        self.params = params
        field = self.field = world.field
        self.robot_radius = world.robot.radius  # [m]
        margin = field.border - self.robot_radius
        self.bounds = Bounds(-field.half_length - margin, field.half_length + margin,
                             -field.half_width - margin, field.half_width + margin)
        # The goals as obstacles: posts and nets, points closer than a robot can pass between (a robot beside or
        # behind a goal must go round it, not plan through its side net)
        self.goal_table = np.array([(x, y, field.post_radius) for side in (1, -1)
                                    for x, y in field.goal_frame(side, spacing=self.robot_radius)]).reshape(-1, 3)
        self.goal_table.setflags(write=False)  # (x, y, radius) rows [m]
        self.mpc = LaguerreMpc(MpcParams(dt=dt, max_speed=params.max_speed, max_accel=params.max_accel)) \
            if params.tracker == "mpc" else None
        self.compute_time = 0.0  # wall time of the last cycle's planning and tracking [s]
        self.position: tuple[float, float] | None = None  # the robot at the last cycle, team frame [m]; None: no plan
        planner = PlannerParams(robot_radius=self.robot_radius, safety_margin=params.clearance)
        self._core = _kernels.MotionCore(params, planner, self.robot_radius, self.bounds, self.goal_table, self.mpc,
                                         ACCEL_ROUNDING, _INTRUSION_TOLERANCE)
        self._trajectory: tuple[int, Trajectory] | None = None  # the plan last read, by the core's plan count

    def reset(self) -> None:
        self._core.reset()
        self.position = None

    @property
    def velocity(self) -> tuple[float, float]:
        """The last commanded velocity, team frame [m/s]."""
        return self._core.velocity

    @property
    def w(self) -> float:
        """The last commanded turn rate [rad/s]."""
        return self._core.w

    @property
    def reference(self) -> tuple[tuple[float, float], tuple[float, float]] | None:
        """Where the robot should be now and how fast ((x, y), (vx, vy)), team frame; None before the first cycle."""
        return self._core.reference

    @property
    def trajectory(self) -> Trajectory | None:
        """The plan being tracked (mpc), its time 0 is when it was made; None: none (baseline, urgent, reset)."""
        core = self._core
        if not core.has_plan:
            return None
        count = core.plan_count
        if self._trajectory is None or self._trajectory[0] != count:
            t, s, xy, v, via = core.plan()
            self._trajectory = (count, _trajectory(t, s, xy, v, tuple(via)))
        return self._trajectory[1]

    def command(self, me: Pose2D, target: Pose2D, obstacles: Sequence[tuple[float, ...]], dt: float,
                speed_limit: float | None = None, holding: bool = False,
                no_go: Sequence[Rect] = (), urgent: bool = False) -> tuple[float, float, float]:
        """One cycle's body-frame command towards ``target`` (position and heading)."""
        return self.follow(me, [(target.x, target.y)], target.theta, obstacles, dt, speed_limit, holding, no_go,
                           urgent)

    def follow(self, me: Pose2D, waypoints: list[tuple[float, float]], heading: float,
               obstacles: Sequence[tuple[float, ...]], dt: float, speed_limit: float | None = None,
               holding: bool = False, no_go: Sequence[Rect] = (), urgent: bool = False) -> tuple[float, float, float]:
        """One cycle's body-frame command along ``waypoints`` (the last is the goal), ending facing ``heading``;
        ``no_go``: rectangles (team frame) it must not enter (``areas.no_go``: the areas the rules keep it out of).

        The mpc tracker passes through the waypoints in order (a waypoint is dropped once passed);
        the baseline heads for the first one and drops it within 0.3 m. ``urgent`` (the goalie stepping into a
        shot) goes the baseline's way with either tracker: no plan to make or keep, the full acceleration at once;
        the mpc tracker plans anew afterwards. A speed limit of None (or 0) is the robot's own. Input that is not
        finite, or no waypoint, raises ValueError naming it.
        """
        started = time.perf_counter()
        self.position = (me.x, me.y)
        command = self._core.follow(me.x, me.y, me.theta, waypoints, heading, obstacles, dt, speed_limit, holding,
                                    no_go, urgent)
        self.compute_time = time.perf_counter() - started
        return command

    @property
    def plan_age(self) -> float:
        """Time since the plan being tracked was made: the robot is at ``trajectory``'s time ``plan_age`` [s]."""
        return self._core.plan_age

    @property
    def waypoints(self) -> tuple[tuple[float, float], ...]:
        """What remains of the route being followed, the goal last (team frame [m]; empty: none)."""
        return self._core.waypoints
