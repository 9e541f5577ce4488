"""Unit tests of the message conversions (coach4sim.conversions): round trips through serialisation."""

import io

import pytest
from geometry_msgs.msg import Pose

from coach4sim.conversions import (
    ball_placement,
    game_state_msg,
    score_view,
    watch_view,
    world_from_model_states,
)
from coach4sim.game import GameController
from coach4sim.params import DEFAULT_TEAMS
from nubot_common.conversions import coach_info_msg
from nubot_common.match_mode import MatchMode
from nubot_common.msg import BallInfo, CoachInfo, GameState, ModelStates, Point2d, RobotInfo, WorldModelInfo


def _round_trip(msg):
    buffer = io.BytesIO()
    msg.serialize(buffer)
    copy = type(msg)()
    copy.deserialize(buffer.getvalue())
    return copy


def test_coach_info_carries_mode_previous_and_stamp():
    msg = _round_trip(coach_info_msg(MatchMode.OPP_THROWIN, MatchMode.STARTROBOT, 12.5))
    assert isinstance(msg, CoachInfo)
    assert (msg.MatchMode, msg.MatchType, msg.header.stamp.to_sec()) == (4, 15, 12.5)


def test_game_state_round_trip():
    game = GameController(DEFAULT_TEAMS)
    game.start_half(2)
    game.command("rival", MatchMode.OUR_CORNERKICK)
    game.goal(-1)
    msg = _round_trip(game_state_msg(game.state(), 3.0))
    assert isinstance(msg, GameState)
    assert (list(msg.teams), list(msg.score), list(msg.attack)) == (["nubot", "rival"], [0, 1], [1, -1])
    assert list(msg.match_mode) == [MatchMode.OPP_CORNERKICK, MatchMode.OUR_CORNERKICK]
    assert (msg.half, msg.running, msg.last_event) == (2, False, "OUR_CORNERKICK for rival")
    view = score_view(msg)
    assert (view.teams, view.score, view.half) == (("nubot", "rival"), (0, 1), 2)


def test_model_states_split_into_ball_and_robots():
    msg = ModelStates(name=["nubot1", "football", "rival1"], pose=[Pose(), Pose(), Pose()])
    msg.pose[0].position.x, msg.pose[1].position.y, msg.pose[1].position.z = -2.0, 3.0, 0.11
    msg.pose[2].position.y = 1.5
    ball, robots = world_from_model_states(msg, "football")
    assert ball == (0.0, 3.0, 0.11)
    assert robots == {"nubot1": (-2.0, 0.0), "rival1": (0.0, 1.5)}
    assert world_from_model_states(msg, "ball")[0] is None


def test_ball_placement_is_at_rest_on_the_carpet():
    state = _round_trip(ball_placement("football", 2.0, 5.9, 0.11))
    p = state.pose.position
    assert (state.model_name, state.reference_frame, p.x, p.y, p.z) == ("football", "world", 2.0, 5.9,
                                                                        pytest.approx(0.11))
    assert state.pose.orientation.w == 1.0
    assert (state.twist.linear.x, state.twist.linear.y, state.twist.linear.z) == (0.0, 0.0, 0.0)


def test_watch_view_from_a_world_model():
    wm = WorldModelInfo()
    wm.header.stamp.secs = 7
    me, mate, gone = RobotInfo(AgentID=2, isvalid=True), RobotInfo(AgentID=1, isvalid=True), RobotInfo(AgentID=3)
    me.pos, me.heading.theta, mate.pos = Point2d(1.0, -1.0), 0.5, Point2d(-3.0, 2.0)
    wm.robotinfo = [mate, me, gone]
    # nubot2's world model fused the ball nubot1 sees (ballinfostate 2: from a teammate).
    wm.ballinfo = [BallInfo(pos=Point2d(4.0, 0.0), pos_known=True, ballinfostate=1),
                   BallInfo(pos=Point2d(4.0, 0.0), pos_known=True, ballinfostate=2), BallInfo()]
    wm.oppinfo.pos = [Point2d(5.0, 5.0)]
    wm.obstacleinfo.pos = [Point2d(5.0, 5.0)]
    wm.coachinfo = CoachInfo(MatchMode=15, MatchType=3)
    view = watch_view("nubot2", wm, None)
    assert view.pose == pytest.approx((1.0, -1.0, 0.5))
    assert view.teammates == ((1, -3.0, 2.0),), "invalid teammates are left out"
    assert (view.ball, view.ball_source) == ((4.0, 0.0), "team"), "nubot2 does not see it; nubot1 does"
    assert (view.opponents, view.mode, view.previous, view.stamp, view.score) == (((5.0, 5.0),), 15, 3, 7.0, None)
    wm.ballinfo[1] = BallInfo(pos=Point2d(2.0, 1.0), pos_known=True, ballinfostate=1)
    assert watch_view("nubot2", wm, GameState(teams=["nubot"], score=[1])).ball_source == "own"
    wm.ballinfo[1] = BallInfo(pos=Point2d(2.0, 1.0), pos_known=False)
    assert watch_view("nubot2", wm, None).ball is None, "the world model lost it: the watch shows no ball"
