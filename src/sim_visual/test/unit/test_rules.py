"""Unit tests of the model plugin's rules (sim_visual.rules)."""

import math

import pytest

from nubot_common.ball_flight import height_at, landing
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from sim_visual import SimVisualError
from sim_visual.params import PluginParams
from sim_visual.rules import (
    clamp_command,
    dribble_condition,
    ground_pass_velocity,
    held_ball_position,
    held_ball_velocity,
    lob_velocity,
)

P = PluginParams()
R = 0.11


def test_command_within_limits_is_kept():
    cmd, clamped = clamp_command(1.0, -0.5, 2.0, P)
    assert (cmd.vx, cmd.vy, cmd.w, clamped) == (1.0, -0.5, 2.0, False)


def test_command_beyond_limits_is_clamped_keeping_direction():
    cmd, clamped = clamp_command(30.0, 40.0, -50.0, P)
    assert clamped
    assert math.hypot(cmd.vx, cmd.vy) == pytest.approx(P.max_linear_speed)
    assert cmd.vy / cmd.vx == pytest.approx(40.0 / 30.0)
    assert cmd.w == -P.max_angular_speed


@pytest.mark.parametrize("bad", [(math.nan, 0, 0), (0, math.inf, 0), (0, 0, -math.inf)])
def test_non_finite_command_is_rejected(bad):
    with pytest.raises(SimVisualError, match="must be finite"):
        clamp_command(*bad, P)


def test_dribble_condition_distance_and_angle():
    robot = Pose2D(0.0, 0.0, 0.0)
    assert dribble_condition(robot, 0.45, 0.0, R, R, P)
    assert not dribble_condition(robot, 0.55, 0.0, R, R, P), "beyond the 0.5 m threshold"
    half = math.radians(P.dribble_angle_deg / 2)
    inside = 0.45 * math.cos(half * 0.9), 0.45 * math.sin(half * 0.9)
    outside = 0.45 * math.cos(half * 1.2), 0.45 * math.sin(half * 1.2)
    assert dribble_condition(robot, *inside, R, R, P)
    assert not dribble_condition(robot, *outside, R, R, P), "outside the 30 deg cone"
    assert not dribble_condition(robot, -0.4, 0.0, R, R, P), "behind the robot"
    assert not dribble_condition(robot, 0.4, 0.0, 0.5, R, P), "ball in the air"


def test_dribble_condition_follows_robot_heading():
    robot = Pose2D(1.0, 1.0, math.pi / 2)
    assert dribble_condition(robot, 1.0, 1.45, R, R, P)
    assert not dribble_condition(robot, 1.45, 1.0, R, R, P)


def test_held_ball_sits_ahead_and_moves_with_a_turning_robot():
    robot = Pose2D(2.0, -1.0, math.pi / 2)
    x, y = held_ball_position(robot, P)
    assert (x, y) == pytest.approx((2.0, -1.0 + P.hold_distance))
    vx, vy = held_ball_velocity(robot, 0.0, 0.0, 1.0, P)  # turning CCW at 1 rad/s
    assert (vx, vy) == pytest.approx((-P.hold_distance, 0.0))


def test_ground_pass_has_the_strength_as_speed_in_the_plane():
    vx, vy, vz = ground_pass_velocity(math.radians(30), 6, P)
    assert math.hypot(vx, vy) == pytest.approx(6.0)
    assert math.atan2(vy, vx) == pytest.approx(math.radians(30))
    assert vz == 0.0
    assert math.hypot(*ground_pass_velocity(0.0, 50, P)[:2]) == P.kick_max_speed
    with pytest.raises(SimVisualError, match="positive speed"):
        ground_pass_velocity(0.0, 0, P)


@pytest.mark.parametrize("start_x,start_y,heading", [(3.0, 0.0, 0.0), (4.0, 1.0, -0.05), (2.5, -1.0, 0.12)])
def test_lob_crosses_the_goal_line_between_posts_under_the_bar(start_x, start_y, heading):
    field = FieldGeometry()
    robot = Pose2D(start_x - P.hold_distance * math.cos(heading), start_y - P.hold_distance * math.sin(heading),
                   heading)
    vx, vy, vz = lob_velocity(robot, start_x, start_y, 1, field, R, -9.8, P)
    assert vz > 0.0
    assert math.atan2(vy, vx) == pytest.approx(heading)
    horizontal = math.hypot(vx, vy)
    distance = (field.half_length - start_x) / math.cos(heading)
    height = height_at(distance, horizontal, vz, R, -9.8)
    assert height + R == pytest.approx(field.goal_height - P.lob_bar_margin, abs=1e-6)
    y_at_line = start_y + vy / vx * (field.half_length - start_x)
    assert field.is_in_goal_mouth(y_at_line, height, R)
    assert math.hypot(horizontal, vz) <= P.lob_max_speed + 1e-9
    # Past the apex when it reaches the line: the ball comes down into the goal.
    assert vz - 9.8 * distance / horizontal < 0.0


def test_a_lob_from_beyond_the_kickers_reach_falls_short():
    """At most lob_max_speed (8.6 m/s, about 45 degrees up): a lob from 11 m out lands before the goal."""
    field = FieldGeometry()
    vx, vy, vz = lob_velocity(Pose2D(-2.43, 0.0, 0.0), -2.0, 0.0, 1, field, R, -9.8, P)
    assert math.hypot(vx, vy, vz) == pytest.approx(P.lob_max_speed)
    landing = vx * 2.0 * vz / 9.8  # back at the height it started from
    assert landing < field.half_length + 2.0


def test_lob_for_a_team_attacking_minus_x():
    field = FieldGeometry()
    vx, _vy, vz = lob_velocity(Pose2D(-2.0, 0.0, math.pi), -2.43, 0.0, -1, field, R, -9.8, P)
    assert vx < 0.0 and vz > 0.0


def test_lob_away_from_the_goal_lands_at_the_default_distance():
    field = FieldGeometry()
    vx, vy, vz = lob_velocity(Pose2D(0.0, 0.0, math.pi), -0.43, 0.0, 1, field, R, -9.8, P)
    down = landing(-0.43, 0.0, R, vx, vy, vz, R, -9.8)
    assert down.t > 0.0
    assert math.hypot(down.x + 0.43, down.y) == pytest.approx(P.lob_default_distance)
