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
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_common.kernels import load_kernels
from nubot_common.world_description import WorldDescription
from nubot_control.areas import Rect, stay_out
from nubot_control.mpc import LaguerreMpc, MpcParams
from nubot_control.params import MotionParams
from nubot_control.path_planning import Bounds, PlannerParams, Trajectory, keeps_clear, plan

if TYPE_CHECKING:
    from nubot_control import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("nubot_control")

_MAX_DETOURS = 3
# A plan whose remaining path enters an obstacle's clearance by more than this is replaced [m]; the planner
# itself leaves violations of a few millimetres (kTolerance in cpp/path_planning.cpp), which must not force a replan.
_INTRUSION_TOLERANCE = 0.01


def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> tuple[float, float]:
    """Distance from P to segment AB, and the position (0..1) of the closest point along AB."""
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 < 1e-12 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2))
    return math.hypot(ax + t * dx - px, ay + t * dy - py), t


def sub_target(start: tuple[float, float], goal: tuple[float, float], obstacles: Sequence[tuple[float, ...]],
               clearance: float) -> tuple[float, float]:
    """The first point to head for on the way from ``start`` to ``goal`` around ``obstacles``.

    An obstacle is (x, y) kept ``clearance`` away, or (x, y, own_clearance).
    """
    target = goal
    for _ in range(_MAX_DETOURS):
        blocking = None
        for obstacle in obstacles:
            ox, oy = obstacle[0], obstacle[1]
            keep = obstacle[2] if len(obstacle) > 2 else clearance
            if math.hypot(ox - start[0], oy - start[1]) < 1e-6:
                continue
            distance, t = _segment_distance(ox, oy, start[0], start[1], target[0], target[1])
            if distance < keep and 0.0 < t < 1.0:
                along = t * math.hypot(target[0] - start[0], target[1] - start[1])
                if blocking is None or along < blocking[0]:
                    blocking = (along, ox, oy, keep)
        if blocking is None:
            return target
        _, ox, oy, keep = blocking
        dx, dy = target[0] - start[0], target[1] - start[1]
        norm = math.hypot(dx, dy)
        nx, ny = -dy / norm, dx / norm  # left of the path
        side = 1.0 if (start[0] - ox) * nx + (start[1] - oy) * ny >= 0.0 else -1.0
        offset = keep * 1.2
        target = (ox + side * nx * offset, oy + side * ny * offset)
    return target


def keep_clear(position: tuple[float, float], velocity: tuple[float, float], robots: Sequence[tuple[float, ...]],
               min_distance: float, brake: float, latency: float, in_the_way: float) -> tuple[float, float]:
    """``velocity`` [m/s] without what would bring the robot at ``position`` within ``min_distance`` [m] (centre to
    centre) of a robot in ``robots`` (x, y): for each robot that the straight line of the velocity would pass closer
    than ``min_distance`` plus ``in_the_way`` [m] (a margin: the other may move into it), the speed towards it is at
    most the speed from which it stops in the room left, braking at ``brake`` [m/s^2] after ``latency`` [s]; in that
    margin less of the limit applies the wider the line passes. A robot the line passes wide of, or one behind, is
    left alone; sideways the velocity is kept. Two robots coming at each other so both brake, at twice ``brake``
    together."""
    vx, vy = velocity
    bt = brake * latency
    for _ in range(3):  # limiting towards one robot can add speed towards another: settle in a few rounds
        changed = False
        speed = math.hypot(vx, vy)
        if speed < 1e-9:
            break
        for robot in robots:
            dx, dy = robot[0] - position[0], robot[1] - position[1]
            distance = math.hypot(dx, dy)
            if distance < 1e-6:
                continue
            towards = (vx * dx + vy * dy) / distance
            wide = abs(vx * dy - vy * dx) / speed - min_distance  # how far the line passes outside min_distance
            if towards <= 0.0 or wide >= in_the_way:
                continue  # going away, or the line passes wide of it (the other may move into it: a margin)
            room = max(distance - min_distance, 0.0)
            allowed = -bt + math.sqrt(bt * bt + 2.0 * brake * room)  # v * latency + v^2 / (2 brake) = room
            if wide > 0.0:  # in the margin: less of the limit the wider the line passes, so the command stays smooth
                allowed += (towards - allowed) * wide / in_the_way if towards > allowed else 0.0
            if towards > allowed + 1e-9:
                cut = towards - allowed
                vx, vy = vx - cut * dx / distance, vy - cut * dy / distance
                changed = True
        if not changed:
            break
    return vx, vy


