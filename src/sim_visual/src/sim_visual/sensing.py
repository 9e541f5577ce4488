"""Synthetic omni-directional vision: what one robot would perceive, with Gaussian noise.

Requires: true world state (``RobotState``, ``BallState``), the robot's ``TeamFrame``, ``NoiseParams``
and a ``numpy.random.Generator``. Provides: ``observe_ball3d`` (the goalie's RGB-D ball, ``Ball3dPercept``) and
``observe`` -> ``RobotView`` (the percepts every percept
provider gives: itself, the ball if seen, the robots it sees) which, like the real vision, measures
positions relative to the robot, adds noise, and places them on the field with the (noisy)
self-localization. Everything is in the robot's team frame: a team attacking -x sees the field
turned half round, so its own goal is always at negative x.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.percepts import Ball3dPercept, BallPercept, RobotReport, RobotView
from nubot_common.team_frame import TeamFrame
from sim_visual.params import NoiseParams
from sim_visual.world import BallState, RobotState


@dataclass(frozen=True)
class RobotFlags:
    """What the robot knows of itself beyond its pose (RobotInfo's flags)."""

    valid: bool = True  # on the field (lines plus border)
    stuck: bool = False
    holding: bool = False
    kicking: bool = False


def observe(stamp: float, me: RobotState, frame: TeamFrame, agent_id: int, flags: RobotFlags, ball: BallState,
            others: list[RobotState], noise: NoiseParams, rng: np.random.Generator) -> RobotView:
    """One vision frame of the robot ``me`` at ``stamp`` [s]."""
    tx, ty = frame.point_to_team(me.x, me.y)
    tvx, tvy = frame.velocity_to_team(me.vx, me.vy)
    truth = Pose2D(tx, ty, frame.heading_to_team(me.theta))
    # What is in range is known before any noise is drawn: all the frame's noise comes from one call, in the
    # order of one call per object (self, ball, robots), which gives the very same numbers.
    things = [(ball.x, ball.y, ball.vx, ball.vy)] + [(r.x, r.y, r.vx, r.vy) for r in others]
    relative = [truth.to_body(*frame.point_to_team(wx, wy)) for wx, wy, _, _ in things]
    in_range = [not (noise.vision_range > 0.0 and math.hypot(bx, by) > noise.vision_range) for bx, by in relative]
    n = rng.normal(0.0, 1.0, size=6 + 4 * sum(in_range)).tolist()
    est = Pose2D(tx + noise.self_position_std * n[0], ty + noise.self_position_std * n[1],
                 wrap_angle(truth.theta + noise.heading_std * n[2]))
    robot = RobotReport(agent_id, est, tvx + noise.velocity_std * n[3], tvy + noise.velocity_std * n[4], me.w,
                        valid=flags.valid, stuck=flags.stuck, holding=flags.holding, kicking=flags.kicking)
    seen: list[tuple[float, float, float, float] | None] = []  # (x, y, vx, vy) in the team frame, or out of range
    k = 6
    for (_, _, wvx, wvy), (bx, by), visible in zip(things, relative, in_range):
        if not visible:
            seen.append(None)
            continue
        d = n[k:k + 4]
        k += 4
        gx, gy = est.to_world(bx + noise.position_std * d[0], by + noise.position_std * d[1])
        vx, vy = frame.velocity_to_team(wvx, wvy)
        seen.append((gx, gy, vx + noise.velocity_std * d[2], vy + noise.velocity_std * d[3]))
    ball_seen = seen[0]
    percept = BallPercept(stamp, *ball_seen, velocity_known=True) if ball_seen is not None else None
    obstacles = tuple((o[0], o[1]) for o in seen[1:] if o is not None)
    return RobotView(stamp, robot, percept, obstacles)


# The goalie's RGB-D cameras as the simulator's percepts give them (the robots not seeing through cameras): what
# kinect_ball makes of the two clouds, with its errors in the simulator's tests (bench_kinect_ball: a few mm in
# position, a parabola that predicts the touchdown within cm).
RGBD_RANGE = 8.0  # [m], the Kinect 2's longest range
RGBD_HALF_FOV = math.radians(32.0 + 70.6 / 2)  # both cameras together, either side of the robot's front [rad]
RGBD_POSITION_STD = 0.01  # [m]
RGBD_VELOCITY_STD = 0.05  # [m/s]


def observe_ball3d(stamp: float, me: RobotState, frame: TeamFrame, ball: BallState,
                   rng: np.random.Generator) -> Ball3dPercept | None:
    """The ball in 3-D as robot ``me``'s RGB-D cameras give it at ``stamp`` (team frame); None out of their view."""
    dx, dy = ball.x - me.x, ball.y - me.y
    bearing = wrap_angle(math.atan2(dy, dx) - me.theta)
    if math.hypot(dx, dy) > RGBD_RANGE or abs(bearing) > RGBD_HALF_FOV:
        return None
    n = rng.normal(0.0, 1.0, size=6).tolist()
    x, y = frame.point_to_team(ball.x, ball.y)
    vx, vy = frame.velocity_to_team(ball.vx, ball.vy)
    p, v = RGBD_POSITION_STD, RGBD_VELOCITY_STD
    return Ball3dPercept(stamp, x + p * n[0], y + p * n[1], ball.z + p * n[2], vx + v * n[3], vy + v * n[4],
                         ball.vz + v * n[5], True)
