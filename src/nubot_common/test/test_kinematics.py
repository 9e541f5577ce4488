import math

import numpy as np
import pytest

from nubot_common import NubotCommonError
from nubot_common.kinematics import GOALIE, REGULAR, BodyLimits, WheelLayout

VELOCITIES = [(1.0, 0.0, 0.0), (0.0, 1.0, 0.0), (0.0, 0.0, 2.0), (1.3, -0.7, 0.9), (-2.0, 1.5, -3.0)]


@pytest.mark.parametrize("layout", [REGULAR, GOALIE], ids=["regular", "goalie"])
@pytest.mark.parametrize("velocity", VELOCITIES)
def test_wheel_speeds_and_back_give_the_same_body_velocity(layout, velocity):
    back = layout.body_velocity(layout.wheel_speeds(*velocity))
    assert back == pytest.approx(velocity, abs=1e-12)


def test_regular_robot_drives_forward_with_all_wheels_at_the_same_share():
    speeds = REGULAR.wheel_speeds(1.0, 0.0, 0.0)
    assert np.abs(speeds) == pytest.approx(np.full(4, math.sqrt(0.5)))


def test_turning_on_the_spot_runs_every_wheel_at_radius_times_rate():
    for layout in (REGULAR, GOALIE):
        assert layout.wheel_speeds(0.0, 0.0, 2.0) == pytest.approx(np.full(4, 2.0 * 0.203))


def test_the_goalie_moves_sideways_faster_than_forwards_at_the_same_wheel_speeds():
    top = GOALIE.max_rim_speed
    forward = top / np.max(np.abs(GOALIE.wheel_speeds(1.0, 0.0, 0.0)))
    sideways = top / np.max(np.abs(GOALIE.wheel_speeds(0.0, 1.0, 0.0)))
    assert sideways / forward == pytest.approx(math.sqrt(3.0))
    regular = [REGULAR.max_rim_speed / np.max(np.abs(REGULAR.wheel_speeds(*v))) for v in ((1, 0, 0), (0, 1, 0))]
    assert regular[0] == pytest.approx(regular[1])
    assert regular[0] == pytest.approx(5.08, abs=0.01)  # the motors' 12000 rpm through gear 21, 0.12 m wheels


def test_limit_scales_all_wheels_together_and_keeps_the_direction():
    wanted = (6.0, 3.0, 4.0)
    speeds, scale = REGULAR.limit(REGULAR.wheel_speeds(*wanted))
    assert scale < 1.0
    assert np.max(np.abs(speeds)) == pytest.approx(REGULAR.max_rim_speed)
    vx, vy, w = REGULAR.body_velocity(speeds)
    assert math.atan2(vy, vx) == pytest.approx(math.atan2(wanted[1], wanted[0]))
    assert w / vx == pytest.approx(wanted[2] / wanted[0])


def test_speeds_within_the_limit_are_untouched():
    raw = REGULAR.wheel_speeds(1.0, 0.5, 0.3)
    speeds, scale = REGULAR.limit(raw)
    assert scale == 1.0 and speeds == pytest.approx(raw)


def test_a_least_squares_body_velocity_averages_wheels_that_disagree():
    speeds = REGULAR.wheel_speeds(1.0, 0.0, 0.0) + np.array([0.05, -0.05, 0.05, -0.05])
    assert REGULAR.body_velocity(speeds)[0] == pytest.approx(1.0, abs=0.08)


def test_body_limits_clip_speed_keeping_direction_and_refuse_nan():
    limits = BodyLimits(max_speed=5.0, max_rotation=12.0)
    vx, vy, w = limits.apply(6.0, 8.0, -20.0)
    assert math.hypot(vx, vy) == pytest.approx(5.0) and vy / vx == pytest.approx(8.0 / 6.0) and w == -12.0
    with pytest.raises(NubotCommonError, match="finite"):
        limits.apply(float("nan"), 0.0, 0.0)


@pytest.mark.parametrize("kwargs, message", [
    ({"wheel_angles_deg": (0.0, 90.0)}, "at least 3 wheels"),
    ({"wheel_angles_deg": (0.0, 0.0, 0.0, 0.0)}, "every direction"),
    ({"wheel_diameter": 0.0}, "wheel_diameter must be positive"),
    ({"gear_ratio": float("inf")}, "finite"),
])
def test_a_layout_that_cannot_drive_is_refused(kwargs, message):
    with pytest.raises(NubotCommonError, match=message):
        WheelLayout(**kwargs)


def test_body_velocity_refuses_the_wrong_number_of_wheels():
    with pytest.raises(NubotCommonError, match="expected 4 wheel speeds"):
        REGULAR.body_velocity(np.zeros(3))
