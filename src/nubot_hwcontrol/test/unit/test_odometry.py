import math

import numpy as np
import pytest

from nubot_common.kinematics import GOALIE, REGULAR
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.odometry import OdometryParams, WheelOdometry


def counts_along(layout, path, dt, counts_per_rev=2000):
    """Ideal encoder readings for a body-frame velocity profile: path(t) -> (vx, vy, w)."""
    per_metre = counts_per_rev * layout.gear_ratio / (math.pi * layout.wheel_diameter)
    turns = np.zeros(layout.wheels)
    t = 0.0
    while True:
        yield t, tuple(int(c) % 2**32 for c in np.floor(turns)), layout.wheel_speeds(*path(t))
        sub = 20
        for k in range(sub):  # integrate finely between two readings
            turns += layout.wheel_speeds(*path(t + (k + 0.5) * dt / sub)) * dt / sub * per_metre
        t += dt


def true_pose(path, end, h=1e-4):
    x = y = th = 0.0
    for k in range(int(round(end / h))):
        vx, vy, w = path((k + 0.5) * h)
        x += (vx * math.cos(th) - vy * math.sin(th)) * h
        y += (vx * math.sin(th) + vy * math.cos(th)) * h
        th += w * h
    return x, y, th


@pytest.mark.parametrize("layout", [REGULAR, GOALIE], ids=["regular", "goalie"])
def test_integrating_the_encoders_follows_a_known_path(layout):
    def path(t):
        return 1.5 * math.cos(0.4 * t), 1.0, 0.6 * math.sin(0.7 * t)

    odo, end = WheelOdometry(layout), 10.0
    for t, counts, cmd in counts_along(layout, path, 0.02):
        est = odo.update(t, counts, cmd)
        if t >= end - 1e-9:
            break
    x, y, th = true_pose(path, end)
    assert (est.x, est.y) == pytest.approx((x, y), abs=0.01)  # over about 12 m
    assert est.theta == pytest.approx(math.atan2(math.sin(th), math.cos(th)), abs=0.002)
    assert (est.vx, est.vy, est.w) == pytest.approx(path(end - 0.01), abs=0.02)
    assert not est.stuck


def test_counters_that_wrap_around_32_bits_give_no_jump():
    odo = WheelOdometry(REGULAR)
    near = 2**32 - 100
    odo.update(0.0, (near,) * 4)
    est = odo.update(0.02, (200,) * 4)  # +300 counts: the counter wrapped past 2**32
    travel = 300 * math.pi * 0.12 / (21 * 2000)
    assert est.w == pytest.approx(travel / 0.203 / 0.02)


def test_wheels_much_slower_than_commanded_for_half_a_second_mean_stuck():
    odo = WheelOdometry(REGULAR, OdometryParams(stuck_time=0.5))
    commanded = REGULAR.wheel_speeds(2.0, 0.0, 0.0)
    per_metre = 2000 * 21 / (math.pi * 0.12)
    turns = np.zeros(4)
    flags = []
    for k in range(60):
        turns += commanded * 0.2 * 0.02 * per_metre  # wheels turn at a fifth of the command: pushing a wall
        flags.append(odo.update(k * 0.02, tuple(int(c) % 2**32 for c in np.floor(turns)), commanded).stuck)
    first = flags.index(True)
    assert 0.48 <= first * 0.02 <= 0.56
    assert all(flags[first:])
    free = odo.update(60 * 0.02, tuple(int(c) % 2**32 for c in np.floor(turns + commanded * 0.02 * per_metre)),
                      commanded)
    assert not free.stuck


def test_a_slow_command_is_never_stuck():
    odo = WheelOdometry(REGULAR)
    commanded = REGULAR.wheel_speeds(0.1, 0.0, 0.0)
    assert not any(odo.update(k * 0.02, (0, 0, 0, 0), commanded).stuck for k in range(100))


def test_readings_out_of_order_or_of_the_wrong_shape_are_refused():
    odo = WheelOdometry(REGULAR)
    odo.update(1.0, (0, 0, 0, 0))
    with pytest.raises(HardwareError, match="not after"):
        odo.update(1.0, (1, 1, 1, 1))
    with pytest.raises(HardwareError, match="expected 4 encoder counts"):
        odo.update(2.0, (1, 1, 1))
