"""Observation vectors in a robot's team frame (own goal at -x, attacked goal at +x), from ground truth.

Requires: the simulator's world (``RobotState``, ``BallState``: world frame, SI units), the field
(``FieldGeometry`` [m]) and ``PluginParams`` (speed limits). Provides: ``Layout`` (the names of a vector's
entries and a float32 ``Box`` with bounds from the field and the limits; ``vector`` clips into it),
``OWN_NAMES`` / ``own_block`` (the robot itself and the ball as it sees them), ``OTHER_NAMES`` /
``other_block`` (another robot).

``own_block`` (12 entries): x, y [m]; cos_theta, sin_theta of the heading; vx, vy [m/s] and w [rad/s]
(velocity over the ground in the team frame, turn rate); ball_dx, ball_dy [m] (ball centre minus robot
centre, team frame); ball_vx, ball_vy [m/s]; holding (1 if this robot holds the ball, else 0).
``other_block`` (4 entries): x, y [m], vx, vy [m/s] in the team frame.
The values are the simulator's true state (no sensor noise; the robots' own world models see noisy vision).
"""

from __future__ import annotations

import math
from collections.abc import Sequence

import numpy as np
from gymnasium import spaces

from nubot_common.field import FieldGeometry
from nubot_common.team_frame import TeamFrame
from sim_visual.params import MAX_BALL_SPEED, PluginParams
from sim_visual.world import BallState, RobotState

OWN_NAMES = ("x", "y", "cos_theta", "sin_theta", "vx", "vy", "w", "ball_dx", "ball_dy", "ball_vx", "ball_vy",
             "holding")
OTHER_NAMES = ("x", "y", "vx", "vy")
_MARGIN = 0.5  # bounds beyond the arena [m]
_ROBOT_SPEED_FACTOR = 1.5  # contacts may push a robot faster than its command for a step
MAX_GOAL_DIFFERENCE = 20.0  # goal differences are clipped to this (bound of the Box)


def _bound(name: str, field: FieldGeometry, plugin: PluginParams) -> float:
    """The symmetric bound of the entry ``name`` (its last word says its kind)."""
    x = field.half_length + max(field.border, field.goal_depth) + _MARGIN  # the ball may lie inside a goal
    y = field.half_width + field.border + _MARGIN
    kind = name.rsplit("_", 1)[-1]
    table = {
        "x": x, "y": y, "dx": 2.0 * x, "dy": 2.0 * y,
        "vx": _ROBOT_SPEED_FACTOR * plugin.max_linear_speed, "vy": _ROBOT_SPEED_FACTOR * plugin.max_linear_speed,
        "w": _ROBOT_SPEED_FACTOR * plugin.max_angular_speed, "theta": 1.0, "difference": MAX_GOAL_DIFFERENCE,
    }
    if name.startswith("ball_v"):
        return MAX_BALL_SPEED
    return table.get(kind, 1.0)  # flags and fractions lie in [0, 1], restarts in [-1, 1]


_NON_NEGATIVE = ("holding", "running", "left")  # entries (by last word) that lie in [0, 1]


class Layout:
    """The entries of an observation vector and its ``Box``."""

    def __init__(self, names: Sequence[str], field: FieldGeometry, plugin: PluginParams):
        self.names = tuple(names)
        high = np.array([_bound(n, field, plugin) for n in self.names], dtype=np.float32)
        low = np.array([0.0 if n.rsplit("_", 1)[-1] in _NON_NEGATIVE else -h for n, h in zip(self.names, high)],
                       dtype=np.float32)
        self.space = spaces.Box(low=low, high=high, dtype=np.float32)

    def index(self, name: str) -> int:
        return self.names.index(name)

    def vector(self, values: Sequence[float]) -> np.ndarray:
        """``values`` as float32, clipped into the space (a contact can push a speed past its bound for a step)."""
        if len(values) != len(self.names):
            raise ValueError(f"{len(values)} values for {len(self.names)} entries")
        out = np.asarray(values, dtype=np.float32)
        return np.clip(out, self.space.low, self.space.high)


def other_names(prefix: str) -> list[str]:
    return [f"{prefix}_{n}" for n in OTHER_NAMES]


def own_block(frame: TeamFrame, me: RobotState, ball: BallState, holding: bool) -> list[float]:
    x, y = frame.point_to_team(me.x, me.y)
    theta = frame.heading_to_team(me.theta)
    vx, vy = frame.velocity_to_team(me.vx, me.vy)
    bx, by = frame.point_to_team(ball.x, ball.y)
    bvx, bvy = frame.velocity_to_team(ball.vx, ball.vy)
    return [x, y, math.cos(theta), math.sin(theta), vx, vy, me.w, bx - x, by - y, bvx, bvy, float(holding)]


def other_block(frame: TeamFrame, robot: RobotState) -> list[float]:
    x, y = frame.point_to_team(robot.x, robot.y)
    vx, vy = frame.velocity_to_team(robot.vx, robot.vy)
    return [x, y, vx, vy]
