"""Unit tests of the chance model the ball carrier weighs (nubot_control.chances) and of where the rules let a field
robot go (nubot_control.areas), team frame on the 18 x 12 m field (goal at +9 m, posts at y = +-1.2 m)."""

import math

import pytest

from nubot_common.field import FieldGeometry
from nubot_control.areas import in_area, keep_out, no_go, stay_out
from nubot_control.chances import ChanceParams, ball_time, lob_chance, pass_margin, shot_chance

F = FieldGeometry()
P = ChanceParams()
GOALIE = (8.6, 0.0)


def test_an_open_goal_from_close_in_is_nearly_sure_and_a_shot_from_the_halfway_line_is_not():
    assert shot_chance((6.0, 0.0), [], F, 10.0, P).chance > 0.95
    far = shot_chance((0.0, 0.0), [GOALIE], F, 10.0, P).chance
    near = shot_chance((5.0, 0.0), [GOALIE], F, 10.0, P).chance
    assert far < 0.35 < near, "from far the scatter and the goalie's time to move spoil the shot"


def test_the_best_aim_is_the_side_the_goalie_leaves_open():
    shot = shot_chance((5.0, 0.0), [(8.6, 0.6)], F, 10.0, P)
    assert shot.aim[1] < -0.5 and shot.chance > 0.5


def test_a_defender_in_the_lane_blocks_the_shot():
    open_lane = shot_chance((5.0, 2.0), [GOALIE], F, 10.0, P).chance
    blocked = shot_chance((5.0, 2.0), [GOALIE, (5.7, 1.65)], F, 10.0, P).chance  # 0.8 m in front, on the way
    assert open_lane > 0.5 and blocked < 0.1


def test_a_wider_scatter_lowers_the_chance():
    tight = shot_chance((3.0, 2.0), [GOALIE], F, 10.0, ChanceParams(kick_direction_std=math.radians(1.0))).chance
    loose = shot_chance((3.0, 2.0), [GOALIE], F, 10.0, ChanceParams(kick_direction_std=math.radians(4.0))).chance
    assert loose < tight


def test_a_lob_flies_over_a_field_defender_but_not_over_the_goalie_or_from_too_far():
    assert lob_chance((4.0, 0.0), [(6.0, 0.0)], F, P) > 0.5
    assert lob_chance((4.0, 0.0), [(6.0, 0.0), (8.9, 0.0)], F, P) < 0.5 * lob_chance((4.0, 0.0), [(6.0, 0.0)], F, P)
    assert lob_chance((-1.0, 0.0), [], F, P) == 0.0, "10 m: the lob falls short"


def test_a_pass_past_a_near_opponent_is_intercepted_and_one_past_a_far_opponent_is_not():
    assert pass_margin((0.0, 0.0), (5.0, 0.0), 6.0, [(2.5, 0.8)], P) > 0.1, "a firm pass beats it"
    assert pass_margin((0.0, 0.0), (5.0, 0.0), 3.0, [(2.5, 0.8)], P) < 0.0, "a slow one does not"
    assert pass_margin((0.0, 0.0), (5.0, 0.0), 6.0, [(1.0, 0.2)], P) < 0.0, "one in its way"
    assert pass_margin((0.0, 0.0), (5.0, 0.0), 6.0, [(2.5, 3.5)], P) > 0.3
    assert ball_time(5.0, 6.0, 0.78) == pytest.approx((6.0 - math.sqrt(36.0 - 2 * 0.78 * 5.0)) / 0.78)
    assert ball_time(30.0, 3.0, 0.78) == math.inf, "a slow pass never gets that far"


def test_targets_keep_out_of_the_areas_the_rules_forbid():
    # the own penalty area: x <= -6.75, |y| <= 3.25; the goal area: x <= -8.25, |y| <= 1.75
    assert in_area(-7.0, 1.0, F, own=True) and not in_area(-6.0, 1.0, F, own=True)
    assert in_area(8.5, 0.0, F, own=False, goal_area=True)
    x, y = keep_out(-7.5, 0.5, F, penalty_areas=True)
    assert not in_area(x, y, F, own=True) and x == pytest.approx(-6.75 + 0.35)
    x, y = keep_out(-7.0, 3.2, F, penalty_areas=True)
    assert (x, y) == pytest.approx((-7.0, 3.25 + 0.35)), "out by the nearer side"
    assert keep_out(-7.5, 0.5, F, penalty_areas=False) == (-7.5, 0.5), "the robot playing the ball may go there"
    x, y = keep_out(8.6, 0.2, F, penalty_areas=False)
    assert not in_area(x, y, F, own=False, goal_area=True)


def test_the_wall_stops_a_robot_at_an_area_and_lets_it_slide_along_it():
    rects = no_go(F, penalty_areas=True)
    # 0.4 m in front of the area (grown by its margin), running straight at it at 3 m/s
    vx, vy = stay_out((-6.0, 0.0), (-3.0, 0.5), rects, 2.0, 0.1)
    assert vx > -1.3 and vy == pytest.approx(0.5)
    assert stay_out((-3.0, 0.0), (-3.0, 0.0), rects, 2.0, 0.1) == (-3.0, 0.0), "far away: no limit"
    inside = stay_out((-7.2, 0.0), (0.0, 0.0), rects, 2.0, 0.1)
    assert inside[0] > 0.5, "from inside it leaves by the nearest side"
