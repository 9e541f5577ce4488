"""Go-to motion with speed/acceleration limits and obstacle avoidance (the baseline tracker).

Requires: own pose and last commanded velocity, a target pose, obstacles (team frame, m).
Provides: ``MotionController.command`` -> body-frame (Vx, Vy, w) for ``nubot_common/VelCmd``.
Obstacles are avoided with sub-targets: when the straight line to the target passes
within the clearance of an obstacle, the robot heads for a point beside that obstacle
instead, on the side nearer the line; this repeats for the next obstacle on the way.
"""

from __future__ import annotations

import math

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_control.params import MotionParams

_MAX_DETOURS = 3


def _segment_distance(px: float, py: float, ax: float, ay: float, bx: float, by: float) -> tuple[float, float]:
    """Distance from P to segment AB, and the position (0..1) of the closest point along AB."""
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    t = 0.0 if length2 < 1e-12 else max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / length2))
    return math.hypot(ax + t * dx - px, ay + t * dy - py), t


def sub_target(start: tuple[float, float], goal: tuple[float, float], obstacles: list[tuple[float, ...]],
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


class MotionController:
    """Turns target poses into body-frame velocity commands, one control cycle at a time."""

    def __init__(self, params: MotionParams, field: FieldGeometry):
        self.params = params
        self.field = field
        self.velocity = (0.0, 0.0)  # last commanded velocity, team frame [m/s]
        self.w = 0.0

    def reset(self) -> None:
        self.velocity, self.w = (0.0, 0.0), 0.0

    def command(self, me: Pose2D, target: Pose2D, obstacles: list[tuple[float, ...]], dt: float,
                speed_limit: float | None = None) -> tuple[float, float, float]:
        """One cycle's body-frame command; an obstacle is (x, y) (a robot) or (x, y, clearance) [m]."""
        p = self.params
        limit = min(p.max_speed, speed_limit or p.max_speed)
        margin = self.field.border - p.robot_radius
        goal = (max(-self.field.half_length - margin, min(self.field.half_length + margin, target.x)),
                max(-self.field.half_width - margin, min(self.field.half_width + margin, target.y)))
        clearance = 2.0 * p.robot_radius + p.clearance
        near = [o for o in obstacles if math.hypot(o[0] - me.x, o[1] - me.y) < 4.0]
        aim = sub_target((me.x, me.y), goal, near, clearance)
        dx, dy = aim[0] - me.x, aim[1] - me.y
        dist_goal = math.hypot(goal[0] - me.x, goal[1] - me.y)
        dist = math.hypot(dx, dy)
        speed = min(limit, math.sqrt(2.0 * p.max_accel * dist_goal), p.position_gain * dist_goal)
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
        step = p.max_accel * dt
        if dv > step:
            dvx, dvy = dvx / dv * step, dvy / dv * step
        vx, vy = self.velocity[0] + dvx, self.velocity[1] + dvy
        v = math.hypot(vx, vy)
        if v > limit:
            vx, vy = vx / v * limit, vy / v * limit
        self.velocity = (vx, vy)
        err = wrap_angle(target.theta - me.theta)
        w_want = max(-p.max_rot_speed, min(p.max_rot_speed, p.heading_gain * err))
        self.w += max(-p.max_rot_accel * dt, min(p.max_rot_accel * dt, w_want - self.w))
        bx, by = rotate(vx, vy, -me.theta)
        return bx, by, self.w
