"""Synthetic omni-directional vision: what one robot would perceive, with Gaussian noise.

Requires: true world state (``RobotState``, ``BallState``), the robot's ``TeamFrame``, ``NoiseParams``
and a ``numpy.random.Generator``; the compiled ``sim_visual._kernels`` (``vision_frames``). Provides:
``observe_ball3d`` (the goalie's RGB-D ball, ``Ball3dPercept``), ``observe`` -> ``RobotView`` (the percepts every
percept provider gives: itself, the ball if seen, the robots it sees) and ``observe_all`` (the frames of many robots
at once), which, like the real vision, measure positions relative to the robot, add noise, and place them on the
field with the (noisy) self-localization. Everything is in the robot's team frame: a team attacking -x sees the field
turned half round, so its own goal is always at negative x.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.kernels import load_kernels
from nubot_common.percepts import Ball3dPercept, BallPercept, RobotReport, RobotView
from nubot_common.records import fast_init
from nubot_common.team_frame import TeamFrame
from sim_visual.params import NoiseParams
from sim_visual.world import BallState, RobotState

if TYPE_CHECKING:
    from sim_visual import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("sim_visual")


@fast_init
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
    return observe_all(stamp, [me, *others], [0], [frame], [agent_id], [flags], ball, noise, rng)[0]


def observe_all(stamp: float, robots: Sequence[RobotState], observers: Sequence[int], frames: Sequence[TeamFrame],
                agent_ids: Sequence[int], flags: Sequence[RobotFlags], ball: BallState, noise: NoiseParams,
                rng: np.random.Generator) -> list[RobotView]:
    """The vision frames at ``stamp`` [s] of the robots ``robots[i]`` for ``i`` in ``observers`` (each with its own
    frame, AgentID and flags; every other robot of ``robots`` is an obstacle it may see), computed together
    (``_kernels.vision_frames``). The noise is drawn in one call, in the order of one call per observer and object
    (self, ball, robots in range), which gives the very same numbers as frame by frame."""
    rows = [(r.x, r.y, r.theta, r.vx, r.vy, r.w) for r in robots]
    ball_row = (ball.x, ball.y, ball.vx, ball.vy)
    attacks = [f.attack for f in frames]
    draws = _kernels.vision_draws(rows, ball_row, observers, attacks, noise.vision_range)
    normals = rng.normal(0.0, 1.0, size=sum(draws))
    made = _kernels.vision_frames(rows, ball_row, observers, attacks, (
        noise.position_std, noise.velocity_std, noise.self_position_std, noise.heading_std, noise.vision_range),
        normals)
    views = []
    for ((x, y, theta, vx, vy), seen, obstacles), i, agent_id, f in zip(made, observers, agent_ids, flags):
        robot = RobotReport(agent_id, Pose2D(x, y, theta), vx, vy, robots[i].w, valid=f.valid, stuck=f.stuck,
                            holding=f.holding, kicking=f.kicking)
        percept = BallPercept(stamp, *seen, velocity_known=True) if seen is not None else None
        views.append(RobotView(stamp, robot, percept, obstacles))
    return views


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
