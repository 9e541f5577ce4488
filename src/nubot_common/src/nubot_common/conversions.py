"""Conversions between the shared messages and the shared representations (the only module that knows both).

Requires: the generated ``nubot_common`` messages and ``genpy`` (no rospy). Provides, both ways where a
node needs both: percepts (``robot_report``/``robot_info_msg``, ``ball_percept``/``ball_info_msg``,
``ball3d_percept``/``ball_info3d_msg`` (BallInfo3d), ``front_ball``/``front_ball_info_msg`` (FrontBallInfo, body
frame), ``robot_view``/``omni_vision_msg``,
``team_views``/``team_message_msg``), coach commands (``coach_fields``, ``coach_info_msg``), team play
(``pass_command``/``pass_commands_msg``, ``strategy_report``/``strategy_info_msg``,
``target_info_msg``/``target_of``), the motion layer's path
(``planned_path_msg``/``planned_path``), the world model's decision (``world_model_info_msg``/``world_state``:
lossless for everything control reads; ``ball_flight_msg``/``ball_flight``: the ball's flight, BallFlightInfo),
commands (``velcmd_msg``/``body_velocity``) and the world description
(``world_description_msg``/``world_description``). Conventions: a zero header stamp means "not stamped" (the
reader uses the time of arrival); ``char`` fields arrive as an int, a byte or a one-letter string and leave as int;
``CoachInfo.header.stamp`` inside ``WorldModelInfo`` is when the current command came into force.
"""

from __future__ import annotations

import dataclasses
import math
from collections import Counter
from collections.abc import Sequence
from typing import Any

import genpy

from nubot_common import NubotCommonError
from nubot_common.commands import BodyVelocity
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, yaw_to_quaternion
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.msg import (
    BallBody as BallBodyMsg,
)
from nubot_common.msg import (
    BallFlightInfo,
    BallInfo,
    BallInfo3d,
    CoachInfo,
    FrontBallInfo,
    ModelState,
    ObstaclesInfo,
    OmniVisionInfo,
    PassCommands,
    PlannedPath,
    Point2d,
    Point3d,
    PPoint,
    RobotInfo,
    StrategyInfo,
    TargetInfo,
    TeamMessage,
    TeamMessages,
    VelCmd,
    WorldModelInfo,
)
from nubot_common.msg import (
    FieldGeometry as FieldGeometryMsg,
)
from nubot_common.msg import (
    RobotBody as RobotBodyMsg,
)
from nubot_common.msg import (
    WorldDescription as WorldDescriptionMsg,
)
from nubot_common.percepts import Ball3dPercept, BallPercept, RobotReport, RobotView
from nubot_common.team_play import PassCommand, Point, Role, StrategyReport
from nubot_common.world_description import BallBody, RobotBody, WorldDescription
from nubot_common.world_state import (
    BallFlight,
    BallSource,
    CoachCommand,
    CoachExtras,
    FusedBall,
    GameState,
    LabelledObstacle,
    ObstacleLabel,
    Teammate,
    WorldState,
)


# --- fields --------------------------------------------------------------------------------------
def model_state_msg(name: str, x: float, y: float, z: float = 0.0, yaw: float = 0.0) -> ModelState:
    """A SetModelState request's model at rest at (x, y, z) [m], heading ``yaw`` [rad], world frame."""
    state = ModelState(model_name=name, reference_frame="world")
    state.pose.position.x, state.pose.position.y, state.pose.position.z = x, y, z
    o = state.pose.orientation
    o.x, o.y, o.z, o.w = yaw_to_quaternion(yaw)
    return state


def char_value(value: int | bytes | str) -> int:
    """The number in a ROS ``char`` field, whether genpy gives it as an int, a byte or a one-letter string."""
    if isinstance(value, bytes | str):
        return ord(value) if value else 0
    return int(value)


def stamp(t: float) -> genpy.Time:
    """A header stamp for sim time ``t`` [s]; zero ("not stamped") for a time that is not positive and finite."""
    return genpy.Time.from_sec(t) if math.isfinite(t) and t > 0.0 else genpy.Time()


