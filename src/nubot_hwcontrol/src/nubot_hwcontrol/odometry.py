"""Wheel odometry from the drives' encoder counts, and stuck detection.

Requires: one encoder count per wheel per cycle (motor shaft counts, 32-bit, wrapping), the wheel layout.
Provides: ``WheelOdometry.update`` -> ``OdometryEstimate``: the body velocity (body frame, as ``OdoInfo``
carries it), the pose integrated in the odometry frame (where the robot started), and ``stuck``: the wheels
turn at less than ``stuck_ratio`` of their commanded speed for ``stuck_time`` while the command asks for at
least ``stuck_min_speed`` (a robot pushing against another slips its wheels at the drives' current limit).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.geometry import wrap_angle
from nubot_common.kinematics import WheelLayout
from nubot_hwcontrol import HardwareError

_WRAP = 2**32


@dataclass(frozen=True)
class OdometryParams:
    counts_per_revolution: int = 2000  # encoder counts per motor revolution (a 500-line quadrature encoder)
    stuck_ratio: float = 0.5  # wheels slower than this share of the command...
    stuck_time: float = 0.5  # ...for this long [s]...
    stuck_min_speed: float = 0.3  # ...while the command's rim speeds reach this (RMS over wheels) [m/s]

    def __post_init__(self) -> None:
        if self.counts_per_revolution <= 0:
            raise HardwareError(f"counts_per_revolution must be positive, got {self.counts_per_revolution}")
        if not 0.0 < self.stuck_ratio < 1.0:
            raise HardwareError(f"stuck_ratio must lie in (0, 1), got {self.stuck_ratio}")
        if not (self.stuck_time > 0.0 and self.stuck_min_speed > 0.0):
            raise HardwareError("stuck_time and stuck_min_speed must be positive")


@dataclass(frozen=True)
class OdometryEstimate:
    stamp: float  # [s]
    vx: float  # body frame [m/s]
    vy: float
    w: float  # [rad/s]
    x: float  # odometry frame [m], where the robot was at the first update
    y: float
    theta: float  # [rad]
    stuck: bool
    rim_speeds: tuple[float, ...]  # each wheel's measured rim speed [m/s]


class WheelOdometry:
    def __init__(self, layout: WheelLayout, params: OdometryParams | None = None):
        params = params or OdometryParams()
        self.layout, self.params = layout, params
        self._metres_per_count = math.pi * layout.wheel_diameter / (layout.gear_ratio * params.counts_per_revolution)
        self._last: tuple[float, np.ndarray] | None = None
        self._slow_since: float | None = None
        self.x = self.y = self.theta = 0.0
        self.estimate = OdometryEstimate(0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, False, (0.0,) * layout.wheels)

    def counts_to_metres(self, counts: np.ndarray) -> np.ndarray:
        return np.asarray(counts, dtype=float) * self._metres_per_count

    def update(self, stamp: float, counts: tuple[int, ...] | np.ndarray,
               commanded: np.ndarray | None = None) -> OdometryEstimate:
        """Take one reading of every wheel's encoder at ``stamp`` [s]; ``commanded`` are the rim speeds the
        drives were told to run at [m/s] (for stuck detection; None: no command)."""
        raw = np.asarray(counts, dtype=np.int64)
        if raw.shape != (self.layout.wheels,):
            raise HardwareError(f"expected {self.layout.wheels} encoder counts, got shape {raw.shape}")
        if not math.isfinite(stamp):
            raise HardwareError(f"odometry stamp must be finite, got {stamp}")
        if self._last is None:
            self._last = (stamp, raw)
            self.estimate = OdometryEstimate(stamp, 0.0, 0.0, 0.0, self.x, self.y, self.theta, False,
                                             (0.0,) * self.layout.wheels)
            return self.estimate
        last_stamp, last_raw = self._last
        dt = stamp - last_stamp
        if dt <= 0.0:
            raise HardwareError(f"encoder reading at {stamp} s is not after the previous one at {last_stamp} s")
        delta = (raw - last_raw + _WRAP // 2) % _WRAP - _WRAP // 2  # 32-bit counters wrap
        self._last = (stamp, raw)
        travel = self.counts_to_metres(delta)
        dx, dy, dtheta = self.layout.body_velocity(travel)
        # Integrate at the middle of the cycle's turn (exact for constant velocities to second order).
        mid = self.theta + 0.5 * dtheta
        self.x += dx * math.cos(mid) - dy * math.sin(mid)
        self.y += dx * math.sin(mid) + dy * math.cos(mid)
        self.theta = wrap_angle(self.theta + dtheta)
        rim = travel / dt
        stuck = self._stuck(stamp, rim, commanded)
        self.estimate = OdometryEstimate(stamp, dx / dt, dy / dt, dtheta / dt, self.x, self.y, self.theta, stuck,
                                         tuple(float(v) for v in rim))
        return self.estimate

    def _stuck(self, stamp: float, rim: np.ndarray, commanded: np.ndarray | None) -> bool:
        p = self.params
        if commanded is None:
            self._slow_since = None
            return False
        wanted = float(np.sqrt(np.mean(np.square(commanded))))
        got = float(np.sqrt(np.mean(np.square(rim))))
        if wanted < p.stuck_min_speed or got >= p.stuck_ratio * wanted:
            self._slow_since = None
            return False
        if self._slow_since is None:
            self._slow_since = stamp
        return stamp - self._slow_since >= p.stuck_time

    def reset_pose(self, x: float = 0.0, y: float = 0.0, theta: float = 0.0) -> None:
        self.x, self.y, self.theta = x, y, theta
