"""Tests for nubot_common.geometry: angles, rotations, polar form, frames and quaternions."""

import math

import numpy as np
import pytest

from nubot_common.geometry import Pose2D, quaternion_to_yaw, rotate, to_polar, wrap_angle, yaw_to_quaternion

RNG_SEED = 20150701


def random_values(count: int, low: float, high: float) -> list[float]:
    return [float(v) for v in np.random.default_rng(RNG_SEED).uniform(low, high, count)]


@pytest.mark.parametrize(
    ("angle", "expected"),
    [
        (0.0, 0.0),
        (math.pi, math.pi),
        (-math.pi, math.pi),
        (3 * math.pi, math.pi),
        (-3 * math.pi, math.pi),
        (2 * math.pi, 0.0),
        (math.pi / 2 + 2 * math.pi, math.pi / 2),
        (-math.pi / 2 - 4 * math.pi, -math.pi / 2),
        (1.5 * math.pi, -0.5 * math.pi),
        (-1.5 * math.pi, 0.5 * math.pi),
    ],
)
def test_wrap_angle_known_values(angle, expected):
    assert wrap_angle(angle) == pytest.approx(expected, abs=1e-12)


@pytest.mark.parametrize("angle", random_values(200, -50.0, 50.0))
def test_wrap_angle_lands_in_half_open_interval_and_keeps_direction(angle):
    wrapped = wrap_angle(angle)
    assert -math.pi < wrapped <= math.pi
    assert math.cos(wrapped) == pytest.approx(math.cos(angle), abs=1e-9)
    assert math.sin(wrapped) == pytest.approx(math.sin(angle), abs=1e-9)
    assert wrap_angle(wrapped) == pytest.approx(wrapped, abs=1e-12)


def test_rotate_quarter_turns_counter_clockwise():
    assert rotate(1.0, 0.0, math.pi / 2) == pytest.approx((0.0, 1.0), abs=1e-12)
    assert rotate(0.0, 1.0, math.pi / 2) == pytest.approx((-1.0, 0.0), abs=1e-12)
    assert rotate(1.0, 2.0, math.pi) == pytest.approx((-1.0, -2.0), abs=1e-12)
    assert rotate(3.0, -4.0, 0.0) == (3.0, -4.0)


@pytest.mark.parametrize("angle", random_values(20, -7.0, 7.0))
def test_rotate_keeps_length_and_is_undone_by_the_opposite_angle(angle):
    x, y = rotate(3.0, -4.0, angle)
    assert math.hypot(x, y) == pytest.approx(5.0)
    assert rotate(x, y, -angle) == pytest.approx((3.0, -4.0))


def test_to_polar_known_values():
    assert to_polar(1.0, 0.0) == (0.0, 1.0)
    assert to_polar(0.0, 2.0) == pytest.approx((math.pi / 2, 2.0))
    assert to_polar(-3.0, 0.0) == pytest.approx((math.pi, 3.0))
    assert to_polar(0.0, -1.0) == pytest.approx((-math.pi / 2, 1.0))
    assert to_polar(3.0, 4.0) == pytest.approx((math.atan2(4.0, 3.0), 5.0))


def test_to_polar_is_inverted_by_rotating_the_radius():
    angle, radius = to_polar(-2.0, 1.5)
    assert rotate(radius, 0.0, angle) == pytest.approx((-2.0, 1.5))


def test_pose_defaults_to_the_origin_and_is_frozen():
    pose = Pose2D()
    assert (pose.x, pose.y, pose.theta) == (0.0, 0.0, 0.0)
    with pytest.raises(AttributeError, match="cannot assign to field 'x'"):
        pose.x = 1.0  # type: ignore[misc]


def test_to_body_of_a_point_ahead_and_to_the_left():
    pose = Pose2D(1.0, 2.0, math.pi / 2)  # facing +y
    assert pose.to_body(1.0, 5.0) == pytest.approx((3.0, 0.0), abs=1e-12)  # 3 m straight ahead
    assert pose.to_body(0.0, 2.0) == pytest.approx((0.0, 1.0), abs=1e-12)  # 1 m to the robot's left
    assert pose.to_body(1.0, 2.0) == pytest.approx((0.0, 0.0), abs=1e-12)


