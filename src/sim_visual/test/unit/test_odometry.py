"""Unit tests of the simulated wheel odometry and inertial heading (sim_visual.odometry)."""

import math
from collections.abc import Sequence

import numpy as np
import pytest

from nubot_common.geometry import wrap_angle
from sim_visual.odometry import (
    ImuParams,
    ImuReading,
    InertialHeading,
    OdometryParams,
    OdometryReading,
    WheelOdometry,
    body_velocity,
)
from sim_visual.world import RobotState

EXACT = OdometryParams(noise_ratio=0.0, linear_noise_floor=0.0, angular_noise_floor=0.0, slip_share_max=0.0,
                       linear_resolution=0.0, angular_resolution=0.0)
SLIPPING = OdometryParams(noise_ratio=0.0, linear_noise_floor=0.0, angular_noise_floor=0.0, slip_share_max=0.3,
                          linear_resolution=0.0, angular_resolution=0.0)
DT = 0.01  # [s]


def readings(odometry: WheelOdometry, velocities: Sequence[tuple[float, float, float]], rng: np.random.Generator,
             stuck: bool = False) -> np.ndarray:
    """The (vx, vy, w) readings of a sequence of true body velocities, one a step."""
    return np.array([[r.vx, r.vy, r.w] for r in (odometry.measure(vx, vy, w, DT, stuck, rng)
                                                   for vx, vy, w in velocities)])


def ramp(start: float, end: float, acceleration: float) -> list[tuple[float, float, float]]:
    """Forward speeds from ``start`` to ``end`` [m/s] at ``acceleration`` [m/s^2], one a step."""
    steps = round(abs(end - start) / (acceleration * DT))
    return [(float(v), 0.0, 0.0) for v in np.linspace(start, end, steps + 1)]


def test_body_velocity_turns_the_world_velocity_into_the_robot_frame():
    """A robot facing +y that moves along world +y moves forward; moving along world +x it moves to its right."""
    assert body_velocity(RobotState(0.0, 0.0, math.pi / 2, 0.0, 2.0, 0.3)) == pytest.approx((2.0, 0.0, 0.3))
    assert body_velocity(RobotState(0.0, 0.0, math.pi / 2, 1.0, 0.0, 0.0)) == pytest.approx((0.0, -1.0, 0.0))


def test_without_noise_slip_and_quantisation_the_readings_are_the_truth():
    odometry = WheelOdometry(EXACT)
    rng = np.random.default_rng(0)
    truth = [(0.0, 0.0, 0.0), (3.0, -1.0, 2.0), (-2.5, 0.7, -4.0), (0.1, 0.2, 0.3)]  # jumps included
    assert readings(odometry, truth, rng) == pytest.approx(np.array(truth))
    reading = odometry.measure(1.0, 0.5, 0.25, DT, False, rng)
    assert reading == OdometryReading(1.0, 0.5, 0.25, robot_stuck=False, power_state=True)


def test_the_stuck_flag_passes_through_and_the_power_is_on():
    odometry = WheelOdometry(OdometryParams())
    rng = np.random.default_rng(1)
    assert odometry.measure(0.5, 0.0, 0.0, DT, True, rng).robot_stuck is True
    reading = odometry.measure(0.5, 0.0, 0.0, DT, False, rng)
    assert reading.robot_stuck is False and reading.power_state is True


def test_measured_speeds_are_quantised_to_the_resolution():
    """Readings are whole multiples of the resolutions, within half a step of the truth."""
    params = OdometryParams(noise_ratio=0.0, linear_noise_floor=0.0, angular_noise_floor=0.0, slip_share_max=0.0,
                            linear_resolution=0.01, angular_resolution=0.02)
    reading = WheelOdometry(params).measure(1.2345, -0.4321, 0.987, DT, False, np.random.default_rng(0))
    assert (reading.vx, reading.vy, reading.w) == pytest.approx((1.23, -0.43, 0.98))


def test_encoder_noise_grows_with_speed_from_its_floor():
    """The spread of the readings is the floor at rest and floor + ratio * speed when moving."""
    params = OdometryParams(slip_share_max=0.0, linear_resolution=0.0, angular_resolution=0.0)
    rng = np.random.default_rng(2)
    at_rest = readings(WheelOdometry(params), [(0.0, 0.0, 0.0)] * 4000, rng)
    moving = readings(WheelOdometry(params), [(3.0, 0.0, 2.0)] * 4000, rng)
    assert at_rest.std(axis=0) == pytest.approx(
        [params.linear_noise_floor, params.linear_noise_floor, params.angular_noise_floor], rel=0.06)
    linear, angular = params.linear_noise_floor + 3.0 * params.noise_ratio, params.angular_noise_floor + 0.04
    assert moving.std(axis=0) == pytest.approx([linear, linear, angular], rel=0.06)
    assert moving.mean(axis=0) == pytest.approx([3.0, 0.0, 2.0], abs=0.005)


