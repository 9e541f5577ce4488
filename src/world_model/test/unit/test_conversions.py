"""The world model's messages (nubot_common.conversions): no ROS master, real generated messages."""

import io
import math

import genpy
import pytest
import yaml
from genpy.message import fill_message_args

from nubot_common import NubotCommonError
from nubot_common import conversions as conv
from nubot_common.msg import (
    BallInfo,
    CoachInfo,
    OmniVisionInfo,
    Point2d,
    PPoint,
    RobotInfo,
    StrategyInfo,
    TargetInfo,
    TeamMessage,
    TeamMessages,
    WorldModelInfo,
)
from nubot_common.team_play import PassCommand, StrategyReport
from nubot_common.world_state import BallSource, ObstacleLabel

CHAPTER_COMMAND = "\nMatchMode: 10\nMatchType: 0 "  # the chapter's rostopic pub argument, as printed


def _round_trip(msg):
    buffer = io.BytesIO()
    msg.serialize(buffer)
    copy = type(msg)()
    copy.deserialize(buffer.getvalue())
    return copy


def test_the_chapter_coach_command_fills_a_coach_info_the_world_model_accepts(make_model):
    msg = CoachInfo()
    fill_message_args(msg, [yaml.safe_load(CHAPTER_COMMAND)])  # what rostopic pub does with it
    mode, match_type, extras = conv.coach_fields(_round_trip(msg))
    assert (mode, match_type) == (10, 0)
    model = make_model()
    model.on_coach(1.0, mode, match_type, extras)
    assert model.game.mode == 10


def test_coach_info_test_fields_are_read():
    msg = CoachInfo(MatchMode=27, MatchType=15, TestMode=3, pointA=Point2d(1.0, 2.0), angleB=-45, idA=2,
                    kickforce=5)
    mode, match_type, extras = conv.coach_fields(_round_trip(msg))
    assert (mode, match_type, extras.test_mode, extras.point_a, extras.angle_b, extras.id_a, extras.kickforce) == \
        (27, 15, 3, (1.0, 2.0), -45, 2, 5)


def _vision_msg(t=12.5, ball=True):
    msg = OmniVisionInfo()
    msg.header.stamp = genpy.Time.from_sec(t)
    if ball:
        msg.ballinfo = BallInfo(ballinfostate=1, pos=Point2d(1.0, 2.0), real_pos=PPoint(0.6, 3.6),
                                velocity=Point2d(0.375, 0.0), pos_known=True, velocity_known=True)
    msg.obstacleinfo.pos = [Point2d(0.0, 2.0), Point2d(4.0, -1.0)]
    me = RobotInfo(AgentID=1, pos=Point2d(-2.0, 0.0), vtrans=Point2d(0.5, 0.0), vrot=0.125, isvalid=True,
                   isdribble=False)
    me.heading.theta = 0.25
    msg.robotinfo = [me]
    return msg


def test_vision_frame_becomes_the_robot_view():
    frame = conv.robot_view(_vision_msg(), now=99.0)
    robot, ball = frame.robot, frame.ball
    assert frame.stamp == 12.5 and robot.agent_id == 1 and robot.valid
    assert (robot.pose.x, robot.pose.y, robot.pose.theta) == pytest.approx((-2.0, 0.0, 0.25))
    assert (ball.stamp, ball.x, ball.y) == (12.5, 1.0, 2.0), "unstamped BallInfo: the frame's time"
    assert frame.obstacles == ((0.0, 2.0), (4.0, -1.0))
    frame = conv.robot_view(_vision_msg(t=0.0, ball=False), now=99.0)
    assert frame.stamp == 99.0 and frame.ball is None


def test_vision_frame_without_the_robot_itself_is_refused():
    msg = _vision_msg()
    msg.robotinfo = []
    with pytest.raises(NubotCommonError, match=r"without robotinfo\[0\]"):
        conv.robot_view(msg, 0.0)


def test_a_frame_published_as_omni_vision_info_reads_back_the_same(make_model):
    frame = conv.robot_view(_vision_msg(), now=99.0)
    again = conv.robot_view(_round_trip(conv.omni_vision_msg(frame)), now=0.0)
    assert again.stamp == frame.stamp and again.robot == frame.robot, "the values are exact in float32"
    assert again.ball == frame.ball and again.obstacles == frame.obstacles


def _fed_model(make_model, see, mate_view):
    model = make_model(agent_id=1)
    model.on_coach(9.0, 10, 0)
    see(model, 10.0, ball=(1.0, 2.0), obstacles=((0.0, 2.1), (4.0, -1.0)))
    model.on_teammate(10.0, mate_view(10.0, 2, 0.0, 2.0, ball=(1.1, 2.0), role=1))
    model.on_strategy(10.0, StrategyReport(10.0, 1, role=0, pass_cmd=PassCommand(1, 2, (-2.0, 0.0), (0.0, 2.0))))
    return model


