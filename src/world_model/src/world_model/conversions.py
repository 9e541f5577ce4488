"""Conversions between ROS messages and the world model's core types (the only place that knows both).

Requires: generated ``nubot_common`` messages and ``genpy`` (no rospy). Provides:
message -> core (``vision_inputs``, ``teammate_views``, ``coach_inputs``,
``strategy_report``) and core -> message (``world_model_info_msg``, ``team_message_msg``).
A zero header stamp means "not stamped": the core then uses the time of arrival.
``char`` fields arrive as int (or one byte) and leave as int.
"""

from __future__ import annotations

import math

import genpy

from nubot_common.conversions import char_value
from nubot_common.geometry import Pose2D
from nubot_common.msg import (
    BallInfo,
    CoachInfo,
    ObstaclesInfo,
    OmniVisionInfo,
    PassCommands,
    Point2d,
    PPoint,
    RobotInfo,
    StrategyInfo,
    TeamMessage,
    TeamMessages,
    WorldModelInfo,
)
from world_model import WorldModelError
from world_model.state import (
    NO_ROLE,
    BallObservation,
    BallSource,
    CoachExtras,
    FusedBall,
    PassCommand,
    Point,
    RobotReport,
    RobotView,
    StrategyReport,
    Teammate,
    WorldState,
)

_CHAR_MAX = 255


def stamp(t: float) -> genpy.Time:
    return genpy.Time.from_sec(t) if math.isfinite(t) and t > 0.0 else genpy.Time()


def _sec(time: genpy.Time) -> float:
    return time.to_sec()


def _role(value: int | bytes | str) -> int:
    role = char_value(value)
    return role if 0 <= role <= _CHAR_MAX else NO_ROLE


# --- messages -> core --------------------------------------------------------------------
def robot_report(info: RobotInfo) -> RobotReport:
    return RobotReport(
        agent_id=int(info.AgentID), pose=Pose2D(info.pos.x, info.pos.y, info.heading.theta),
        vx=info.vtrans.x, vy=info.vtrans.y, w=info.vrot, valid=bool(info.isvalid), stuck=bool(info.isstuck),
        dribble=bool(info.isdribble), kick=bool(info.iskick), role=_role(info.current_role), role_time=info.role_time,
        target_nums=(info.targetNum1, info.targetNum2, info.targetNum3, info.targetNum4),
        static_pass=info.staticpassNum, static_catch=info.staticcatchNum, target=(info.target.x, info.target.y))


def ball_observation(ball: BallInfo, fallback: float) -> BallObservation | None:
    """The ball of a BallInfo if its position is known; stamped ``fallback`` when the message is not."""
    if not ball.pos_known:
        return None
    t = _sec(ball.header.stamp) or fallback
    return BallObservation(t, ball.pos.x, ball.pos.y, ball.velocity.x, ball.velocity.y, bool(ball.velocity_known))


def vision_inputs(msg: OmniVisionInfo, now: float) -> tuple[float, RobotReport, BallObservation | None, list[Point]]:
    """(t, robot, ball, obstacles) for ``WorldModel.on_vision``; ``robotinfo[0]`` is the robot itself."""
    if not msg.robotinfo:
        raise WorldModelError("OmniVisionInfo without robotinfo[0] (the robot itself)")
    t = _sec(msg.header.stamp) or now
    return t, robot_report(msg.robotinfo[0]), ball_observation(msg.ballinfo, t), \
        [(p.x, p.y) for p in msg.obstacleinfo.pos]


def teammate_views(msg: TeamMessages) -> list[RobotView]:
    """One view per relayed message, stamped by the sender's robot state (0: unknown, use arrival)."""
    views = []
    for m in msg.messages:
        t = _sec(m.robot.header.stamp) or _sec(m.header.stamp)
        views.append(RobotView(t, robot_report(m.robot), ball_observation(m.ball, t),
                               tuple((p.x, p.y) for p in m.obstacles.pos)))
    return views


def coach_inputs(msg: CoachInfo) -> tuple[int, int, CoachExtras]:
    """(MatchMode, MatchType, extras) for ``WorldModel.on_coach``."""
    extras = CoachExtras(char_value(msg.TestMode), (msg.pointA.x, msg.pointA.y), (msg.pointB.x, msg.pointB.y),
                         int(msg.angleA), int(msg.angleB), char_value(msg.idA), char_value(msg.idB),
                         char_value(msg.kickforce))
    return char_value(msg.MatchMode), char_value(msg.MatchType), extras


def pass_command(msg: PassCommands) -> PassCommand:
    return PassCommand(msg.pass_id, msg.catch_id, (msg.pass_pt.x, msg.pass_pt.y), (msg.catch_pt.x, msg.catch_pt.y),
                       bool(msg.is_passout), bool(msg.is_dynamic_pass), bool(msg.is_static_pass), bool(msg.is_valid))


def strategy_report(msg: StrategyInfo) -> StrategyReport:
    return StrategyReport(
        _sec(msg.header.stamp), int(msg.AgentID), _role(msg.role), msg.role_time,
        (msg.targetNum1, msg.targetNum2, msg.targetNum3, msg.targetNum4), msg.staticpassNum, msg.staticcatchNum,
        bool(msg.is_dribble), pass_command(msg.pass_cmd), (msg.target.x, msg.target.y))