def dead_reckoning(params: OdometryParams, seed: int) -> tuple[float, float, float]:
    """Drive 10 s along a curve (2 m/s forward, 0.5 m/s left, turning 0.5 rad/s); return the error (x, y [m],
    heading [rad]) of the pose integrated from the readings against the one integrated from the truth."""
    odometry, rng = WheelOdometry(params), np.random.default_rng(seed)
    true_pose, measured_pose = np.zeros(3), np.zeros(3)
    for _ in range(1000):
        truth = (2.0, 0.5, 0.5)
        reading = odometry.measure(*truth, DT, False, rng)
        for pose, (vx, vy, w) in ((true_pose, truth), (measured_pose, (reading.vx, reading.vy, reading.w))):
            c, s = math.cos(pose[2]), math.sin(pose[2])
            pose += (c * vx - s * vy) * DT, (s * vx + c * vy) * DT, w * DT
    error = measured_pose - true_pose
    return float(error[0]), float(error[1]), wrap_angle(float(error[2]))


def test_integrated_readings_end_near_the_true_pose():
    """Dead reckoning over a 21 m curve with the default errors (the centripetal 1 m/s^2 does not slip) ends
    a few centimetres and a fraction of a degree from the truth: the noise averages out; it is not zero."""
    errors = np.array([dead_reckoning(OdometryParams(), seed) for seed in range(12)])
    position = np.hypot(errors[:, 0], errors[:, 1])
    assert np.sqrt(np.mean(position ** 2)) < 0.1
    assert np.sqrt(np.mean(errors[:, 2] ** 2)) < 0.02
    assert position.min() > 1e-4
    assert dead_reckoning(EXACT, 0) == pytest.approx((0.0, 0.0, 0.0), abs=1e-9)


def test_the_wheels_slip_only_when_accelerating_hard():
    """Steady and gentle (3 m/s^2) driving reads true; a 10 m/s^2 start overshoots the true speed by up to
    slip_share_max, a hard stop reads slower; a hard angular start overshoots w."""
    rng = np.random.default_rng(3)
    share = SLIPPING.slip_share_max
    gentle = ramp(0.0, 2.0, 3.0) + [(2.0, 0.0, 0.0)] * 50 + ramp(2.0, 0.0, 3.0)
    assert readings(WheelOdometry(SLIPPING), gentle, rng) == pytest.approx(np.array(gentle))
    hard = ramp(0.0, 3.0, 10.0)[1:]
    start = readings(WheelOdometry(SLIPPING), ramp(0.0, 3.0, 10.0), rng)[1:, 0]
    true = np.array([v[0] for v in hard])
    assert np.all(start >= true) and np.all(start <= true * (1 + share) + 1e-12)
    assert np.mean(start / true - 1.0) == pytest.approx(share / 2, abs=0.06), "a uniform share of the speed"
    stop = readings(WheelOdometry(SLIPPING), ramp(3.0, 0.5, 10.0), rng)[1:, 0]
    true = np.array([v[0] for v in ramp(3.0, 0.5, 10.0)[1:]])
    assert np.all(stop <= true) and np.any(stop < true)
    spin = [(0.0, 0.0, float(w)) for w in np.linspace(0.0, 30.0, 51)]  # 60 rad/s^2
    true = np.array([w for *_, w in spin[1:]])
    measured = readings(WheelOdometry(SLIPPING), spin, rng)[1:, 2]
    assert np.all(measured >= true) and np.mean(measured / true - 1.0) == pytest.approx(share / 2, abs=0.06)


def test_a_fast_tight_turn_slips_towards_the_centre():
    """Driving 3 m/s forward while turning left at 3 rad/s (9 m/s^2 centripetal) slips: the wheels report a
    leftward velocity the robot does not have; the same turn at 1 rad/s (3 m/s^2) reads true."""
    rng = np.random.default_rng(4)
    fast = readings(WheelOdometry(SLIPPING), [(3.0, 0.0, 3.0)] * 200, rng)
    assert np.all(fast[1:, 1] >= 0.0) and np.mean(fast[1:, 1]) > 0.3
    slow = readings(WheelOdometry(SLIPPING), [(3.0, 0.0, 1.0)] * 200, rng)
    assert slow == pytest.approx(np.array([(3.0, 0.0, 1.0)] * 200))