def point2d(x: float, y: float) -> Point2d:
    """A Point2d [m]. Messages are built field by field here: genpy's constructor with arguments costs several
    times as much, and a match builds thousands of messages a second."""
    p = Point2d()
    p.x, p.y = x, y
    return p


def ppoint(angle: float, radius: float) -> PPoint:
    """A PPoint (angle [rad], radius [m])."""
    p = PPoint()
    p.angle, p.radius = angle, radius
    return p


def seconds(time: genpy.Time) -> float:
    return float(time.to_sec())


def _point(p: Point2d) -> Point:
    return float(p.x), float(p.y)


# --- percepts ------------------------------------------------------------------------------------
def robot_report(info: RobotInfo) -> RobotReport:
    return RobotReport(
        agent_id=int(info.AgentID), pose=Pose2D(info.pos.x, info.pos.y, info.heading.theta),
        vx=info.vtrans.x, vy=info.vtrans.y, w=info.vrot, valid=bool(info.isvalid), stuck=bool(info.isstuck),
        holding=bool(info.isdribble), kicking=bool(info.iskick), role=Role.of(char_value(info.current_role)),
        role_time=info.role_time, target_nums=(info.targetNum1, info.targetNum2, info.targetNum3, info.targetNum4),
        static_pass=info.staticpassNum, static_catch=info.staticcatchNum, target=_point(info.target))


def robot_info_msg(report: RobotReport | None, agent_id: int, valid: bool, t: float) -> RobotInfo:
    """RobotInfo of ``report`` produced at ``t``; a robot never heard of has only its AgentID (and is invalid)."""
    info = RobotInfo()
    info.header.stamp = stamp(t)
    info.AgentID = agent_id
    info.isvalid = valid
    if report is None:
        return info
    r = report
    info.targetNum1, info.targetNum2, info.targetNum3, info.targetNum4 = r.target_nums
    info.staticpassNum, info.staticcatchNum = r.static_pass, r.static_catch
    info.pos.x, info.pos.y = r.pose.x, r.pose.y  # into the fields' own messages, made with ``info``
    info.heading.theta = r.pose.theta
    info.vrot = r.w
    info.vtrans.x, info.vtrans.y = r.vx, r.vy
    info.iskick, info.isstuck, info.isdribble = r.kicking, r.stuck, r.holding
    info.current_role = int(r.role)
    info.role_time = r.role_time
    info.target.x, info.target.y = r.target
    return info


def ball_percept(ball: BallInfo, fallback: float) -> BallPercept | None:
    """The ball of a BallInfo if its position is known; stamped ``fallback`` when the message is not."""
    if not ball.pos_known:
        return None
    t = seconds(ball.header.stamp) or fallback
    return BallPercept(t, ball.pos.x, ball.pos.y, ball.velocity.x, ball.velocity.y, bool(ball.velocity_known))


def ball_info_msg(percept: BallPercept | None, source: BallSource, observer: Pose2D | None) -> BallInfo:
    """BallInfo of a ball one robot saw (``source`` OWN or TEAMMATE); polar from ``observer`` if given."""
    ball = BallInfo()
    if percept is None:
        return ball
    ball.header.stamp = stamp(percept.stamp)
    ball.ballinfostate = int(source)
    ball.pos.x, ball.pos.y, ball.velocity.x, ball.velocity.y = percept.x, percept.y, percept.vx, percept.vy
    if observer is not None:
        ball.real_pos.angle = observer.bearing_to(percept.x, percept.y)
        ball.real_pos.radius = observer.distance_to(percept.x, percept.y)
    ball.pos_known, ball.velocity_known = True, percept.velocity_known
    return ball


def ball3d_percept(msg: BallInfo3d, fallback: float) -> Ball3dPercept | None:
    """The ball of a BallInfo3d (team frame [m], [m/s]) if its 3-D position is known and finite; stamped
    ``fallback`` when the message is not. A velocity that is not finite counts as unknown."""
    p, v = msg.pos, msg.velocity
    if not msg.pos_known_3d or not all(math.isfinite(c) for c in (p.x, p.y, p.z)):
        return None
    t = seconds(msg.header.stamp) or fallback
    if msg.velocity_known and all(math.isfinite(c) for c in (v.x, v.y, v.z)):
        return Ball3dPercept(t, p.x, p.y, p.z, v.x, v.y, v.z, True)
    return Ball3dPercept(t, p.x, p.y, p.z)


