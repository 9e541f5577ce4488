"""Conversions between ROS messages and the control core (WorldModelInfo -> TeamState, outputs -> messages).

Requires: generated ``nubot_common`` messages (no rospy).
"""

from __future__ import annotations

import genpy

from nubot_common.conversions import char_value
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.msg import PassCommands, Point2d, StrategyInfo, VelCmd, WorldModelInfo
from nubot_control.roles import Role
from nubot_control.strategy import ControlOutput
from nubot_control.team_state import Ball, Mate, PassPlan, TeamState


def _role(value: int) -> Role:
    try:
        return Role(value)
    except ValueError:
        return Role.NOROLE


def mode_of(msg: WorldModelInfo) -> tuple[MatchMode, MatchMode]:
    """The current and previous game command; an unknown value reads as STOPROBOT (stay safe)."""
    def parse(value: int | bytes | str) -> MatchMode:
        try:
            return parse_match_mode(char_value(value))
        except ValueError:
            return MatchMode.STOPROBOT
    return parse(msg.coachinfo.MatchMode), parse(msg.coachinfo.MatchType)


def team_state(msg: WorldModelInfo, agent_id: int, time: float, mode_since: float, goalie_id: int,
               pass_plan: PassPlan | None, playing: set[int] | None = None) -> TeamState | None:
    """The strategy's view of one WorldModelInfo; None while the robot does not know where it is.

    ``playing`` holds the AgentIDs whose control is alive (their strategy is being relayed);
    a teammate outside it is left out, so the others take over its role. None: everyone plays.
    """
    index = agent_id - 1
    if index >= len(msg.robotinfo) or not msg.robotinfo[index].isvalid:
        return None
    mates = []
    me = None
    for i, info in enumerate(msg.robotinfo):
        if not info.isvalid or (playing is not None and i != index and i + 1 not in playing):
            continue
        mate = Mate(i + 1, Pose2D(info.pos.x, info.pos.y, info.heading.theta), info.vtrans.x, info.vtrans.y,
                    _role(char_value(info.current_role)), info.role_time, info.isdribble, True)
        if i == index:
            me = mate
        else:
            mates.append(mate)
    assert me is not None
    ball_info = msg.ballinfo[index] if index < len(msg.ballinfo) else None
    if ball_info is not None and ball_info.pos_known:
        ball = Ball(ball_info.pos.x, ball_info.pos.y, ball_info.velocity.x, ball_info.velocity.y, True)
    else:
        ball = Ball(me.pose.x + 1.0, me.pose.y, 0.0, 0.0, False)
    opponents = tuple((p.x, p.y) for p in msg.oppinfo.pos)
    mode, previous = mode_of(msg)
    return TeamState(time, me, tuple(mates), ball, opponents, mode, previous, mode_since, pass_plan, goalie_id)


def pass_plan_from(commands: list[PassCommands]) -> PassPlan | None:
    """The valid pass command among the team's strategies, if any."""
    for cmd in commands:
        if cmd.is_valid and cmd.catch_id > 0:
            return PassPlan(cmd.pass_id, cmd.catch_id, cmd.catch_pt.x, cmd.catch_pt.y, cmd.is_passout)
    return None


def velcmd_msg(out: ControlOutput) -> VelCmd:
    return VelCmd(Vx=out.vx, Vy=out.vy, w=out.w)


def strategy_msg(out: ControlOutput, agent_id: int, time: float, role_time: float, holding: bool,
                 kickoff: bool) -> StrategyInfo:
    msg = StrategyInfo()
    msg.header.stamp = genpy.Time.from_sec(time)
    msg.AgentID = agent_id
    roles = out.role_of or {}
    by_role = {role: aid for aid, role in roles.items()}
    msg.targetNum1 = by_role.get(Role.ACTIVE, 0)
    msg.targetNum2 = by_role.get(Role.PASSIVE, 0)
    msg.targetNum3 = by_role.get(Role.ASSISTANT, 0)
    msg.targetNum4 = by_role.get(Role.MIDFIELD, 0)
    msg.staticpassNum, msg.staticcatchNum = out.static_pass
    msg.role = int(out.role)
    msg.action = int(out.action)
    msg.is_dribble = holding
    msg.is_kickoff = kickoff
    msg.role_time = role_time
    msg.target = Point2d(*out.target)
    if out.pass_plan is not None:
        p = out.pass_plan
        msg.pass_cmd = PassCommands(p.passer, p.catcher, Point2d(0.0, 0.0), Point2d(p.catch_x, p.catch_y),
                                    p.kicked, True, False, True)
    return msg