def test_every_reading_draws_the_same_amount_of_randomness():
    """Whether it slips or not, a reading draws the same numbers: runs that differ in slipping stay in step,
    and the same seed gives the same readings."""
    first_rng, second_rng = np.random.default_rng(5), np.random.default_rng(5)
    readings(WheelOdometry(OdometryParams()), ramp(0.0, 3.0, 50.0), first_rng)
    readings(WheelOdometry(OdometryParams()), ramp(0.0, 3.0, 1.0)[:len(ramp(0.0, 3.0, 50.0))], second_rng)
    assert first_rng.random() == second_rng.random()
    runs = [readings(WheelOdometry(OdometryParams()), ramp(0.0, 3.0, 20.0), np.random.default_rng(6))
            for _ in range(2)]
    assert np.array_equal(runs[0], runs[1])


def test_without_errors_the_imu_reads_the_true_heading():
    imu = InertialHeading(ImuParams(heading_noise_std=0.0, bias_walk=0.0, drift_rate=0.0, rate_noise_std=0.0))
    rng = np.random.default_rng(0)
    assert imu.measure(3.0, 0.4, DT, rng) == ImuReading(3.0, 0.4)
    assert imu.measure(math.pi + 0.1, 0.0, DT, rng).yaw == pytest.approx(-math.pi + 0.1), "wrapped"


def test_the_imu_bias_drifts_as_configured():
    """Over 100 s the heading error of many sensors has the constant drift as its mean and the random walk's
    bias_walk sqrt(T) as its spread; recalibrating zeroes it; the rate carries the drift as its bias."""
    params = ImuParams(heading_noise_std=0.0, bias_walk=0.01, drift_rate=0.001, rate_noise_std=0.02)
    rng = np.random.default_rng(7)
    imus = [InertialHeading(params) for _ in range(300)]
    seconds, dt = 100, 0.5
    rates = []
    for _ in range(round(seconds / dt)):
        for imu in imus:
            rates.append(imu.measure(0.3, 0.5, dt, rng).yaw_rate)
    errors = np.array([imu.measure(0.3, 0.5, 0.0, rng).yaw - 0.3 for imu in imus])
    assert errors.mean() == pytest.approx(params.drift_rate * seconds, abs=0.02)
    assert errors.std() == pytest.approx(params.bias_walk * math.sqrt(seconds), rel=0.13)
    assert np.mean(rates) == pytest.approx(0.5 + params.drift_rate, abs=0.0003)
    assert np.std(rates) == pytest.approx(params.rate_noise_std, rel=0.05)
    imus[0].reset()
    assert imus[0].bias == 0.0 and imus[0].measure(0.3, 0.5, 0.0, rng).yaw == pytest.approx(0.3)


def test_the_imu_heading_noise_is_white_with_the_configured_spread():
    params = ImuParams(heading_noise_std=0.01, bias_walk=0.0, drift_rate=0.0)
    imu, rng = InertialHeading(params), np.random.default_rng(8)
    errors = np.array([imu.measure(-1.0, 0.0, DT, rng).yaw + 1.0 for _ in range(4000)])
    assert errors.std() == pytest.approx(0.01, rel=0.05) and abs(errors.mean()) < 0.001
    assert abs(np.corrcoef(errors[:-1], errors[1:])[0, 1]) < 0.05, "uncorrelated from reading to reading"


@pytest.mark.parametrize(("cls", "field", "value", "message"), [
    (OdometryParams, "noise_ratio", -0.1, "noise_ratio must not be negative"),
    (OdometryParams, "noise_ratio", 1.5, "noise_ratio must be at most 1"),
    (OdometryParams, "slip_acceleration", 0.0, "slip_acceleration must be positive"),
    (OdometryParams, "slip_acceleration", math.inf, "slip_acceleration must be finite"),
    (OdometryParams, "slip_share_max", 2.0, "slip_share_max must be at most 1"),
    (OdometryParams, "linear_resolution", -0.001, "linear_resolution must not be negative"),
    (ImuParams, "bias_walk", -1.0, "bias_walk must not be negative"),
    (ImuParams, "heading_noise_std", 4.0, "heading_noise_std must be at most"),
    (ImuParams, "drift_rate", math.nan, "drift_rate must be finite"),
    (ImuParams, "drift_rate", 2.0, "drift_rate must lie in"),
])
def test_bad_parameters_are_refused_naming_the_field(cls, field, value, message):
    with pytest.raises(ValueError, match=message):
        cls(**{field: value})


def test_bad_time_steps_and_velocities_are_refused():
    rng = np.random.default_rng(0)
    with pytest.raises(ValueError, match="dt must be positive"):
        WheelOdometry(OdometryParams()).measure(1.0, 0.0, 0.0, 0.0, False, rng)
    with pytest.raises(ValueError, match="vx must be finite"):
        WheelOdometry(OdometryParams()).measure(math.nan, 0.0, 0.0, DT, False, rng)
    with pytest.raises(ValueError, match="dt must not be negative"):
        InertialHeading(ImuParams()).measure(0.0, 0.0, -DT, rng)