def obstacle_table(position: tuple[float, float], obstacles: Sequence[tuple[float, ...]], goals: np.ndarray,
                   robot_radius: float, clearance: float, planning_range: float) -> np.ndarray:
    """The planner's obstacles this cycle as (k, 3) rows (x, y, radius) [m]: the ``goals``' rows, then each obstacle
    (a robot's (x, y): the robot radius; an (x, y, keep) whose centre must stay ``keep`` from the robot's: the disc
    that leaves that, max(0, keep - robot_radius - clearance)), only the rows within ``planning_range`` of
    ``position``. A NaN or infinite obstacle raises ValueError naming the field. Compiled (``cpp/motion.cpp``)."""
    return _kernels.obstacle_table(float(position[0]), float(position[1]), goals, obstacles, float(robot_radius),
                                   float(clearance), float(planning_range))


def dribble_scale(bx: float, by: float, p: MotionParams) -> float:
    """The factor (at most 1) that brings the body velocity (bx ahead, by left [m/s]) within what the ball handler
    keeps: ``dribble_speed`` forwards, ``dribble_back_speed`` backwards, ``dribble_side_speed`` sideways."""
    scale = 1.0
    if bx > p.dribble_speed:
        scale = p.dribble_speed / bx
    elif bx < -p.dribble_back_speed:
        scale = p.dribble_back_speed / -bx
    if abs(by) > p.dribble_side_speed:
        scale = min(scale, p.dribble_side_speed / abs(by))
    return scale


