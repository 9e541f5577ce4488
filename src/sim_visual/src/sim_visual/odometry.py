"""Simulated wheel odometry and inertial heading of one robot: what its base and its inertial sensor report.

Requires: the robot's true velocity in its body frame (``body_velocity`` of its world-frame ``RobotState``:
x forward, y left [m/s], w [rad/s]), its true heading in its team frame [rad] (0 faces the goal the team
attacks: the team calibrates the sensor so before a half), the time step [s], whether the robot is stuck,
``OdometryParams`` / ``ImuParams`` and the run's ``numpy.random.Generator`` (the only source of randomness;
each reading draws the same amount of it, slipping or not).
Provides: ``WheelOdometry.measure`` -> ``OdometryReading`` (the content of nubot_common/OdoInfo: Vx, Vy
[m/s], w [rad/s], RobotStuck, PowerState), ``InertialHeading.measure`` -> ``ImuReading`` (yaw [rad], yaw rate
[rad/s]; the node publishes it as sensor_msgs/Imu) and ``body_velocity``. Both keep one robot's state.

Error model, at the level of the body velocity (wheel kinematics belong to the base's own package):
- encoders: Gaussian noise on each component, std ``*_noise_floor`` plus ``noise_ratio`` times the speed
  (linear [m/s] for Vx and Vy, angular [rad/s] for w);
- slip: while the base's true acceleration (in the body frame, the centripetal w x v included) exceeds
  ``slip_acceleration`` [m/s^2], the wheels slip along it: the measured velocity overshoots the true one by
  a share, uniform in [0, ``slip_share_max``], of the speed (spinning when speeding up, skidding when
  braking); the same for w above ``slip_angular_acceleration`` [rad/s^2];
- quantisation: measured speeds are multiples of ``linear_resolution`` [m/s] and ``angular_resolution``
  [rad/s] (0: none).
Inertial heading: yaw = true heading + bias + white noise (``heading_noise_std`` [rad]); the bias starts at
0 and drifts by ``drift_rate`` [rad/s] plus a random walk of ``bias_walk`` [rad/sqrt(s)]; yaw rate = true w
+ drift_rate + white noise (``rate_noise_std`` [rad/s]).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.geometry import rotate, wrap_angle
from nubot_common.params import require_non_negative, require_positive
from sim_visual.world import RobotState


def body_velocity(state: RobotState) -> tuple[float, float, float]:
    """A robot's world-frame velocity as (forward [m/s], left [m/s], w [rad/s]) in its body frame."""
    vx, vy = rotate(state.vx, state.vy, -state.theta)
    return vx, vy, state.w


def _require_finite(**values: float) -> None:
    for name, value in values.items():
        if not math.isfinite(value):
            raise ValueError(f"{name} must be finite, got {value}")


def _quantise(value: float, step: float) -> float:
    return round(value / step) * step if step > 0.0 else value


@dataclass(frozen=True)
class OdometryParams:
    noise_ratio: float = 0.02  # encoder noise std per unit of speed
    linear_noise_floor: float = 0.005  # [m/s] encoder noise std at rest
    angular_noise_floor: float = 0.01  # [rad/s]
    slip_acceleration: float = 5.0  # [m/s^2] the wheels' grip on the carpet (about mu g)
    slip_angular_acceleration: float = 20.0  # [rad/s^2]
    slip_share_max: float = 0.3  # largest overshoot of a slipping wheel, a share of the speed
    linear_resolution: float = 0.001  # [m/s]; 0: not quantised
    angular_resolution: float = 0.001  # [rad/s]

    def __post_init__(self) -> None:
        require_non_negative(self, "noise_ratio", "linear_noise_floor", "angular_noise_floor", "slip_share_max",
                             "linear_resolution", "angular_resolution")
        require_positive(self, "slip_acceleration", "slip_angular_acceleration")
        for name in ("noise_ratio", "slip_share_max"):
            if not getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must be at most 1, got {getattr(self, name)}")
        _require_finite(slip_acceleration=self.slip_acceleration,
                        slip_angular_acceleration=self.slip_angular_acceleration)
        for name in ("linear_noise_floor", "angular_noise_floor", "linear_resolution", "angular_resolution"):
            if not getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must be at most 1, got {getattr(self, name)}")


