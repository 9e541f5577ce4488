"""The team frame: each team sees its own goal at -x; the transforms go both ways without loss."""

import math

import numpy as np
import pytest

from nubot_common import NubotCommonError
from nubot_common.geometry import Pose2D
from nubot_common.team_frame import TeamFrame

SAMPLES = np.random.default_rng(0).uniform([-20.0, -20.0, -math.pi], [20.0, 20.0, math.pi], size=(200, 3))


@pytest.mark.parametrize("attack", [1, -1])
def test_world_to_team_and_back_is_the_identity(attack):
    frame = TeamFrame(attack)
    for x, y, theta in SAMPLES:
        assert frame.point_to_world(*frame.point_to_team(x, y)) == pytest.approx((x, y))
        assert frame.velocity_to_world(*frame.velocity_to_team(x, y)) == pytest.approx((x, y))
        back = frame.pose_to_world(frame.pose_to_team(Pose2D(x, y, theta)))
        assert (back.x, back.y) == pytest.approx((x, y))
        assert math.cos(back.theta - theta) == pytest.approx(1.0)
        assert -math.pi < frame.pose_to_team(Pose2D(x, y, theta)).theta <= math.pi


def test_a_team_attacking_plus_x_sees_the_world_frame():
    frame = TeamFrame(1)
    assert frame.point_to_team(3.0, -1.0) == (3.0, -1.0)
    assert frame.pose_to_team(Pose2D(1.0, 2.0, 0.5)) == Pose2D(1.0, 2.0, 0.5)


def test_a_team_attacking_minus_x_sees_the_field_turned_half_round():
    frame = TeamFrame(-1)
    assert frame.point_to_team(8.0, 1.0) == (-8.0, -1.0), "the goal it attacks (world -x) is at +x for it"
    assert frame.velocity_to_team(2.0, 0.0) == (-2.0, 0.0)
    facing = frame.pose_to_team(Pose2D(0.0, 0.0, math.pi))  # faces the world's -x goal ...
    assert facing.theta == pytest.approx(0.0), "... which it attacks: straight ahead in its frame"
    assert -math.pi < frame.heading_to_team(0.0) <= math.pi


def test_relative_geometry_does_not_depend_on_the_frame():
    me, ball = Pose2D(2.0, 1.0, 0.3), (4.0, -2.0)
    for frame in (TeamFrame(1), TeamFrame(-1)):
        mine, seen = frame.pose_to_team(me), frame.point_to_team(*ball)
        assert mine.distance_to(*seen) == pytest.approx(me.distance_to(*ball))
        assert mine.bearing_to(*seen) == pytest.approx(me.bearing_to(*ball))


@pytest.mark.parametrize("attack", [0, 2, True, "1"])
def test_an_attack_other_than_plus_or_minus_one_is_refused(attack):
    with pytest.raises(NubotCommonError, match=r"attack must be 1 \(the goal at \+x\) or -1"):
        TeamFrame(attack)
