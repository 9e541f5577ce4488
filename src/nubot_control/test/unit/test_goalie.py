"""Unit tests of the goalie's keep_goal: lobs met where they come down, shots met on their line at once, and its
spot against a still ball (goalie_spot: on the bisector of the angle the goal makes at the ball)."""

import math

import pytest

from nubot_common.ball_flight import GRAVITY
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_common.percepts import Ball3dPercept, RobotReport
from nubot_common.world_state import BallFlight, FusedBall
from nubot_control.behaviours import Action, goalie_spot, keep_goal
from nubot_control.chances import ChanceParams, shot_chance
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
    spot = goalie_spot((-L + 5.0, 1.0), F, params.play.goalie_line)
    ground = BallFlight.of(Ball3dPercept(1.0, -L + 5.0, 1.0, R, 0.0, 0.0, 0.0, True), R, 0.1)
    away = flying(-L + 5.0, 1.0, 1.0, 4.0, 0.0, 2.0)
    wide = flying(-L + 4.0, 4.0, 1.5, -6.0, 0.0, 1.0)
    for flight in (ground, away, wide):
        intent = keep_goal(state(FusedBall(-L + 5.0, 1.0), flight), params)
        assert (intent.target.x, intent.target.y) == pytest.approx(spot)


def _off_the_bisector(ball, spot) -> float:
    """How far [rad] the line from the ball through ``spot`` is off the bisector of the angle the goal makes at the
    ball."""
    ux = uy = 0.0
    for post in (F.goal_width / 2, -F.goal_width / 2):
        d = math.hypot(-L - ball[0], post - ball[1])
        ux, uy = ux + (-L - ball[0]) / d, uy + (post - ball[1]) / d
    sx, sy = spot[0] - ball[0], spot[1] - ball[1]
    return abs(math.atan2(ux * sy - uy * sx, ux * sx + uy * sy))


@pytest.mark.parametrize("ball", [(-L + 4.0, 0.0), (-L + 4.0, 2.0), (-L + 3.0, -2.5), (-L + 6.5, 3.0), (-L + 8.0, -1.0),
                                  (-L + 5.0, 4.0)])
def test_against_a_still_ball_the_goalie_stands_on_the_bisector_of_the_angle_the_goal_makes_at_it(ball):
    params = ControlParams()
    play = params.play
    spot = goalie_spot(ball, F, play.goalie_line)
    assert spot[0] == pytest.approx(-L + play.goalie_line)
    assert _off_the_bisector(ball, spot) < 1e-6

    def shooters_chance(keeper) -> float:  # the shooter's frame has the goal at +x
        return shot_chance((-ball[0], -ball[1]), [(-keeper[0], -keeper[1])], F, play.shot_speed, ChanceParams()).chance

    on_the_centre_line = (-L + play.goalie_line, ball[1] * play.goalie_line / (ball[0] + L))
    assert shooters_chance(spot) <= shooters_chance(on_the_centre_line) + 1e-9, \
        "from the ball the goal looks no more open than with the goalie on the line to the goal's centre"


def test_the_goalie_keeps_within_the_posts_and_on_the_ball_s_side_of_a_ball_level_with_it():
    line = ControlParams().play.goalie_line
    inside = F.goal_width / 2 - 0.2
    assert goalie_spot((-L + 0.5, 3.0), F, line)[1] == pytest.approx(inside)
    assert goalie_spot((-L + 0.2, -0.5), F, line) == pytest.approx((-L + line, -0.5))


def test_a_ground_shot_is_met_on_its_line_the_shortest_way_and_at_once():
    params = ControlParams()
    me = (-L + 0.6, 0.2)
    ball = FusedBall(-L + 5.0, 0.0, -8.0, 1.2, velocity_known=True)
    intent = keep_goal(state(ball, me=me), params)
    assert intent.urgent, "no plan: straight there"
    speed = math.hypot(ball.vx, ball.vy)
    ux, uy = ball.vx / speed, ball.vy / speed
    ahead = (me[0] - ball.x) * ux + (me[1] - ball.y) * uy
    foot = (ball.x + ux * ahead, ball.y + uy * ahead)  # where the goalie's perpendicular meets the ball's line
    assert (intent.target.x, intent.target.y) == pytest.approx(foot)


def test_a_ball_dribbled_across_towards_the_goal_leaves_the_goalie_at_its_spot():
    """A slow ball whose line would cross far wide (an opponent dribbling diagonally in) is no shot: the goalie keeps
    its spot between ball and goal instead of running to a post."""
    params = ControlParams()
    ball = FusedBall(-L + 5.0, -3.0, -1.0, 1.5, velocity_known=True)
    intent = keep_goal(state(ball), params)
    assert not intent.urgent
    spot = goalie_spot((ball.x, ball.y), F, params.play.goalie_line)
    assert (intent.target.x, intent.target.y) == pytest.approx(spot)


def test_a_fast_ball_wide_of_the_goal_or_a_slow_one_at_it_is_no_shot():
    params = ControlParams()
    spot = goalie_spot((-L + 6.0, 1.0), F, params.play.goalie_line)
    wide = FusedBall(-L + 6.0, 1.0, -8.0, 4.0, velocity_known=True)  # crosses the line 4.8 m from the centre
    slow = FusedBall(-L + 6.0, 1.0, -1.5, -0.3, velocity_known=True)  # at 1.5 m/s: a dribble
    for ball in (wide, slow):
        intent = keep_goal(state(ball), params)
        assert (intent.target.x, intent.target.y) == pytest.approx(spot) and not intent.urgent
    shot = FusedBall(-L + 6.0, 1.0, -8.0, -1.0, velocity_known=True)
    assert keep_goal(state(shot), params).urgent


def test_the_lob_line_must_lie_behind_the_guarded_line():
    with pytest.raises(ValueError, match="lob_line"):
        PlayParams(lob_line=0.5, goalie_line=0.4)


def test_gravity_of_the_flight_is_the_shared_one():
    f = flying(0.0, 0.0, 1.0, -1.0, 0.0, 0.0)
    _, _, when = f.touchdown
    assert when - 1.0 == pytest.approx(math.sqrt(2 * (1.0 - R) / -GRAVITY))