@dataclass(frozen=True)
class ImuParams:
    heading_noise_std: float = 0.005  # [rad] white noise on the yaw
    bias_walk: float = 0.002  # [rad/sqrt(s)] random walk of the yaw's bias
    drift_rate: float = 0.0002  # [rad/s] constant drift of the yaw's bias (the gyro's rate bias)
    rate_noise_std: float = 0.01  # [rad/s] white noise on the yaw rate

    def __post_init__(self) -> None:
        require_non_negative(self, "heading_noise_std", "bias_walk", "rate_noise_std")
        _require_finite(drift_rate=self.drift_rate)
        for name, high in (("heading_noise_std", math.pi), ("bias_walk", 1.0), ("rate_noise_std", 10.0)):
            if not getattr(self, name) <= high:
                raise ValueError(f"{name} must be at most {high:g}, got {getattr(self, name)}")
        if not abs(self.drift_rate) <= 1.0:
            raise ValueError(f"drift_rate must lie in [-1, 1] rad/s, got {self.drift_rate}")


@dataclass(frozen=True)
class OdometryReading:
    """What the base reports (nubot_common/OdoInfo), in the body frame."""

    vx: float  # forward [m/s]
    vy: float  # left [m/s]
    w: float  # [rad/s], counter-clockwise
    robot_stuck: bool
    power_state: bool = True


@dataclass(frozen=True)
class ImuReading:
    yaw: float  # [rad] in the team frame, (-pi, pi], 0 facing the goal the team attacks
    yaw_rate: float  # [rad/s]


class WheelOdometry:
    """One robot's wheel odometry; remembers the last true velocity to tell its acceleration."""

    def __init__(self, params: OdometryParams):
        self.params = params
        self._last: tuple[float, float, float] | None = None

    def reset(self) -> None:
        """Forget the last velocity (the robot was placed anew): the next reading sees no acceleration."""
        self._last = None

    def measure(self, vx: float, vy: float, w: float, dt: float, stuck: bool,
                rng: np.random.Generator) -> OdometryReading:
        """The reading for the true body velocity (vx forward, vy left [m/s], w [rad/s]) held over the last
        ``dt`` [s]."""
        _require_finite(vx=vx, vy=vy, w=w, dt=dt)
        if dt <= 0.0:
            raise ValueError(f"dt must be positive, got {dt}")
        p = self.params
        noise = rng.standard_normal(3)
        share = rng.random(2) * p.slip_share_max
        last = self._last if self._last is not None else (vx, vy, w)
        self._last = (vx, vy, w)
        ax = (vx - last[0]) / dt - w * vy  # the body frame turns: its acceleration has the w x v term
        ay = (vy - last[1]) / dt + w * vx
        alpha = (w - last[2]) / dt
        speed, accel = math.hypot(vx, vy), math.hypot(ax, ay)
        mx, my, mw = vx, vy, w
        if accel > p.slip_acceleration:
            mx += share[0] * speed * ax / accel
            my += share[0] * speed * ay / accel
        if abs(alpha) > p.slip_angular_acceleration:
            mw += share[1] * abs(w) * math.copysign(1.0, alpha)
        linear_std = p.linear_noise_floor + p.noise_ratio * speed
        angular_std = p.angular_noise_floor + p.noise_ratio * abs(w)
        return OdometryReading(_quantise(mx + linear_std * noise[0], p.linear_resolution),
                               _quantise(my + linear_std * noise[1], p.linear_resolution),
                               _quantise(mw + angular_std * noise[2], p.angular_resolution), bool(stuck))


class InertialHeading:
    """One robot's inertial heading sensor, zeroed facing the attacked goal; its bias drifts from 0."""

    def __init__(self, params: ImuParams):
        self.params = params
        self.bias = 0.0  # [rad]

    def reset(self) -> None:
        """Recalibrate (before a half): the bias is 0 again."""
        self.bias = 0.0

    def measure(self, yaw: float, w: float, dt: float, rng: np.random.Generator) -> ImuReading:
        """The reading for the true team-frame heading ``yaw`` [rad] and rate ``w`` [rad/s], ``dt`` [s] after
        the last one."""
        _require_finite(yaw=yaw, w=w, dt=dt)
        if dt < 0.0:
            raise ValueError(f"dt must not be negative, got {dt}")
        p = self.params
        noise = rng.standard_normal(3)
        self.bias += p.drift_rate * dt + p.bias_walk * math.sqrt(dt) * noise[0]
        return ImuReading(wrap_angle(yaw + self.bias + p.heading_noise_std * noise[1]),
                          w + p.drift_rate + p.rate_noise_std * noise[2])