class MotionController:
    """Turns target poses into body-frame velocity commands, one control cycle at a time."""

    def __init__(self, params: MotionParams, world: WorldDescription, dt: float = 1.0 / 33.0):
        self.params = params
        field = self.field = world.field
        self.robot_radius = world.robot.radius  # [m]
        self.velocity = (0.0, 0.0)  # last commanded velocity, team frame [m/s]
        self.w = 0.0
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
        self.trajectory: Trajectory | None = None  # the plan being tracked (mpc), its time 0 is the last cycle
        self.reference: tuple[tuple[float, float], tuple[float, float]] | None = None  # (position, velocity) now
        self.compute_time = 0.0  # wall time of the last cycle's planning and tracking [s]
        self.position: tuple[float, float] | None = None  # the robot at the last cycle, team frame [m]; None: no plan
        self._given: list[tuple[float, float]] = []  # the route asked for last cycle
        self._waypoints: list[tuple[float, float]] = []  # what remains of it
        self._plan_goals: list[tuple[float, float]] = []  # the route asked for when the plan was made
        self._plan_limits = (0.0, 0.0)  # the speed [m/s] and acceleration [m/s^2] limits it was made under
        self._plan_age = 0.0  # time since the plan was made (its time 0) [s]
        self._plan_keepable = False  # the robot can follow the plan (see _within_accel)
        self._horizon_times = (np.arange(self.mpc.params.horizon + 1) * self.mpc.params.dt
                               if self.mpc is not None else np.zeros(0))  # the MPC's steps [s]

    def reset(self) -> None:
        self.velocity, self.w = (0.0, 0.0), 0.0
        self.trajectory, self.reference, self._given, self._waypoints = None, None, [], []
        self.position = None
        self._plan_goals, self._plan_limits, self._plan_age, self._plan_keepable = [], (0.0, 0.0), 0.0, False

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
        the mpc tracker plans anew afterwards.
        """
        started = time.perf_counter()
        p = self.params
        self.position = (me.x, me.y)
        limit = min(p.max_speed, speed_limit or p.max_speed, p.dribble_speed if holding else math.inf)
        accel = p.dribble_accel if holding else p.max_accel
        goals = [self.bounds.clamp(w) for w in waypoints]
        if urgent:
            self.trajectory, self._plan_keepable = None, False
        if self.mpc is not None and not urgent:
            vx, vy = self._track(me, goals, obstacles, dt, limit, accel)
        else:
            if goals != self._given:  # a new route; else go on with what remains of it
                self._given, self._waypoints = goals, list(goals)
            while len(self._waypoints) > 1 and \
                    math.hypot(self._waypoints[0][0] - me.x, self._waypoints[0][1] - me.y) < 0.3:
                self._waypoints.pop(0)
            vx, vy = self._baseline(me, self._waypoints[0], obstacles, dt, limit, accel)
        if no_go:
            vx, vy = stay_out((me.x, me.y), (vx, vy), no_go, p.contact_brake, p.contact_latency)
        if p.contact_margin > 0.0:
            robots = [o for o in obstacles if len(o) == 2]
            # A line that keeps the planner's clearance is left alone: the guard does not bend a plan that avoids
            # the robots, it stops what drives into one.
            vx, vy = keep_clear((me.x, me.y), (vx, vy), robots, 2.0 * self.robot_radius + p.contact_margin,
                                p.contact_brake, p.contact_latency, max(p.clearance - p.contact_margin, 0.0))
        bx, by = rotate(vx, vy, -me.theta)
        if holding:
            scale = dribble_scale(bx, by, p)
            bx, by, vx, vy = bx * scale, by * scale, vx * scale, vy * scale
        self.velocity = (vx, vy)
        err = wrap_angle(heading - me.theta)
        turn = p.dribble_rot_speed if holding else p.max_rot_speed
        w_want = max(-turn, min(turn, p.heading_gain * err))
        self.w += max(-p.max_rot_accel * dt, min(p.max_rot_accel * dt, w_want - self.w))
        self.w = max(-turn, min(turn, self.w))
        self.compute_time = time.perf_counter() - started
        return bx, by, self.w

    @property
    def plan_age(self) -> float:
        """Time since the plan being tracked was made: the robot is at ``trajectory``'s time ``plan_age`` [s]."""
        return self._plan_age

    @property
    def waypoints(self) -> tuple[tuple[float, float], ...]:
        """What remains of the route being followed, the goal last (team frame [m]; empty: none)."""
        return tuple(self._waypoints)

    # --- mpc: replan when the plan no longer holds, then track ---------------------------------
    def _obstacle_table(self, me: Pose2D, obstacles: Sequence[tuple[float, ...]]) -> np.ndarray:
        """The goals (posts and nets) and obstacles within planning_range as (x, y, radius) rows [m], the goals
        first (``obstacle_table``)."""
        p = self.params
        return obstacle_table((me.x, me.y), obstacles, self.goal_table, self.robot_radius, p.clearance,
                              p.planning_range)

    def _plan_holds(self, me: Pose2D, goals: list[tuple[float, float]], table: np.ndarray,
                    limits: tuple[float, float]) -> bool:
        """Whether the plan being tracked may be kept this cycle (see ``MotionParams.keep_plan_*``)."""
        p, trajectory = self.params, self.trajectory
        if (trajectory is None or not self._plan_keepable or self._plan_age >= p.keep_plan_time
                or limits != self._plan_limits):
            return False
        if len(goals) != len(self._plan_goals):
            return False
        for (gx, gy), (hx, hy) in zip(goals, self._plan_goals):
            shift = p.keep_plan_goal_shift + p.keep_plan_goal_share * math.hypot(gx - me.x, gy - me.y)
            if math.hypot(gx - hx, gy - hy) > shift:
                return False
        ref, _ = trajectory.state_at(self._plan_age)
        if math.hypot(float(ref[0]) - me.x, float(ref[1]) - me.y) > p.keep_plan_deviation:
            return False
        if len(table) == 0:
            return True
        first = max(int(np.searchsorted(trajectory.t, self._plan_age, side="right")) - 1, 0)
        return keeps_clear(trajectory.xy[first:], [(me.x, me.y), *goals], table, self.robot_radius + p.clearance,
                           _INTRUSION_TOLERANCE)

    def _track(self, me: Pose2D, goals: list[tuple[float, float]], obstacles: Sequence[tuple[float, ...]],
               dt: float, limit: float, accel: float) -> tuple[float, float]:
        self._plan_age += dt
        table = self._obstacle_table(me, obstacles)
        if self._plan_holds(me, goals, table, (limit, accel)):
            assert self.trajectory is not None  # a plan that holds exists
            ref, ref_v = self.trajectory.state_at(self._plan_age)
            start, start_velocity = (float(ref[0]), float(ref[1])), (float(ref_v[0]), float(ref_v[1]))
            self._given, self._waypoints = goals, self._ahead(start, start_velocity, self._waypoints[:-1]) + [goals[-1]]
        else:
            self._replan(me, goals, table, limit, accel)
        mpc = self.mpc
        assert mpc is not None and self.trajectory is not None  # _track runs only with the mpc tracker
        horizon = mpc.params.horizon
        ref_positions, ref_velocities = self.trajectory.states_at(self._plan_age + self._horizon_times)
        self.reference = ((float(ref_positions[0, 0]), float(ref_positions[0, 1])),
                          (float(ref_velocities[0, 0]), float(ref_velocities[0, 1])))
        u = mpc.command(np.array([me.x, me.y]), np.array(self.velocity), ref_positions,
                        ref_velocities[:horizon], max_speed=min(limit, mpc.params.max_speed),
                        max_accel=min(accel, mpc.params.max_accel))
        return float(u[0]), float(u[1])

    def _replan(self, me: Pose2D, goals: list[tuple[float, float]], table: np.ndarray,
                limit: float, accel: float) -> None:
        """A new plan, made now: from where the last plan has the robot when it is on track, else from the robot."""
        p = self.params
        given, start, start_velocity = goals, (me.x, me.y), self.velocity
        if self.trajectory is not None and self._given and math.dist(self._given[-1], goals[-1]) < p.replan_tolerance:
            ref, ref_v = self.trajectory.state_at(self._plan_age)  # where the last plan has the robot now
            if math.dist(ref, (me.x, me.y)) < p.replan_tolerance:  # on track: replan from there, smoothly
                start, start_velocity = (float(ref[0]), float(ref[1])), (float(ref_v[0]), float(ref_v[1]))
            if len(goals) == len(self._given):  # the same route, on track or not: the waypoints still ahead
                goals = self._ahead(start, start_velocity, self._waypoints[:-1]) + [goals[-1]]
        self._given, self._waypoints = given, goals
        planner = PlannerParams(robot_radius=self.robot_radius, safety_margin=p.clearance,
                                max_speed=limit * p.plan_share, max_accel=accel * p.plan_share,
                                max_lateral_accel=p.max_lateral_accel * p.plan_share)
        self.trajectory = plan(start, goals, table, planner, self.bounds, start_velocity=start_velocity)
        self._plan_goals, self._plan_limits, self._plan_age = given, (limit, accel), 0.0
        self._plan_keepable = self._within_accel(self.trajectory, accel)

    def _within_accel(self, trajectory: Trajectory, accel: float) -> bool:
        """Whether the robot can follow the plan for as long as it may be kept: its acceleration [m/s^2] stays
        within ``accel``. A plan from a fast start can turn harder than that at first (its speed profile cannot
        brake the start); replanned every cycle, it is bent into one the robot can follow."""
        return trajectory.followable(self.params.keep_plan_time, accel)

    @staticmethod
    def _ahead(start: tuple[float, float], velocity: tuple[float, float],
               waypoints: list[tuple[float, float]]) -> list[tuple[float, float]]:
        """The waypoints not yet passed from ``start`` moving at ``velocity``: a waypoint is passed when
        it is within 10 cm, or within 1 m and behind."""
        remaining = list(waypoints)
        while remaining:
            gx, gy = remaining[0]
            close = math.hypot(gx - start[0], gy - start[1])
            behind = (gx - start[0]) * velocity[0] + (gy - start[1]) * velocity[1] < 0.0
            if not (close < 0.1 or (behind and close < 1.0)):
                break
            remaining.pop(0)
        return remaining

    # --- baseline ----------------------------------------------------------------------------
    def _baseline(self, me: Pose2D, goal: tuple[float, float], obstacles: Sequence[tuple[float, ...]], dt: float,
                  limit: float, accel: float) -> tuple[float, float]:
        p = self.params
        clearance = 2.0 * self.robot_radius + p.clearance
        near = [o for o in obstacles if math.hypot(o[0] - me.x, o[1] - me.y) < 4.0]
        aim = sub_target((me.x, me.y), goal, near, clearance)
        dx, dy = aim[0] - me.x, aim[1] - me.y
        dist_goal = math.hypot(goal[0] - me.x, goal[1] - me.y)
        dist = math.hypot(dx, dy)
        speed = min(limit, math.sqrt(2.0 * accel * dist_goal), p.position_gain * dist_goal)
        want = (dx / dist * speed, dy / dist * speed) if dist > 1e-3 else (0.0, 0.0)
        for obstacle in near:  # push away from anything already too close
            ox, oy = obstacle[0], obstacle[1]
            keep = obstacle[2] if len(obstacle) > 2 else clearance
            gap = math.hypot(me.x - ox, me.y - oy)
            if 1e-6 < gap < keep:
                push = (keep - gap) * 3.0
                want = (want[0] + (me.x - ox) / gap * push, want[1] + (me.y - oy) / gap * push)
        dvx, dvy = want[0] - self.velocity[0], want[1] - self.velocity[1]
        dv = math.hypot(dvx, dvy)
        step = accel * dt
        if dv > step:
            dvx, dvy = dvx / dv * step, dvy / dv * step
        vx, vy = self.velocity[0] + dvx, self.velocity[1] + dvy
        v = math.hypot(vx, vy)
        if v > limit:
            vx, vy = vx / v * limit, vy / v * limit
        self.reference = ((goal[0], goal[1]), (0.0, 0.0))
        return vx, vy
