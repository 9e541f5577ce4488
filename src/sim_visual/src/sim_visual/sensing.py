"""Synthetic omni-directional vision: what one robot would perceive, with Gaussian noise.

Requires: true world state (``RobotState``, ``BallState``), ``NoiseParams`` and a
``numpy.random.Generator``. Provides: ``OmniVisionFrame`` and ``observe`` which,
like the real vision, measures positions relative to the robot, adds noise, and
places them on the field with the (noisy) self-localization. Everything is given
in the robot's team frame: a team attacking -x sees the field rotated by pi, so
its own goal is always at negative x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.geometry import Pose2D, to_polar, wrap_angle
from sim_visual.params import NoiseParams
from sim_visual.world import BallState, RobotState


@dataclass(frozen=True)
class SeenObject:
    """An object in the team frame [m], [m/s] and relative to the robot (polar, body frame)."""

    x: float
    y: float
    angle: float  # [rad] from the robot front
    radius: float  # [m]
    vx: float = 0.0
    vy: float = 0.0


@dataclass(frozen=True)
class SelfState:
    """The robot's own state in the team frame, as self-localization and odometry give it."""

    agent_id: int
    x: float
    y: float
    theta: float
    vx: float
    vy: float
    w: float
    is_valid: bool
    is_stuck: bool
    is_dribble: bool
    is_kick: bool


@dataclass(frozen=True)
class OmniVisionFrame:
    stamp: float  # sim time [s]
    ball: SeenObject | None  # None when not seen
    obstacles: tuple[SeenObject, ...]
    robot: SelfState


def to_team_frame(x: float, y: float, attack: int) -> tuple[float, float]:
    """World to team frame: the identity for a team attacking +x, a half turn otherwise."""
    return (x, y) if attack == 1 else (-x, -y)


def observe(stamp: float, me: RobotState, attack: int, agent_id: int, flags: tuple[bool, bool, bool, bool],
            ball: BallState, others: list[RobotState], noise: NoiseParams, rng: np.random.Generator) -> OmniVisionFrame:
    """Build one vision frame for the robot ``me``; ``flags`` are (valid, stuck, dribble, kick)."""
    tx, ty = to_team_frame(me.x, me.y, attack)
    tvx, tvy = to_team_frame(me.vx, me.vy, attack)
    theta = me.theta if attack == 1 else wrap_angle(me.theta + math.pi)
    truth = Pose2D(tx, ty, theta)
    n = rng.normal(0.0, 1.0, size=6)
    est = Pose2D(tx + noise.self_position_std * n[0], ty + noise.self_position_std * n[1],
                 wrap_angle(theta + noise.heading_std * n[2]))
    robot = SelfState(agent_id, est.x, est.y, est.theta, tvx + noise.velocity_std * n[3],
                      tvy + noise.velocity_std * n[4], me.w, *flags)

    def seen(wx: float, wy: float, wvx: float, wvy: float) -> SeenObject | None:
        px, py = to_team_frame(wx, wy, attack)
        bx, by = truth.to_body(px, py)
        if noise.vision_range > 0.0 and math.hypot(bx, by) > noise.vision_range:
            return None
        d = rng.normal(0.0, 1.0, size=4)
        bx, by = bx + noise.position_std * d[0], by + noise.position_std * d[1]
        gx, gy = est.to_world(bx, by)
        vx, vy = to_team_frame(wvx, wvy, attack)
        angle, radius = to_polar(bx, by)
        return SeenObject(gx, gy, angle, radius, vx + noise.velocity_std * d[2], vy + noise.velocity_std * d[3])

    seen_ball = seen(ball.x, ball.y, ball.vx, ball.vy)
    obstacles = tuple(o for o in (seen(r.x, r.y, r.vx, r.vy) for r in others) if o is not None)
    return OmniVisionFrame(stamp, seen_ball, obstacles, robot)