def ball_info3d_msg(percept: Ball3dPercept | None, t: float, frame_id: str = "") -> BallInfo3d:
    """BallInfo3d of the ball an RGB-D camera saw (team frame), or one with nothing known at ``t`` [s]."""
    msg = BallInfo3d()
    msg.header.stamp = stamp(percept.stamp if percept is not None else t)
    msg.header.frame_id = frame_id
    if percept is None:
        return msg
    msg.pos = Point3d(percept.x, percept.y, percept.z)
    msg.pos_known_3d = msg.pos_known_2d = True
    if percept.velocity_known:
        msg.velocity = Point3d(percept.vx, percept.vy, percept.vz)
        msg.velocity_known = True
    return msg


def front_ball_info_msg(percept: BallPercept | None, t: float, frame_id: str = "") -> FrontBallInfo:
    """FrontBallInfo of the ball the front camera saw: ``percept`` (x, y) [m] in the robot's body frame, sent as
    polar ``real_pos`` (angle [rad] from the front, counter-clockwise; radius [m]); None: not known, at ``t``."""
    msg = FrontBallInfo()
    msg.header.stamp = stamp(percept.stamp if percept is not None else t)
    msg.header.frame_id = frame_id
    if percept is not None and math.isfinite(percept.x) and math.isfinite(percept.y):
        msg.real_pos = PPoint(math.atan2(percept.y, percept.x), math.hypot(percept.x, percept.y))
        msg.pos_known = True
    return msg


def front_ball(msg: FrontBallInfo, fallback: float) -> BallPercept | None:
    """The ball of a FrontBallInfo as (x, y) [m] in the robot's body frame, if known and finite; stamped
    ``fallback`` when the message is not."""
    angle, radius = msg.real_pos.angle, msg.real_pos.radius
    if not msg.pos_known or not (math.isfinite(angle) and math.isfinite(radius)) or radius < 0.0:
        return None
    return BallPercept(seconds(msg.header.stamp) or fallback, radius * math.cos(angle), radius * math.sin(angle))


def obstacles_msg(points: Sequence[Point], observer: Pose2D | None, t: float) -> ObstaclesInfo:
    """ObstaclesInfo of ``points`` (team frame [m]), with polar positions from ``observer`` when given."""
    msg = ObstaclesInfo()
    msg.header.stamp = stamp(t)
    msg.pos = [point2d(x, y) for x, y in points]
    if observer is not None:
        msg.polar_pos = [ppoint(observer.bearing_to(x, y), observer.distance_to(x, y)) for x, y in points]
    return msg


def robot_view(msg: OmniVisionInfo, now: float) -> RobotView:
    """One vision frame: ``robotinfo[0]`` is the robot itself; an unstamped frame is taken at ``now``."""
    if not msg.robotinfo:
        raise NubotCommonError("OmniVisionInfo without robotinfo[0] (the robot itself)")
    t = seconds(msg.header.stamp) or now
    return RobotView(t, robot_report(msg.robotinfo[0]), ball_percept(msg.ballinfo, t),
                     tuple(_point(p) for p in msg.obstacleinfo.pos))


def omni_vision_msg(view: RobotView) -> OmniVisionInfo:
    """OmniVisionInfo of one vision frame (what the simulator or omni_vision publishes)."""
    msg = OmniVisionInfo()
    msg.header.stamp = stamp(view.stamp)
    me = view.robot.pose
    msg.ballinfo = ball_info_msg(view.ball, BallSource.OWN, me)
    msg.ballinfo.header.stamp = msg.header.stamp
    msg.obstacleinfo = obstacles_msg(view.obstacles, me, view.stamp)
    msg.robotinfo = [robot_info_msg(view.robot, view.robot.agent_id, view.robot.valid, view.stamp)]
    return msg


def team_message_msg(view: RobotView, t: float) -> TeamMessage:
    """This robot's packet for its teammates, sent at ``t``; the robot part is stamped with its frame's time."""
    msg = TeamMessage()
    msg.header.stamp = stamp(t)
    me = view.robot.pose
    msg.robot = robot_info_msg(view.robot, view.robot.agent_id, view.robot.valid, view.stamp)
    msg.ball = ball_info_msg(view.ball, BallSource.OWN, me)
    msg.obstacles = obstacles_msg(view.obstacles, me, view.stamp)
    return msg