def test_world_model_info_has_every_robot_and_ball_by_agent_id(make_model, see, mate_view):
    state = _fed_model(make_model, see, mate_view).snapshot(10.02)
    msg = _round_trip(conv.world_model_info_msg(state))
    assert isinstance(msg, WorldModelInfo) and msg.header.stamp.to_sec() == pytest.approx(10.02)
    assert [r.AgentID for r in msg.robotinfo] == [1, 2, 3, 4, 5]
    assert [r.isvalid for r in msg.robotinfo] == [True, True, False, False, False]
    assert msg.robotinfo[1].current_role == 1 and msg.robotinfo[0].current_role == 0
    own, mate = msg.ballinfo[0], msg.ballinfo[1]
    assert (own.ballinfostate, own.pos_known, own.pos.x, own.pos.y) == (BallSource.OWN, True, 1.0, 2.0)
    assert own.real_pos.radius == pytest.approx(math.hypot(3.0, 2.0), abs=1e-5)
    assert (mate.ballinfostate, mate.pos_known) == (BallSource.TEAMMATE, True)
    assert mate.real_pos.radius == pytest.approx(1.1, abs=1e-5), "relative to the teammate that saw it"
    assert [b.pos_known for b in msg.ballinfo[2:]] == [False, False, False]
    assert [c for p in msg.obstacleinfo.pos for c in (p.x, p.y)] == pytest.approx([0.0, 2.1, 4.0, -1.0])
    assert [(p.x, p.y) for p in msg.oppinfo.pos] == [(4.0, -1.0)]
    assert msg.oppinfo.polar_pos[0].radius == pytest.approx(math.hypot(6.0, 1.0), abs=1e-5)
    assert (msg.coachinfo.MatchMode, msg.coachinfo.MatchType) == (10, 0)
    assert (msg.pass_cmd.is_valid, msg.pass_cmd.pass_id, msg.pass_cmd.catch_id) == (True, 1, 2)
    assert [o.label for o in state.obstacles] == [ObstacleLabel.TEAMMATE, ObstacleLabel.OPPONENT]


def test_world_model_info_before_any_input_is_all_unknown(make_model):
    msg = _round_trip(conv.world_model_info_msg(make_model().snapshot(0.5)))
    assert len(msg.robotinfo) == 5 and not any(r.isvalid for r in msg.robotinfo)
    assert (msg.ballinfo[0].ballinfostate, msg.ballinfo[0].pos_known) == (0, False)
    assert (msg.coachinfo.MatchMode, msg.pass_cmd.is_valid) == (0, False)


def test_team_message_round_trips_into_the_teammate_view(make_model, see, mate_view):
    model = _fed_model(make_model, see, mate_view)
    view = model.own_view(10.02)
    msg = _round_trip(conv.team_message_msg(view, 10.02))
    assert isinstance(msg, TeamMessage) and msg.header.stamp.to_sec() == pytest.approx(10.02)
    assert msg.robot.header.stamp.to_sec() == pytest.approx(10.0), "stamped with the vision frame's time"
    assert (msg.ball.ballinfostate, msg.ball.pos_known) == (BallSource.OWN, True)
    (back,) = conv.team_views(TeamMessages(messages=[msg]))
    assert back.stamp == pytest.approx(10.0) and back.robot.agent_id == 1 and back.robot.role == 0
    assert (back.ball.x, back.ball.y) == pytest.approx((1.0, 2.0))
    assert [c for p in back.obstacles for c in p] == pytest.approx([0.0, 2.1, 4.0, -1.0])


def test_strategy_info_becomes_a_strategy_report():
    msg = StrategyInfo(AgentID=2, targetNum1=2, role=9, role_time=3.0, staticpassNum=4, staticcatchNum=2)
    msg.header.stamp = genpy.Time.from_sec(5.0)
    msg.pass_cmd.pass_id, msg.pass_cmd.catch_id, msg.pass_cmd.is_valid = 4, 2, True
    target = conv.target_of(_round_trip(TargetInfo(target=[Point2d(3.5, -1.0)])))
    report = conv.strategy_report(_round_trip(msg), target)
    assert (report.stamp, report.agent_id, report.role, report.role_time) == (5.0, 2, 9, pytest.approx(3.0))
    assert (report.static_pass, report.static_catch, report.target_nums) == (4, 2, (2, 0, 0, 0))
    assert report.target == pytest.approx((3.5, -1.0))
    assert report.pass_cmd.is_valid and (report.pass_cmd.pass_id, report.pass_cmd.catch_id) == (4, 2)
    again = conv.strategy_report(_round_trip(conv.strategy_info_msg(report)), report.target)
    assert again == report
    msg.role = 300
    assert conv.strategy_report(msg).role == 8, "not a char: NOROLE"
