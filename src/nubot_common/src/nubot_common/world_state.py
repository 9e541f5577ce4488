"""One robot's fused world model: the world model's decision, which control acts on (WorldModelInfo).

Provides: ``WorldState`` (at one time: every teammate with its validity, the fused ball, the ball's
flight in 3-D, labelled obstacles, the game state, the pass in force) and its parts ``Teammate``,
``FusedBall``, ``BallFlight``, ``LabelledObstacle``, ``GameState``, ``CoachCommand``, ``CoachExtras``,
``BallSource``, ``BallSensor``, ``ObstacleLabel``. The world model decides each of these once; control
and every other reader use them as they are. Team frame (own goal at -x): [m], [m/s], [rad]; times are sim time [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum, IntEnum
from functools import cached_property
from typing import NamedTuple

from nubot_common.ball_flight import GRAVITY, landing
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import Ball3dPercept, BallPercept, RobotReport
from nubot_common.records import fast_init
from nubot_common.team_play import PassCommand, Point, Role


class BallSource(IntEnum):
    """Where the fused ball comes from; the values are BallInfo.ballinfostate's."""

    UNKNOWN = 0
    OWN = 1
    TEAMMATE = 2


class BallSensor(IntEnum):
    """Which of this robot's own sensors the fused ball comes from (NONE: a teammate's, or unknown)."""

    NONE = 0
    OMNI = 1  # the omni-directional camera
    FRONT = 2  # the front camera (near ball)
    RGBD = 3  # the goalie's RGB-D cameras (the ball in 3-D)


class ObstacleLabel(Enum):
    TEAMMATE = "teammate"
    OPPONENT = "opponent"


@fast_init
@dataclass(frozen=True)
class FusedBall:
    """The ball as the world model believes it; when not ``known``, (x, y) is where it was last seen."""

    x: float  # [m]
    y: float  # [m]
    vx: float = 0.0  # least-squares fit over the velocity window [m/s]
    vy: float = 0.0  # [m/s]
    known: bool = True  # seen recently enough, by this robot or a valid teammate
    velocity_known: bool = False
    confidence: float = 0.0  # 0 (unknown) .. 1, from the age and the number of robots seeing it
    seen_by: tuple[int, ...] = ()  # AgentIDs whose fresh ball agrees with this one
    source: BallSource = BallSource.UNKNOWN
    source_id: int = 0  # AgentID whose observation this is; 0 when unknown
    stamp: float = -math.inf  # time of that observation [s]
    angle: float = 0.0  # bearing from this robot's front [rad]
    radius: float = 0.0  # distance from this robot's centre [m]
    sensor: BallSensor = BallSensor.NONE  # the own sensor it comes from (source OWN)

    @property
    def position(self) -> Point:
        return self.x, self.y


@fast_init
@dataclass(frozen=True)
class BallFlight:
    """The ball in 3-D from this robot's RGB-D cameras, and where and when it comes down while it flies."""

    ball: Ball3dPercept  # the latest own 3-D observation, its velocity fitted over the flight
    touchdown: tuple[float, float, float] | None = None  # (x, y [m], sim time [s]) its centre comes down to its
    # radius; None while it is on the ground or its velocity is not known

    @classmethod
    def of(cls, ball: Ball3dPercept, ball_radius: float, air_margin: float,
           gravity: float = GRAVITY) -> BallFlight:
        """``ball`` with its touchdown when its centre is more than ``air_margin`` [m] above a ball at rest."""
        if not (ball.velocity_known and ball.z > ball_radius + air_margin):
            return cls(ball)
        down = landing(ball.x, ball.y, ball.z, ball.vx, ball.vy, ball.vz, ball_radius, gravity)
        return cls(ball, (down.x, down.y, ball.stamp + down.t))

    @property
    def in_air(self) -> bool:
        return self.touchdown is not None


@fast_init
@dataclass(frozen=True)
class Teammate:
    """A member of the team (this robot included) as the world model sees it now."""

    agent_id: int
    valid: bool  # fresh (age <= teammate_timeout), reported valid, and playing (its strategy is heard)
    age: float  # time since its state was produced [s]; inf when never heard of
    report: RobotReport | None = None  # the last report, also when no longer valid

    @property
    def pose(self) -> Pose2D | None:
        return self.report.pose if self.report is not None else None

    @property
    def role(self) -> Role:
        return self.report.role if self.report is not None else Role.NOROLE


class LabelledObstacle(NamedTuple):
    """An obstacle of the fused world model (a record built by the dozen every cycle: a named tuple, which is made
    several times faster than a frozen dataclass)."""

    x: float  # [m]
    y: float  # [m]
    label: ObstacleLabel
    teammate_id: int = 0  # the teammate it is, 0 for an opponent
    observer_id: int = 0  # AgentID of the robot that saw it
    angle: float = 0.0  # bearing from this robot's front [rad]
    radius: float = 0.0  # distance from this robot's centre [m]
    vx: float = 0.0  # [m/s], as this robot's obstacle tracker estimates it; 0 for a teammate's report
    vy: float = 0.0


@dataclass(frozen=True)
class CoachExtras:
    """The test-mode fields of a coach command, passed through unchanged."""

    test_mode: int = 0
    point_a: Point = (0.0, 0.0)  # [m]
    point_b: Point = (0.0, 0.0)  # [m]
    angle_a: int = 0  # [deg]
    angle_b: int = 0  # [deg]
    id_a: int = 0
    id_b: int = 0
    kickforce: int = 0  # [m/s]


@dataclass(frozen=True)
class CoachCommand:
    """A validated game command: the current MatchMode and the previous one (MatchType)."""

    mode: MatchMode = MatchMode.STOPROBOT
    previous: MatchMode = MatchMode.STOPROBOT
    extras: CoachExtras = field(default_factory=CoachExtras)


@dataclass(frozen=True)
class GameState:
    command: CoachCommand = field(default_factory=CoachCommand)  # the last valid command
    since: float = 0.0  # when the current command came into force [s]
    stamp: float = -math.inf  # when the last valid command arrived [s]; -inf before any

    @property
    def mode(self) -> MatchMode:
        return self.command.mode

    @property
    def previous(self) -> MatchMode:
        return self.command.previous


@fast_init
@dataclass(frozen=True)
class WorldState:
    """One robot's fused world model at ``stamp``."""

    stamp: float  # [s]
    agent_id: int  # this robot
    robots: tuple[Teammate, ...]  # index AgentID - 1, this robot included
    ball: FusedBall
    team_balls: tuple[BallPercept | None, ...]  # each robot's own fresh ball (index AgentID - 1)
    obstacles: tuple[LabelledObstacle, ...]
    game: GameState
    pass_cmd: PassCommand | None  # the valid pass in force, if any
    flight: BallFlight | None = None  # the ball in 3-D from own RGB-D cameras, while fresh

    @property
    def me(self) -> Teammate:
        return self.robots[self.agent_id - 1]

    # Worked out once and kept in the (frozen) instance's __dict__: read several times a cycle.
    @cached_property
    def teammates(self) -> tuple[Teammate, ...]:
        return tuple(r for r in self.robots if r.agent_id != self.agent_id)

    @cached_property
    def opponents(self) -> tuple[LabelledObstacle, ...]:
        return tuple(o for o in self.obstacles if o.label is ObstacleLabel.OPPONENT)
