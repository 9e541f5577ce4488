"""What a robot asks of its base, its ball handler and its kicker (the robot interface, chapter Table 3).

Provides: ``BodyVelocity`` (VelCmd), ``KickKind`` (Shoot.ShootPos), ``KickCommand`` (a Shoot
request) and ``RobotCommand`` (one control cycle's commands: the velocity, the dribbler wish, the
BallHandle request to send now if any, the kick to make now if any). Body frame (REP 103: x forward
along the kicking mechanism, y left): [m/s], [rad/s].
"""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

from nubot_common.records import fast_init


class KickKind(IntEnum):
    GROUND = -1  # ground pass along the robot's heading, strength = initial ball speed [m/s]
    LOB = 1  # lob shot at the attacked goal; the kicker computes its strength


@fast_init
@dataclass(frozen=True)
class BodyVelocity:
    vx: float = 0.0  # forward [m/s]
    vy: float = 0.0  # leftward [m/s]
    w: float = 0.0  # counter-clockwise [rad/s]


@dataclass(frozen=True)
class KickCommand:
    kind: KickKind
    strength: int  # ground pass: initial ball speed [m/s] (Shoot.strength is int64, chapter Table 3)


@fast_init
@dataclass(frozen=True)
class RobotCommand:
    velocity: BodyVelocity = BodyVelocity()
    dribble: bool = False  # the dribbler should hold the ball
    ball_handle: int | None = None  # BallHandle.enable to send this cycle (1 on, 0 off); None: no call
    kick: KickCommand | None = None  # Shoot to call this cycle; None: no kick
