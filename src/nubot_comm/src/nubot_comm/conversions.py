"""ROS messages <-> LCM packets of the team link, field by field (the only module that knows both).

Requires: the generated ``nubot_common`` messages and ``genpy`` (no rospy), ``nubot_lcm``.
Provides: ``team_packet`` (a robot's TeamMessage and StrategyInfo -> the content of a team packet),
``team_message``/``strategy_info`` (a team packet -> the two messages again), ``coach_packet``/``coach_info``
(CoachInfo both ways). Everything the messages carry travels, except the headers' ``seq`` (rospy numbers
each publisher's messages itself) and ``frame_id`` (the team's field frame, by convention, for all of them).
Stamps travel as nanoseconds; ROS ``char`` fields leave as int (``nubot_common.conversions.char_value``).
"""

from __future__ import annotations

import genpy

from nubot_common.conversions import char_value, point2d, ppoint
from nubot_common.msg import (
    Angle,
    BallInfo,
    CoachInfo,
    ObstaclesInfo,
    PassCommands,
    Point2d,
    PPoint,
    RobotInfo,
    StrategyInfo,
    TeamMessage,
)
from nubot_lcm import (
    ball_info_t,
    coach_info_t,
    coach_packet_t,
    obstacles_info_t,
    pass_commands_t,
    point2d_t,
    ppoint_t,
    robot_info_t,
    strategy_info_t,
    team_packet_t,
)

_TARGET_NUMS = ("targetNum1", "targetNum2", "targetNum3", "targetNum4", "staticpassNum", "staticcatchNum")
_NS = 1_000_000_000


# --- plain fields --------------------------------------------------------------------------------------
def nanoseconds(stamp: genpy.Time) -> int:
    return int(stamp.secs) * _NS + int(stamp.nsecs)


def ros_time(ns: int) -> genpy.Time:
    secs, nsecs = divmod(int(ns), _NS)
    return genpy.Time(secs, nsecs)


def _point(p: Point2d) -> point2d_t:
    out = point2d_t()
    out.x, out.y = float(p.x), float(p.y)
    return out


def _point_msg(p: point2d_t) -> Point2d:
    return point2d(p.x, p.y)


def _polar(p: PPoint) -> ppoint_t:
    out = ppoint_t()
    out.angle, out.radius = float(p.angle), float(p.radius)
    return out


def _polar_msg(p: ppoint_t) -> PPoint:
    return ppoint(p.angle, p.radius)


# --- team packet ---------------------------------------------------------------------------------------
def team_packet(message: TeamMessage, strategy: StrategyInfo) -> team_packet_t:
    """The content of this robot's team packet; ``TeamLink.send_team`` adds the envelope."""
    packet = team_packet_t()
    packet.message_stamp_ns = nanoseconds(message.header.stamp)
    packet.robot = _robot(message.robot)
    packet.ball = _ball(message.ball)
    packet.obstacles = _obstacles(message.obstacles)
    packet.strategy = _strategy(strategy)
    return packet


def team_message(packet: team_packet_t) -> TeamMessage:
    msg = TeamMessage(robot=_robot_msg(packet.robot), ball=_ball_msg(packet.ball),
                      obstacles=_obstacles_msg(packet.obstacles))
    msg.header.stamp = ros_time(packet.message_stamp_ns)
    return msg


def strategy_info(packet: team_packet_t) -> StrategyInfo:
    s = packet.strategy
    msg = StrategyInfo(AgentID=s.AgentID, role=s.role, action=s.action, is_dribble=s.is_dribble,
                       is_kickoff=s.is_kickoff, role_time=s.role_time, pass_cmd=_pass_msg(s.pass_cmd))
    for name in _TARGET_NUMS:
        setattr(msg, name, getattr(s, name))
    msg.header.stamp = ros_time(s.stamp_ns)
    return msg


def _robot(msg: RobotInfo) -> robot_info_t:
    out = robot_info_t()
    out.stamp_ns, out.AgentID = nanoseconds(msg.header.stamp), int(msg.AgentID)
    for name in _TARGET_NUMS:
        setattr(out, name, int(getattr(msg, name)))
    out.pos, out.heading, out.vrot = _point(msg.pos), float(msg.heading.theta), float(msg.vrot)
    out.vtrans, out.target = _point(msg.vtrans), _point(msg.target)
    out.iskick, out.isvalid = bool(msg.iskick), bool(msg.isvalid)
    out.isstuck, out.isdribble = bool(msg.isstuck), bool(msg.isdribble)
    out.current_role, out.role_time = char_value(msg.current_role), float(msg.role_time)
    return out


