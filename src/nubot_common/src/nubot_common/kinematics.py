"""Omni-wheel kinematics of the robot's base: body velocity to wheel rim speeds and back, with limits.

A wheel sits at angle ``phi`` around the robot centre (0 = the robot's front, x; counter-clockwise) at
``wheel_distance`` from it and drives along ``phi + 90 deg``. Its rim speed for a body velocity
(vx, vy, w) is ``-sin(phi) vx + cos(phi) vy + wheel_distance w``. With four wheels the inverse is over-
determined: ``body_velocity`` is its least-squares solution, so wheels that disagree (slip) average out.

Layouts: the regular robot has its wheels at +-45 and +-135 deg (NuBot's base: the same top speed in every
direction); the goalie's wheels are at +-60 and +-120 deg, so that at the same wheel speeds it moves sideways
(along the goal line) 1.73 times as fast as forwards. Both are configurable (``config/nubot_hwcontrol.yaml``):
measure your own robot.
Wheel order: as listed in ``wheel_angles_deg`` (default front-left, rear-left, rear-right, front-right).
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property

import numpy as np

from nubot_common import NubotCommonError
from nubot_common.arrays import FloatArray


@dataclass(frozen=True)
class WheelLayout:
    wheel_angles_deg: tuple[float, ...] = (45.0, 135.0, -135.0, -45.0)  # each wheel's position [deg]
    wheel_distance: float = 0.203  # robot centre to wheel [m]
    wheel_diameter: float = 0.12  # [m]
    gear_ratio: float = 21.0  # motor revolutions per wheel revolution
    max_motor_rpm: float = 12000.0  # the drives' limit [rpm]

    def __post_init__(self) -> None:
        if len(self.wheel_angles_deg) < 3:
            raise NubotCommonError(f"a holonomic base needs at least 3 wheels, got {len(self.wheel_angles_deg)}")
        values = (*self.wheel_angles_deg, self.wheel_distance, self.wheel_diameter, self.gear_ratio,
                  self.max_motor_rpm)
        if not all(math.isfinite(v) for v in values):
            raise NubotCommonError(f"wheel layout values must be finite, got {values}")
        for name in ("wheel_distance", "wheel_diameter", "gear_ratio", "max_motor_rpm"):
            if getattr(self, name) <= 0.0:
                raise NubotCommonError(f"wheel layout: {name} must be positive, got {getattr(self, name)}")
        if np.linalg.matrix_rank(self.matrix) < 3:
            raise NubotCommonError(f"wheels at {self.wheel_angles_deg} deg cannot move the base in every direction")

    @property
    def wheels(self) -> int:
        return len(self.wheel_angles_deg)

    @cached_property
    def matrix(self) -> FloatArray:
        """(wheels x 3): rim speeds = matrix @ (vx, vy, w)."""
        phi = np.radians(np.asarray(self.wheel_angles_deg, dtype=float))
        return np.column_stack([-np.sin(phi), np.cos(phi), np.full(phi.shape, self.wheel_distance)])

    @cached_property
    def _pseudo_inverse(self) -> FloatArray:
        return np.linalg.pinv(self.matrix)

    @property
    def max_rim_speed(self) -> float:
        """The rim speed at the motors' limit [m/s]."""
        return self.motor_rpm_to_rim(self.max_motor_rpm)

    def wheel_speeds(self, vx: float, vy: float, w: float) -> FloatArray:
        """Rim speeds [m/s] for a body velocity (vx, vy [m/s], w [rad/s], body frame)."""
        speeds: FloatArray = self.matrix @ np.array([vx, vy, w], dtype=float)
        return speeds

    def body_velocity(self, rim_speeds: FloatArray) -> tuple[float, float, float]:
        """The body velocity that best explains the wheels' rim speeds (least squares)."""
        speeds = np.asarray(rim_speeds, dtype=float)
        if speeds.shape != (self.wheels,):
            raise NubotCommonError(f"expected {self.wheels} wheel speeds, got shape {speeds.shape}")
        vx, vy, w = self._pseudo_inverse @ speeds
        return float(vx), float(vy), float(w)

    def rim_to_motor_rpm(self, rim_speed: FloatArray | float) -> FloatArray | float:
        return np.asarray(rim_speed) * (60.0 * self.gear_ratio / (math.pi * self.wheel_diameter))

    def motor_rpm_to_rim(self, rpm: float) -> float:
        return float(rpm) * math.pi * self.wheel_diameter / (60.0 * self.gear_ratio)

    def limit(self, rim_speeds: FloatArray) -> tuple[FloatArray, float]:
        """Scale all wheels down together when one exceeds the motors' limit, which keeps the direction of
        motion and the ratio of turning to driving; returns the speeds and the factor (1 if within limits)."""
        speeds = np.asarray(rim_speeds, dtype=float)
        peak = float(np.max(np.abs(speeds))) if speeds.size else 0.0
        if peak <= self.max_rim_speed:
            return speeds, 1.0
        scale = self.max_rim_speed / peak
        return speeds * scale, scale


REGULAR = WheelLayout()
GOALIE = WheelLayout(wheel_angles_deg=(60.0, 120.0, -120.0, -60.0))
LAYOUTS = {"regular": REGULAR, "goalie": GOALIE}


@dataclass(frozen=True)
class BodyLimits:
    """The software limits on a body velocity command (before the wheels' own limit)."""

    max_speed: float = 5.0  # [m/s]
    max_rotation: float = 12.0  # [rad/s]

    def __post_init__(self) -> None:
        if not (self.max_speed > 0.0 and self.max_rotation > 0.0):
            raise NubotCommonError(f"body limits must be positive, got {self.max_speed}, {self.max_rotation}")

    def apply(self, vx: float, vy: float, w: float) -> tuple[float, float, float]:
        """Clip the speed (keeping the direction) and the rotation; refuses a command that is not finite."""
        if not all(math.isfinite(v) for v in (vx, vy, w)):
            raise NubotCommonError(f"velocity command must be finite, got ({vx}, {vy}, {w})")
        speed = math.hypot(vx, vy)
        if speed > self.max_speed:
            vx, vy = vx * self.max_speed / speed, vy * self.max_speed / speed
        return vx, vy, max(-self.max_rotation, min(self.max_rotation, w))