def team_views(msg: TeamMessages) -> list[RobotView]:
    """One view per relayed packet, stamped by the sender's robot state (0 when it was not stamped)."""
    views = []
    for m in msg.messages:
        t = seconds(m.robot.header.stamp) or seconds(m.header.stamp)
        obstacles = tuple(_point(p) for p in m.obstacles.pos)
        views.append(RobotView(t, robot_report(m.robot), ball_percept(m.ball, t), obstacles))
    return views


# --- coach ---------------------------------------------------------------------------------------
def coach_fields(msg: CoachInfo) -> tuple[int, int, CoachExtras]:
    """(MatchMode, MatchType, extras) as numbers; the world model validates them."""
    extras = CoachExtras(char_value(msg.TestMode), _point(msg.pointA), _point(msg.pointB), int(msg.angleA),
                         int(msg.angleB), char_value(msg.idA), char_value(msg.idB), char_value(msg.kickforce))
    return char_value(msg.MatchMode), char_value(msg.MatchType), extras


def coach_info_msg(mode: int, previous: int, t: float, extras: CoachExtras | None = None) -> CoachInfo:
    msg = CoachInfo()
    msg.MatchMode, msg.MatchType = int(mode), int(previous)
    msg.header.stamp = stamp(t)
    e = extras or CoachExtras()
    msg.TestMode = e.test_mode
    (msg.pointA.x, msg.pointA.y), (msg.pointB.x, msg.pointB.y) = e.point_a, e.point_b
    msg.angleA, msg.angleB, msg.idA, msg.idB, msg.kickforce = e.angle_a, e.angle_b, e.id_a, e.id_b, e.kickforce
    return msg


def _safe_mode(value: int | bytes | str) -> MatchMode:
    try:
        return parse_match_mode(char_value(value))
    except NubotCommonError:
        return MatchMode.STOPROBOT  # a command nobody knows: stay still


# --- team play -----------------------------------------------------------------------------------
def pass_command(msg: PassCommands) -> PassCommand | None:
    """The pass of a PassCommands, None unless it is in force."""
    if not msg.is_valid:
        return None
    return PassCommand(int(msg.pass_id), int(msg.catch_id), _point(msg.pass_pt), _point(msg.catch_pt),
                       bool(msg.is_passout), bool(msg.is_dynamic_pass), bool(msg.is_static_pass), True)


def pass_commands_msg(cmd: PassCommand | None) -> PassCommands:
    if cmd is None:
        return PassCommands()  # is_valid false
    msg = PassCommands()
    msg.pass_id, msg.catch_id = max(cmd.pass_id, 0), max(cmd.catch_id, 0)
    (msg.pass_pt.x, msg.pass_pt.y), (msg.catch_pt.x, msg.catch_pt.y) = cmd.pass_pt, cmd.catch_pt
    msg.is_passout, msg.is_dynamic_pass, msg.is_static_pass = cmd.is_passout, cmd.is_dynamic_pass, cmd.is_static_pass
    msg.is_valid = cmd.is_valid
    return msg


def strategy_report(msg: StrategyInfo, target: Point = (0.0, 0.0)) -> StrategyReport:
    """A StrategyInfo as a report; its target travels apart (TargetInfo), so it is given here."""
    return StrategyReport(
        seconds(msg.header.stamp), int(msg.AgentID), Role.of(int(msg.role)), int(msg.action), float(msg.role_time),
        (msg.targetNum1, msg.targetNum2, msg.targetNum3, msg.targetNum4), msg.staticpassNum, msg.staticcatchNum,
        bool(msg.is_dribble), bool(msg.is_kickoff), pass_command(msg.pass_cmd), target)


