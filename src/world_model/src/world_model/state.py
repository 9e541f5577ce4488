"""The plain data the world model takes in and gives out (no ROS types).

Inputs: ``RobotReport`` (one robot's own state as it shares it), ``BallObservation``
(a ball seen by one robot's own sensors), ``RobotView`` (a robot's report with its ball
and obstacles: own vision frame or a teammate's message), ``StrategyReport`` (a robot's
strategy: role, targets, ``PassCommand``), ``CoachExtras`` (the test-mode fields of a
coach command). Outputs: ``WorldState`` with ``Teammate``, ``FusedBall``,
``LabelledObstacle``, ``GameState``. All positions and velocities are in the team frame
(own goal at -x): [m], [m/s], headings [rad]; stamps are sim time [s].
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field
from enum import Enum, IntEnum

from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode

NO_ROLE = 8  # NOROLE in the NuBot role enum (GOALIE 0 ... PASSOFPASS 10)

Point = tuple[float, float]


class BallSource(IntEnum):
    """Where the fused ball comes from; the values are BallInfo.ballinfostate's."""

    UNKNOWN = 0
    OWN = 1
    TEAMMATE = 2


class ObstacleLabel(Enum):
    TEAMMATE = "teammate"
    OPPONENT = "opponent"


@dataclass(frozen=True)
class RobotReport:
    """One robot's state as it shares it with its teammates (RobotInfo)."""

    agent_id: int
    pose: Pose2D  # [m], [rad]
    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    w: float = 0.0  # [rad/s]
    valid: bool = True  # localized and on the field
    stuck: bool = False
    dribble: bool = False
    kick: bool = False
    role: int = NO_ROLE
    role_time: float = 0.0  # time the robot has kept its role [s]
    target_nums: tuple[int, int, int, int] = (0, 0, 0, 0)  # robot IDs assigned to target positions 1..4
    static_pass: int = 0  # passer's ID in a static pass
    static_catch: int = 0  # catcher's ID in a static pass
    target: Point = (0.0, 0.0)  # [m]


@dataclass(frozen=True)
class BallObservation:
    """The ball as one robot's own sensors saw it at ``stamp``."""

    stamp: float  # [s]
    x: float  # [m]
    y: float  # [m]
    vx: float = 0.0  # [m/s]; a per-frame estimate, not used by the fusion
    vy: float = 0.0  # [m/s]
    velocity_known: bool = False

    @property
    def position(self) -> Point:
        return self.x, self.y


@dataclass(frozen=True)
class RobotView:
    """What one robot knows from its own sensors at ``stamp``: itself, the ball, other robots."""

    stamp: float  # [s]
    robot: RobotReport
    ball: BallObservation | None = None  # None when not seen (recently enough)
    obstacles: tuple[Point, ...] = ()  # other robots, both teams, unlabelled [m]


@dataclass(frozen=True)
class PassCommand:
    """A pass agreed between two teammates (PassCommands)."""

    pass_id: int  # passer's AgentID
    catch_id: int  # catcher's AgentID
    pass_pt: Point = (0.0, 0.0)  # where the passer kicks from [m]
    catch_pt: Point = (0.0, 0.0)  # where the catcher receives [m]
    is_passout: bool = False  # the ball has left the passer
    is_dynamic_pass: bool = False
    is_static_pass: bool = False
    is_valid: bool = True


@dataclass(frozen=True)
class StrategyReport:
    """One robot's strategy state (StrategyInfo)."""

    stamp: float  # [s]
    agent_id: int
    role: int = NO_ROLE
    role_time: float = 0.0  # [s]
    target_nums: tuple[int, int, int, int] = (0, 0, 0, 0)
    static_pass: int = 0
    static_catch: int = 0
    is_dribble: bool = False
    pass_cmd: PassCommand | None = None
    target: tuple[float, float] = (0.0, 0.0)  # where the robot is heading, team frame [m]


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
    since: float = 0.0  # when the current mode began [s]
    stamp: float = -math.inf  # when the last valid command arrived [s]; -inf before any

    @property
    def mode(self) -> MatchMode:
        return self.command.mode

    @property
    def previous(self) -> MatchMode:
        return self.command.previous


@dataclass(frozen=True)
class Teammate:
    """A member of the team (this robot included) as the world model sees it now."""

    agent_id: int
    valid: bool  # reported valid and fresh (age <= teammate_timeout)
    age: float  # time since its state was produced [s]; inf when never heard of
    report: RobotReport | None = None  # the last report, also when no longer valid

    @property
    def pose(self) -> Pose2D | None:
        return self.report.pose if self.report is not None else None

    @property
    def velocity(self) -> Point:
        return (self.report.vx, self.report.vy) if self.report is not None else (0.0, 0.0)

    @property
    def role(self) -> int:
        return self.report.role if self.report is not None else NO_ROLE


@dataclass(frozen=True)
class FusedBall:
    known: bool
    x: float = 0.0  # [m]; the last fused position when not known
    y: float = 0.0  # [m]
    vx: float = 0.0  # least-squares fit over velocity_window [m/s]
    vy: float = 0.0  # [m/s]
    velocity_known: bool = False
    confidence: float = 0.0  # 0 (unknown) .. 1, from the age and the number of robots seeing it
    seen_by: tuple[int, ...] = ()  # AgentIDs whose fresh ball agrees with this one
    source: BallSource = BallSource.UNKNOWN
    source_id: int = 0  # AgentID whose observation this is; 0 when unknown
    stamp: float = -math.inf  # time of that observation [s]
    angle: float = 0.0  # bearing from this robot's front [rad]
    radius: float = 0.0  # distance from this robot's centre [m]


@dataclass(frozen=True)
class LabelledObstacle:
    x: float  # [m]
    y: float  # [m]
    label: ObstacleLabel
    teammate_id: int = 0  # the teammate it is, 0 for an opponent
    observer_id: int = 0  # AgentID of the robot that saw it
    angle: float = 0.0  # bearing from this robot's front [rad]
    radius: float = 0.0  # distance from this robot's centre [m]


@dataclass(frozen=True)
class WorldState:
    """One robot's fused world model at ``stamp``."""

    stamp: float  # [s]
    agent_id: int  # this robot
    robots: tuple[Teammate, ...]  # index AgentID - 1, this robot included
    ball: FusedBall
    team_balls: tuple[BallObservation | None, ...]  # each robot's own fresh ball (index AgentID - 1)
    obstacles: tuple[LabelledObstacle, ...]
    game: GameState
    pass_cmd: PassCommand | None  # the valid pass in force, if any

    @property
    def me(self) -> Teammate:
        return self.robots[self.agent_id - 1]

    @property
    def teammates(self) -> tuple[Teammate, ...]:
        return tuple(r for r in self.robots if r.agent_id != self.agent_id)

    @property
    def opponents(self) -> tuple[LabelledObstacle, ...]:
        return tuple(o for o in self.obstacles if o.label is ObstacleLabel.OPPONENT)