# --- core -> messages --------------------------------------------------------------------
def robot_info_msg(report: RobotReport | None, agent_id: int, valid: bool, t: float) -> RobotInfo:
    info = RobotInfo()
    info.header.stamp = stamp(t)
    info.AgentID = agent_id
    info.isvalid = valid
    if report is None:
        return info
    r = report
    info.targetNum1, info.targetNum2, info.targetNum3, info.targetNum4 = r.target_nums
    info.staticpassNum, info.staticcatchNum = r.static_pass, r.static_catch
    info.pos = Point2d(r.pose.x, r.pose.y)
    info.heading.theta = r.pose.theta
    info.vrot = r.w
    info.vtrans = Point2d(r.vx, r.vy)
    info.iskick, info.isstuck, info.isdribble = r.kick, r.stuck, r.dribble
    info.current_role = r.role
    info.role_time = r.role_time
    info.target = Point2d(*r.target)
    return info


def _teammate_info(mate: Teammate, now: float) -> RobotInfo:
    return robot_info_msg(mate.report, mate.agent_id, mate.valid, now - mate.age if math.isfinite(mate.age) else 0.0)


def _observed_ball_msg(obs: BallObservation | None, state: BallSource, observer: Pose2D | None) -> BallInfo:
    ball = BallInfo()
    if obs is None:
        return ball
    ball.header.stamp = stamp(obs.stamp)
    ball.ballinfostate = int(state)
    ball.pos, ball.velocity = Point2d(obs.x, obs.y), Point2d(obs.vx, obs.vy)
    if observer is not None:
        ball.real_pos = PPoint(observer.bearing_to(obs.x, obs.y), observer.distance_to(obs.x, obs.y))
    ball.pos_known, ball.velocity_known = True, obs.velocity_known
    return ball


def fused_ball_msg(fused: FusedBall) -> BallInfo:
    ball = BallInfo()
    ball.header.stamp = stamp(fused.stamp)
    ball.ballinfostate = int(fused.source)
    ball.pos, ball.velocity = Point2d(fused.x, fused.y), Point2d(fused.vx, fused.vy)
    ball.real_pos = PPoint(fused.angle, fused.radius)
    ball.pos_known, ball.velocity_known = fused.known, fused.velocity_known
    return ball


def _obstacles_msg(points: list[tuple[float, float, float, float]], t: float) -> ObstaclesInfo:
    msg = ObstaclesInfo()
    msg.header.stamp = stamp(t)
    msg.pos = [Point2d(x, y) for x, y, _, _ in points]
    msg.polar_pos = [PPoint(angle, radius) for _, _, angle, radius in points]
    return msg


def pass_commands_msg(cmd: PassCommand | None) -> PassCommands:
    if cmd is None:
        return PassCommands()  # is_valid false
    return PassCommands(cmd.pass_id, cmd.catch_id, Point2d(*cmd.pass_pt), Point2d(*cmd.catch_pt), cmd.is_passout,
                        cmd.is_dynamic_pass, cmd.is_static_pass, cmd.is_valid)


def world_model_info_msg(state: WorldState) -> WorldModelInfo:
    msg = WorldModelInfo()
    msg.header.stamp = stamp(state.stamp)
    every = [(o.x, o.y, o.angle, o.radius) for o in state.obstacles]
    opponents = [(o.x, o.y, o.angle, o.radius) for o in state.opponents]
    msg.obstacleinfo, msg.oppinfo = _obstacles_msg(every, state.stamp), _obstacles_msg(opponents, state.stamp)
    msg.robotinfo = [_teammate_info(r, state.stamp) for r in state.robots]
    msg.ballinfo = [fused_ball_msg(state.ball) if r.agent_id == state.agent_id else
                    _observed_ball_msg(state.team_balls[r.agent_id - 1], BallSource.TEAMMATE, r.pose)
                    for r in state.robots]
    game = state.game
    coach = CoachInfo()
    coach.header.stamp = stamp(game.stamp)
    coach.MatchMode, coach.MatchType = int(game.mode), int(game.previous)
    e = game.command.extras
    coach.TestMode = e.test_mode
    coach.pointA, coach.pointB = Point2d(*e.point_a), Point2d(*e.point_b)
    coach.angleA, coach.angleB, coach.idA, coach.idB, coach.kickforce = e.angle_a, e.angle_b, e.id_a, e.id_b, \
        e.kickforce
    msg.coachinfo = coach
    msg.pass_cmd = pass_commands_msg(state.pass_cmd)
    return msg


def team_message_msg(view: RobotView, t: float) -> TeamMessage:
    """This robot's shared state, produced at ``t``; the robot part is stamped with its vision frame's time."""
    msg = TeamMessage()
    msg.header.stamp = stamp(t)
    me = view.robot.pose
    msg.robot = robot_info_msg(view.robot, view.robot.agent_id, view.robot.valid, view.stamp)
    msg.ball = _observed_ball_msg(view.ball, BallSource.OWN, me)
    msg.obstacles = _obstacles_msg([(x, y, me.bearing_to(x, y), me.distance_to(x, y)) for x, y in view.obstacles],
                                   view.stamp)
    return msg
