"""What a robot perceives of itself, the ball and other robots (the same from every percept provider).

Provides: ``BallPercept`` (the ball as one robot's own sensors saw it, on the field plane),
``Ball3dPercept`` (the ball in 3-D as an RGB-D camera sees it, with its flight), ``RobotReport`` (a robot's
state as it reports it: self-localisation, motion, flags and its strategy fields; RobotInfo) and
``RobotView`` (one robot's percepts at one time: itself, the ball if seen, the robots it sees;
an own vision frame or a teammate's packet). The simulator's noisy truth, omni_vision, front_vision
and kinect_ball all produce these. Team frame (own goal at -x): [m], [m/s], [rad]; stamps in sim
time [s].
"""

from __future__ import annotations

from dataclasses import dataclass

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.records import fast_init
from nubot_common.team_play import Point, Role


@fast_init
@dataclass(frozen=True)
class BallPercept:
    stamp: float  # time of the observation [s]
    x: float  # [m]
    y: float  # [m]
    vx: float = 0.0  # a per-frame estimate [m/s]; the world model fits its own
    vy: float = 0.0  # [m/s]
    velocity_known: bool = False

    @property
    def position(self) -> Point:
        return self.x, self.y


@fast_init
@dataclass(frozen=True)
class Ball3dPercept:
    """The ball in 3-D (the goalie's RGB-D cameras, BallInfo3d): its centre and, once fitted, its velocity.

    ``z`` is the height of the ball's centre above the ground (a ball on the ground: its radius). When
    ``velocity_known``, (vx, vy, vz) is the slope at ``stamp`` of the parabola fitted to the recent track, so
    ``nubot_common.ball_flight.landing`` gives where and when it comes down.
    """

    stamp: float  # time of the observation [s]
    x: float  # [m]
    y: float  # [m]
    z: float  # [m]
    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    vz: float = 0.0  # [m/s]
    velocity_known: bool = False

    @property
    def position(self) -> Point:
        return self.x, self.y

    def on_ground(self) -> BallPercept:
        """The same observation as a field-plane percept (its ground projection)."""
        return BallPercept(self.stamp, self.x, self.y, self.vx, self.vy, self.velocity_known)


@fast_init
@dataclass(frozen=True)
class RobotReport:
    agent_id: int
    pose: Pose2D  # [m], [rad]
    vx: float = 0.0  # [m/s]
    vy: float = 0.0  # [m/s]
    w: float = 0.0  # [rad/s], counter-clockwise
    valid: bool = True  # localized and on the field
    stuck: bool = False  # moves much slower than commanded
    holding: bool = False  # holds (dribbles) the ball
    kicking: bool = False  # kicks the ball
    role: Role = Role.NOROLE
    role_time: float = 0.0  # how long it has kept its role [s]
    target_nums: tuple[int, int, int, int] = (0, 0, 0, 0)  # AgentIDs at target positions 1..4
    static_pass: int = 0  # the passer's AgentID of a set-play pass
    static_catch: int = 0  # the catcher's AgentID of a set-play pass
    target: Point = (0.0, 0.0)  # where it is heading [m]

    def moved_on(self, dt: float) -> RobotReport:
        """This report ``dt`` [s] later, had the robot kept its velocity (where a teammate whose packet is ``dt``
        old is now); heading wrapped to (-pi, pi]."""
        if dt == 0.0:
            return self
        pose = self.pose
        moved = object.__new__(RobotReport)  # as replaced() makes it, without its check: every teammate, every cycle
        moved.__dict__.update(self.__dict__, pose=Pose2D(pose.x + self.vx * dt, pose.y + self.vy * dt,
                                                         wrap_angle(pose.theta + self.w * dt)))
        return moved

    def replaced(self, **changes: object) -> RobotReport:
        """``dataclasses.replace`` at a tenth of its cost, for the reports made every cycle: the other fields copied
        as they are, without running ``__init__`` again (it checks nothing); an unknown field is an error."""
        fields = self.__dict__
        for name in changes:
            if name not in fields:
                raise TypeError(f"RobotReport has no field {name}")
        made = object.__new__(RobotReport)
        made.__dict__.update(fields, **changes)
        return made


@fast_init
@dataclass(frozen=True)
class RobotView:
    stamp: float  # [s]
    robot: RobotReport
    ball: BallPercept | None = None  # None: not seen
    obstacles: tuple[Point, ...] = ()  # other robots seen, either team, unlabelled [m]
