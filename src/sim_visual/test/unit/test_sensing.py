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


def _observe_one_draw_per_object(stamp, me, frame, agent_id, flags, ball, others, noise, rng):
    """The frame as drawn object by object (self, ball, each robot in range): the order the noise must follow."""
    from nubot_common.geometry import Pose2D, wrap_angle

    tx, ty = frame.point_to_team(me.x, me.y)
    truth = Pose2D(tx, ty, frame.heading_to_team(me.theta))
    n = rng.normal(0.0, 1.0, size=6)
    est = Pose2D(tx + noise.self_position_std * n[0], ty + noise.self_position_std * n[1],
                 wrap_angle(truth.theta + noise.heading_std * n[2]))
    seen = []
    for wx, wy in [(ball.x, ball.y)] + [(r.x, r.y) for r in others]:
        bx, by = truth.to_body(*frame.point_to_team(wx, wy))
        if noise.vision_range > 0.0 and math.hypot(bx, by) > noise.vision_range:
            seen.append(None)
            continue
        d = rng.normal(0.0, 1.0, size=4)
        seen.append(est.to_world(bx + noise.position_std * d[0], by + noise.position_std * d[1]))
    return est, seen


@pytest.mark.parametrize("vision_range", [0.0, 2.5])
def test_the_noise_is_drawn_in_one_call_with_the_numbers_of_one_draw_per_object(vision_range):
    noise = NoiseParams(vision_range=vision_range)
    others = [OTHER, RobotState(4.0, 2.0, 0.0, 0.0, 0.0, 0.0), RobotState(1.5, 2.5, 0.0, 0.0, 0.0, 0.0)]
    frame = observe(3.0, ME, MINUS_X, 1, FLAGS, BALL, others, noise, np.random.default_rng(5))
    est, seen = _observe_one_draw_per_object(3.0, ME, MINUS_X, 1, FLAGS, BALL, others, noise,
                                             np.random.default_rng(5))
    assert (frame.robot.pose.x, frame.robot.pose.y, frame.robot.pose.theta) == (est.x, est.y, est.theta)
    assert (frame.ball.x, frame.ball.y) == seen[0]
    assert list(frame.obstacles) == [p for p in seen[1:] if p is not None]
    assert len(frame.obstacles) == (3 if vision_range == 0.0 else 2)