def test_to_world_of_a_body_point():
    pose = Pose2D(-3.0, 1.0, math.pi)  # facing -x
    assert pose.to_world(2.0, 0.0) == pytest.approx((-5.0, 1.0), abs=1e-12)
    assert pose.to_world(0.0, 1.0) == pytest.approx((-3.0, 0.0), abs=1e-12)


@pytest.mark.parametrize("seed", range(10))
def test_to_body_and_to_world_are_inverse(seed):
    rng = np.random.default_rng(RNG_SEED + seed)
    x, y, theta, px, py = (float(v) for v in rng.uniform(-10.0, 10.0, 5))
    pose = Pose2D(x, y, theta)
    assert pose.to_world(*pose.to_body(px, py)) == pytest.approx((px, py))
    assert pose.to_body(*pose.to_world(px, py)) == pytest.approx((px, py))
    assert math.hypot(*pose.to_body(px, py)) == pytest.approx(pose.distance_to(px, py))


def test_bearing_to_known_points():
    pose = Pose2D(0.0, 0.0, math.pi / 2)
    assert pose.bearing_to(0.0, 5.0) == pytest.approx(0.0)
    assert pose.bearing_to(-1.0, 0.0) == pytest.approx(math.pi / 2)
    assert pose.bearing_to(1.0, 0.0) == pytest.approx(-math.pi / 2)
    assert pose.bearing_to(0.0, -1.0) == pytest.approx(math.pi)


def test_bearing_is_wrapped_into_half_open_interval():
    pose = Pose2D(0.0, 0.0, 3.0)
    bearing = pose.bearing_to(1.0, -0.5)  # atan2 = -0.46, minus 3.0 is below -pi without wrapping
    assert -math.pi < bearing <= math.pi
    assert bearing == pytest.approx(math.atan2(-0.5, 1.0) - 3.0 + 2 * math.pi)


@pytest.mark.parametrize("seed", range(10))
def test_bearing_matches_the_body_frame_angle(seed):
    rng = np.random.default_rng(RNG_SEED + seed)
    x, y, theta, px, py = (float(v) for v in rng.uniform(-10.0, 10.0, 5))
    pose = Pose2D(x, y, theta)
    angle, _radius = to_polar(*pose.to_body(px, py))
    assert pose.bearing_to(px, py) == pytest.approx(angle)


def test_distance_to():
    assert Pose2D(1.0, 1.0, 2.0).distance_to(4.0, 5.0) == pytest.approx(5.0)
    assert Pose2D(1.0, 1.0).distance_to(1.0, 1.0) == 0.0


def test_yaw_to_quaternion_known_values():
    assert yaw_to_quaternion(0.0) == (0.0, 0.0, 0.0, 1.0)
    assert yaw_to_quaternion(math.pi) == pytest.approx((0.0, 0.0, 1.0, 0.0), abs=1e-12)
    half = math.sqrt(0.5)
    assert yaw_to_quaternion(math.pi / 2) == pytest.approx((0.0, 0.0, half, half))


@pytest.mark.parametrize("yaw", random_values(50, -math.pi, math.pi) + [math.pi, 0.0, -math.pi / 2])
def test_yaw_quaternion_round_trip_and_unit_norm(yaw):
    quaternion = yaw_to_quaternion(yaw)
    assert math.fsum(c * c for c in quaternion) == pytest.approx(1.0)
    assert wrap_angle(quaternion_to_yaw(*quaternion) - yaw) == pytest.approx(0.0, abs=1e-9)


def test_quaternion_to_yaw_ignores_sign_of_the_quaternion():
    x, y, z, w = yaw_to_quaternion(1.0)
    assert quaternion_to_yaw(-x, -y, -z, -w) == pytest.approx(1.0)


def test_quaternion_to_yaw_of_a_pure_roll_is_zero():
    half = math.sqrt(0.5)
    assert quaternion_to_yaw(half, 0.0, 0.0, half) == pytest.approx(0.0)