def strategy_info_msg(report: StrategyReport) -> StrategyInfo:
    msg = StrategyInfo()
    msg.header.stamp = stamp(report.stamp)
    msg.AgentID = report.agent_id
    msg.targetNum1, msg.targetNum2, msg.targetNum3, msg.targetNum4 = report.target_nums
    msg.staticpassNum, msg.staticcatchNum = report.static_pass, report.static_catch
    msg.role, msg.action = int(report.role), max(int(report.action), 0)
    msg.is_dribble, msg.is_kickoff = report.holding, report.kickoff
    msg.role_time = report.role_time
    msg.pass_cmd = pass_commands_msg(report.pass_cmd)
    return msg


def target_info_msg(report: StrategyReport) -> TargetInfo:
    """Where the robot heads: ``target[0]`` (team frame [m])."""
    msg = TargetInfo()
    msg.target = [point2d(*report.target)]
    msg.header.stamp = stamp(report.stamp)
    return msg


def target_of(msg: TargetInfo) -> Point | None:
    return _point(msg.target[0]) if msg.target else None


def planned_path_msg(points: Sequence[Point], t: float, team: str) -> PlannedPath:
    """The path a robot of team ``team`` follows (team frame [m]; no points: none), stamped ``t`` [s]."""
    msg = PlannedPath()
    msg.points = [point2d(x, y) for x, y in points]
    msg.header.stamp, msg.header.frame_id = stamp(t), team
    return msg


def planned_path(msg: PlannedPath) -> list[Point]:
    return [_point(p) for p in msg.points]


# --- the world model's decision -----------------------------------------------------------------------
def fused_ball_msg(ball: FusedBall) -> BallInfo:
    msg = BallInfo()
    msg.header.stamp = stamp(ball.stamp)
    msg.ballinfostate = int(ball.source)
    msg.pos.x, msg.pos.y, msg.velocity.x, msg.velocity.y = ball.x, ball.y, ball.vx, ball.vy
    msg.real_pos.angle, msg.real_pos.radius = ball.angle, ball.radius
    msg.pos_known, msg.velocity_known = ball.known, ball.velocity_known
    return msg


def fused_ball(msg: BallInfo) -> FusedBall:
    source = BallSource(msg.ballinfostate) if msg.ballinfostate in (0, 1, 2) else BallSource.UNKNOWN
    t = seconds(msg.header.stamp)
    return FusedBall(msg.pos.x, msg.pos.y, msg.velocity.x, msg.velocity.y, bool(msg.pos_known),
                     bool(msg.velocity_known), source=source, stamp=t if t > 0.0 else -math.inf,
                     angle=msg.real_pos.angle, radius=msg.real_pos.radius)


def world_model_info_msg(state: WorldState) -> WorldModelInfo:
    msg = WorldModelInfo()
    msg.header.stamp = stamp(state.stamp)
    me = state.me.pose
    msg.obstacleinfo = obstacles_msg([(o.x, o.y) for o in state.obstacles], me, state.stamp)
    msg.oppinfo = obstacles_msg([(o.x, o.y) for o in state.opponents], me, state.stamp)
    msg.robotinfo = [robot_info_msg(r.report, r.agent_id, r.valid,
                                    state.stamp - r.age if math.isfinite(r.age) else 0.0) for r in state.robots]
    msg.ballinfo = [fused_ball_msg(state.ball) if r.agent_id == state.agent_id else
                    ball_info_msg(state.team_balls[r.agent_id - 1], BallSource.TEAMMATE, r.pose)
                    for r in state.robots]
    game = state.game
    msg.coachinfo = coach_info_msg(game.mode, game.previous, game.since, game.command.extras)
    msg.pass_cmd = pass_commands_msg(state.pass_cmd)
    return msg


