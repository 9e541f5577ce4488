"""Unit tests of the synthetic omni-vision (sim_visual.sensing)."""

import math

import numpy as np
import pytest

from nubot_common.team_frame import TeamFrame
from sim_visual.params import NoiseParams
from sim_visual.sensing import RobotFlags, observe
from sim_visual.world import BallState, RobotState

ME = RobotState(1.0, 2.0, math.pi / 2, 0.5, 0.0, 0.1)
BALL = BallState(1.0, 4.0, 0.11, 1.0, -1.0, 0.0)
OTHER = RobotState(-1.0, 2.0, 0.0, 0.0, 0.0, 0.0)
FLAGS = RobotFlags()
PLUS_X, MINUS_X = TeamFrame(1), TeamFrame(-1)


def test_without_noise_the_frame_is_the_truth():
    frame = observe(3.0, ME, PLUS_X, 1, FLAGS, BALL, [OTHER], NoiseParams(0, 0, 0, 0), np.random.default_rng(0))
    assert frame.stamp == 3.0
    me = frame.robot.pose
    assert (me.x, me.y, me.theta) == pytest.approx((1.0, 2.0, math.pi / 2))
    assert (frame.ball.x, frame.ball.y, frame.ball.vx, frame.ball.vy) == pytest.approx((1.0, 4.0, 1.0, -1.0))
    assert (me.bearing_to(*frame.ball.position), me.distance_to(*frame.ball.position)) == pytest.approx((0.0, 2.0)), \
        "straight ahead, 2 m"
    obstacle = frame.obstacles[0]
    assert (me.bearing_to(*obstacle), me.distance_to(*obstacle)) == pytest.approx((math.pi / 2, 2.0)), "to the left"


def test_a_team_attacking_minus_x_sees_a_rotated_field():
    frame = observe(0.0, ME, MINUS_X, 1, FLAGS, BALL, [], NoiseParams(0, 0, 0, 0), np.random.default_rng(0))
    me = frame.robot.pose
    assert (me.x, me.y) == pytest.approx((-1.0, -2.0))
    assert me.theta == pytest.approx(-math.pi / 2)
    assert (frame.ball.x, frame.ball.y, frame.ball.vx) == pytest.approx((-1.0, -4.0, -1.0))
    assert me.bearing_to(*frame.ball.position) == pytest.approx(0.0), "relative measurements do not depend on the frame"


def test_noise_has_the_configured_spread():
    noise = NoiseParams(position_std=0.1, velocity_std=0.2, self_position_std=0.0, heading_std=0.0)
    rng = np.random.default_rng(7)
    frames = [observe(0.0, ME, PLUS_X, 1, FLAGS, BALL, [], noise, rng) for _ in range(4000)]
    xs = np.array([f.ball.x for f in frames])
    vxs = np.array([f.ball.vx for f in frames])
    assert xs.mean() == pytest.approx(1.0, abs=0.01)
    assert xs.std() == pytest.approx(0.1, rel=0.1)
    assert vxs.std() == pytest.approx(0.2, rel=0.1)


def test_same_seed_same_noise():
    noise = NoiseParams()
    a = observe(0.0, ME, PLUS_X, 1, FLAGS, BALL, [OTHER], noise, np.random.default_rng(3))
    b = observe(0.0, ME, PLUS_X, 1, FLAGS, BALL, [OTHER], noise, np.random.default_rng(3))
    c = observe(0.0, ME, PLUS_X, 1, FLAGS, BALL, [OTHER], noise, np.random.default_rng(4))
    assert a == b and a != c


def test_vision_range_hides_far_objects():
    noise = NoiseParams(0, 0, 0, 0, vision_range=1.5)
    frame = observe(0.0, ME, PLUS_X, 1, FLAGS, BALL, [OTHER], noise, np.random.default_rng(0))
    assert frame.ball is None and frame.obstacles == ()
