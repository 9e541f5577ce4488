"""Unit tests of the goalie's keep_goal: lobs met where they come down, ground balls on the ball-goal line."""

import math

import pytest

from nubot_common.ball_flight import GRAVITY
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import Ball3dPercept, RobotReport
from nubot_common.world_state import BallFlight, FusedBall
from nubot_control.behaviours import Action, keep_goal
from nubot_control.params import ControlParams, PlayParams
from nubot_control.team_state import TeamState

F = FieldGeometry()
L = F.half_length
R = 0.11


def state(ball: FusedBall, flight: BallFlight | None = None, me=(-L + 0.4, 0.0)) -> TeamState:
    return TeamState(1.0, RobotReport(1, Pose2D(*me, 0.0)), (), ball, (), F, MatchMode.STARTROBOT, flight=flight)


def flying(x, y, z, vx, vy, vz) -> BallFlight:
    return BallFlight.of(Ball3dPercept(1.0, x, y, z, vx, vy, vz, True), R, 0.1)


def test_a_lob_into_the_goal_is_met_on_the_lob_line_where_it_crosses_it():
    params = ControlParams(play=PlayParams(lob_line=-0.2))
    f = flying(-L + 3.0, 1.0, 1.6, -6.0, -0.3, 1.0)  # 3 m out, coming down into the goal, drifting to -y
    assert f.touchdown[0] < -L - 0.2
    intent = keep_goal(state(FusedBall(-L + 3.0, 1.0, -6.0, -0.3), f), params)
    t = (3.0 + 0.2) / 6.0
    assert intent.action == Action.KEEP_GOAL
    assert (intent.target.x, intent.target.y) == pytest.approx((-L - 0.2, 1.0 - 0.3 * t))
    assert intent.target.theta == pytest.approx(math.atan2(1.0 - intent.target.y, 3.2))


def test_a_lob_coming_down_in_front_of_the_goal_is_met_where_it_lands():
    f = flying(-L + 6.0, -1.0, 1.0, -3.0, 0.0, 0.5)
    x, y, _ = f.touchdown
    assert x > -L + 1.0, "lands well in front of the goal"
    intent = keep_goal(state(FusedBall(-L + 6.0, -1.0, -3.0, 0.0), f), ControlParams())
    assert (intent.target.x, intent.target.y) == pytest.approx((x, y))


def test_a_ball_on_the_ground_or_flying_away_or_wide_is_not_a_lob_to_meet():
    params = ControlParams()
    line_x = -L + params.play.goalie_line
    ground = BallFlight.of(Ball3dPercept(1.0, -L + 5.0, 1.0, R, 0.0, 0.0, 0.0, True), R, 0.1)
    away = flying(-L + 5.0, 1.0, 1.0, 4.0, 0.0, 2.0)
    wide = flying(-L + 4.0, 4.0, 1.5, -6.0, 0.0, 1.0)
    for flight in (ground, away, wide):
        intent = keep_goal(state(FusedBall(-L + 5.0, 1.0), flight), params)
        assert intent.target.x == pytest.approx(line_x)


def test_against_a_still_ball_the_goalie_stands_on_the_line_from_the_goal_centre_to_the_ball():
    params = ControlParams()
    line_x = -L + params.play.goalie_line
    ball = FusedBall(-L + 4.0, 2.0)
    intent = keep_goal(state(ball), params)
    # on the segment goal centre -> ball, at the guarded line
    assert intent.target.x == pytest.approx(line_x)
    assert intent.target.y == pytest.approx(2.0 * params.play.goalie_line / 4.0)


def test_a_ground_shot_is_met_where_it_crosses_the_guarded_line():
    params = ControlParams()
    line_x = -L + params.play.goalie_line
    ball = FusedBall(-L + 5.0, 0.0, -8.0, 1.2, velocity_known=True)
    intent = keep_goal(state(ball), params)
    t = (line_x - ball.x) / ball.vx
    assert (intent.target.x, intent.target.y) == pytest.approx((line_x, 1.2 * t))


def test_the_lob_line_must_lie_behind_the_guarded_line():
    with pytest.raises(ValueError, match="lob_line"):
        PlayParams(lob_line=0.5, goalie_line=0.4)


def test_gravity_of_the_flight_is_the_shared_one():
    f = flying(0.0, 0.0, 1.0, -1.0, 0.0, 0.0)
    _, _, when = f.touchdown
    assert when - 1.0 == pytest.approx(math.sqrt(2 * (1.0 - R) / -GRAVITY))


def test_a_ball_dribbled_across_towards_the_goal_leaves_the_goalie_between_ball_and_goal():
    """A slow ball whose line would cross far wide (an opponent dribbling diagonally in) is no shot: the goalie keeps
    its place on the line from the goal's centre to the ball instead of running to a post."""
    params = ControlParams()
    ball = FusedBall(-L + 5.0, -3.0, -1.0, 1.5, velocity_known=True)
    intent = keep_goal(state(ball), params)
    assert intent.target.y == pytest.approx(-3.0 * params.play.goalie_line / 5.0)


def test_a_fast_ball_wide_of_the_goal_or_a_slow_one_at_it_is_no_shot():
    params = ControlParams()
    centre_line = 1.0 * params.play.goalie_line / 6.0
    wide = FusedBall(-L + 6.0, 1.0, -8.0, 4.0, velocity_known=True)  # crosses the line 4.8 m from the centre
    slow = FusedBall(-L + 6.0, 1.0, -1.5, -0.3, velocity_known=True)  # at 1.5 m/s: a dribble
    for ball in (wide, slow):
        assert keep_goal(state(ball), params).target.y == pytest.approx(centre_line)
    shot = FusedBall(-L + 6.0, 1.0, -8.0, -1.0, velocity_known=True)
    t = (params.play.goalie_line - 6.0) / -8.0
    assert keep_goal(state(shot), params).target.y == pytest.approx(1.0 - 1.0 * t)