def _robot_msg(r: robot_info_t) -> RobotInfo:
    msg = RobotInfo(AgentID=r.AgentID, pos=_point_msg(r.pos), heading=Angle(r.heading), vrot=r.vrot,
                    vtrans=_point_msg(r.vtrans), iskick=r.iskick, isvalid=r.isvalid, isstuck=r.isstuck,
                    isdribble=r.isdribble, current_role=r.current_role, role_time=r.role_time,
                    target=_point_msg(r.target))
    for name in _TARGET_NUMS:
        setattr(msg, name, getattr(r, name))
    msg.header.stamp = ros_time(r.stamp_ns)
    return msg


def _ball(msg: BallInfo) -> ball_info_t:
    out = ball_info_t()
    out.stamp_ns, out.ballinfostate = nanoseconds(msg.header.stamp), int(msg.ballinfostate)
    out.pos, out.real_pos, out.velocity = _point(msg.pos), _polar(msg.real_pos), _point(msg.velocity)
    out.pos_known, out.velocity_known = bool(msg.pos_known), bool(msg.velocity_known)
    return out


def _ball_msg(b: ball_info_t) -> BallInfo:
    msg = BallInfo(ballinfostate=b.ballinfostate, pos=_point_msg(b.pos), real_pos=_polar_msg(b.real_pos),
                   velocity=_point_msg(b.velocity), pos_known=b.pos_known, velocity_known=b.velocity_known)
    msg.header.stamp = ros_time(b.stamp_ns)
    return msg


def _obstacles(msg: ObstaclesInfo) -> obstacles_info_t:
    out = obstacles_info_t()
    out.stamp_ns = nanoseconds(msg.header.stamp)
    out.pos = [_point(p) for p in msg.pos]
    out.polar_pos = [_polar(p) for p in msg.polar_pos]
    out.num_pos, out.num_polar_pos = len(out.pos), len(out.polar_pos)
    return out


def _obstacles_msg(o: obstacles_info_t) -> ObstaclesInfo:
    msg = ObstaclesInfo(pos=[_point_msg(p) for p in o.pos], polar_pos=[_polar_msg(p) for p in o.polar_pos])
    msg.header.stamp = ros_time(o.stamp_ns)
    return msg


def _strategy(msg: StrategyInfo) -> strategy_info_t:
    out = strategy_info_t()
    out.stamp_ns, out.AgentID = nanoseconds(msg.header.stamp), int(msg.AgentID)
    for name in _TARGET_NUMS:
        setattr(out, name, int(getattr(msg, name)))
    out.role, out.action = int(msg.role), int(msg.action)
    out.is_dribble, out.is_kickoff, out.role_time = bool(msg.is_dribble), bool(msg.is_kickoff), float(msg.role_time)
    out.pass_cmd = _pass(msg.pass_cmd)
    return out


def _pass(msg: PassCommands) -> pass_commands_t:
    out = pass_commands_t()
    out.pass_id, out.catch_id = int(msg.pass_id), int(msg.catch_id)
    out.pass_pt, out.catch_pt = _point(msg.pass_pt), _point(msg.catch_pt)
    out.is_passout, out.is_dynamic_pass, out.is_static_pass, out.is_valid = (
        bool(msg.is_passout), bool(msg.is_dynamic_pass), bool(msg.is_static_pass), bool(msg.is_valid))
    return out


def _pass_msg(p: pass_commands_t) -> PassCommands:
    return PassCommands(p.pass_id, p.catch_id, _point_msg(p.pass_pt), _point_msg(p.catch_pt), p.is_passout,
                        p.is_dynamic_pass, p.is_static_pass, p.is_valid)


# --- coach packet --------------------------------------------------------------------------------------
def coach_packet(msg: CoachInfo) -> coach_packet_t:
    """The content of a coach packet; ``TeamLink.send_coach`` adds the envelope."""
    c = coach_info_t()
    c.stamp_ns = nanoseconds(msg.header.stamp)
    c.MatchMode, c.MatchType, c.TestMode = (char_value(msg.MatchMode), char_value(msg.MatchType),
                                            char_value(msg.TestMode))
    c.pointA, c.pointB, c.angleA, c.angleB = _point(msg.pointA), _point(msg.pointB), int(msg.angleA), int(msg.angleB)
    c.idA, c.idB, c.kickforce = char_value(msg.idA), char_value(msg.idB), char_value(msg.kickforce)
    packet = coach_packet_t()
    packet.coach = c
    return packet


def coach_info(packet: coach_packet_t) -> CoachInfo:
    c = packet.coach
    msg = CoachInfo(MatchMode=c.MatchMode, MatchType=c.MatchType, TestMode=c.TestMode, pointA=_point_msg(c.pointA),
                    pointB=_point_msg(c.pointB), angleA=c.angleA, angleB=c.angleB, idA=c.idA, idB=c.idB,
                    kickforce=c.kickforce)
    msg.header.stamp = ros_time(c.stamp_ns)
    return msg