def world_state(msg: WorldModelInfo, agent_id: int) -> WorldState:
    """The world model's decision back from its message, as robot ``agent_id``'s control reads it.

    Everything control reads comes back as the world model decided it; an unknown MatchMode reads
    as STOPROBOT (stay still).
    """
    if not 1 <= agent_id <= len(msg.robotinfo):
        raise NubotCommonError(f"WorldModelInfo has {len(msg.robotinfo)} robots; no AgentID {agent_id}")
    t = seconds(msg.header.stamp)
    robots = []
    for index, info in enumerate(msg.robotinfo):
        produced = seconds(info.header.stamp)  # 0: not stamped (a world model that does not stamp its robots)
        heard = produced > 0.0 or bool(info.isvalid)
        age = max(0.0, t - produced) if produced > 0.0 else 0.0 if heard else math.inf
        robots.append(Teammate(index + 1, bool(info.isvalid), age, robot_report(info) if heard else None))
    balls = tuple(None if i == agent_id - 1 else ball_percept(b, t) for i, b in enumerate(msg.ballinfo))
    balls += (None,) * (len(robots) - len(balls))
    own_ball = msg.ballinfo[agent_id - 1] if agent_id <= len(msg.ballinfo) else BallInfo()
    me = robots[agent_id - 1].pose or Pose2D()
    opponents = Counter(_point(p) for p in msg.oppinfo.pos)
    obstacles = []
    for p in msg.obstacleinfo.pos:
        x, y = _point(p)
        label = ObstacleLabel.OPPONENT if opponents[(x, y)] > 0 else ObstacleLabel.TEAMMATE
        opponents[(x, y)] -= 1
        obstacles.append(LabelledObstacle(x, y, label, angle=me.bearing_to(x, y), radius=me.distance_to(x, y)))
    coach = msg.coachinfo
    since = seconds(coach.header.stamp)
    mode, previous, extras = coach_fields(coach)
    game = GameState(CoachCommand(_safe_mode(mode), _safe_mode(previous), extras), since, since)
    return WorldState(t, agent_id, tuple(robots), fused_ball(own_ball), balls, tuple(obstacles), game,
                      pass_command(msg.pass_cmd))



def ball_flight_msg(flight: BallFlight | None, t: float) -> BallFlightInfo:
    """BallFlightInfo of the world model's flight at its snapshot ``t`` [s]; None: ``ball.pos_known_3d`` false."""
    msg = BallFlightInfo()
    msg.header.stamp = stamp(t)
    if flight is None:
        msg.ball.header.stamp = msg.header.stamp
        return msg
    msg.ball = ball_info3d_msg(flight.ball, t)
    if flight.touchdown is not None:
        x, y, when = flight.touchdown
        msg.in_air, msg.touchdown_time = True, when
        msg.touchdown.x, msg.touchdown.y = x, y
    return msg


def ball_flight(msg: BallFlightInfo) -> BallFlight | None:
    """The world model's flight back from its message (None when no 3-D ball is known); a touchdown that is
    not finite reads as none (the ball on the ground)."""
    ball = ball3d_percept(msg.ball, seconds(msg.header.stamp))
    if ball is None:
        return None
    down = (float(msg.touchdown.x), float(msg.touchdown.y), float(msg.touchdown_time))
    if not (msg.in_air and all(math.isfinite(v) for v in down)):
        return BallFlight(ball)
    return BallFlight(ball, down)


# --- commands ------------------------------------------------------------------------------------
def velcmd_msg(velocity: BodyVelocity) -> VelCmd:
    return VelCmd(Vx=velocity.vx, Vy=velocity.vy, w=velocity.w)


def body_velocity(msg: VelCmd) -> BodyVelocity:
    return BodyVelocity(msg.Vx, msg.Vy, msg.w)


# --- the world description -------------------------------------------------------------------------
def _fill(msg: Any, value: Any) -> Any:
    for f in dataclasses.fields(value):
        setattr(msg, f.name, getattr(value, f.name))
    return msg


def _read(cls: type, msg: Any) -> Any:
    return cls(**{f.name: getattr(msg, f.name) for f in dataclasses.fields(cls)})


def world_description_msg(world: WorldDescription, t: float) -> WorldDescriptionMsg:
    msg = WorldDescriptionMsg(field=_fill(FieldGeometryMsg(), world.field), ball=_fill(BallBodyMsg(), world.ball),
                              robot=_fill(RobotBodyMsg(), world.robot), ball_name=world.ball_name)
    msg.header.stamp = stamp(t)
    return msg


def world_description(msg: WorldDescriptionMsg) -> WorldDescription:
    try:
        return WorldDescription(_read(FieldGeometry, msg.field), _read(BallBody, msg.ball), _read(RobotBody, msg.robot),
                                msg.ball_name)
    except ValueError as exc:
        raise NubotCommonError(f"bad world description: {exc}") from exc
