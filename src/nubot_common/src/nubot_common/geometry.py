"""2-D geometry for a planar robot on the field (SI units, REP 103 frames).

Provides: ``wrap_angle``, ``Pose2D`` (x [m], y [m], theta [rad]) with frame
conversions between the field (world) frame and a robot body frame, polar
helpers, and ``yaw_to_quaternion`` / ``quaternion_to_yaw`` for 3-D poses.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_common.records import fast_init


def wrap_angle(angle: float) -> float:
    """Wrap an angle [rad] into (-pi, pi]."""
    wrapped = math.fmod(angle + math.pi, 2.0 * math.pi)
    if wrapped <= 0.0:
        wrapped += 2.0 * math.pi
    return wrapped - math.pi


def rotate(x: float, y: float, angle: float) -> tuple[float, float]:
    """Rotate the vector (x, y) counter-clockwise by ``angle`` [rad]."""
    c, s = math.cos(angle), math.sin(angle)
    return c * x - s * y, s * x + c * y


def to_polar(x: float, y: float) -> tuple[float, float]:
    """Return (angle [rad], radius [m]) of the vector (x, y)."""
    return math.atan2(y, x), math.hypot(x, y)


@fast_init
@dataclass(frozen=True)
class Pose2D:
    """A pose in the field plane: position [m] and heading [rad] (counter-clockwise from +x)."""

    x: float = 0.0
    y: float = 0.0
    theta: float = 0.0

    @classmethod
    def looking_at(cls, x: float, y: float, fx: float, fy: float) -> Pose2D:
        """The pose at (x, y) [m] facing the point (fx, fy) [m]."""
        return cls(x, y, math.atan2(fy - y, fx - x))

    def to_body(self, px: float, py: float) -> tuple[float, float]:
        """Express the world point (px, py) in this pose's body frame."""
        return rotate(px - self.x, py - self.y, -self.theta)

    def to_world(self, bx: float, by: float) -> tuple[float, float]:
        """Express the body-frame point (bx, by) in the world frame."""
        wx, wy = rotate(bx, by, self.theta)
        return self.x + wx, self.y + wy

    def bearing_to(self, px: float, py: float) -> float:
        """Angle [rad] from this pose's front to the world point (px, py), in (-pi, pi]."""
        return wrap_angle(math.atan2(py - self.y, px - self.x) - self.theta)

    def distance_to(self, px: float, py: float) -> float:
        return math.hypot(px - self.x, py - self.y)


def yaw_to_quaternion(yaw: float) -> tuple[float, float, float, float]:
    """Quaternion (x, y, z, w) of a rotation by ``yaw`` [rad] about +z."""
    return 0.0, 0.0, math.sin(yaw / 2.0), math.cos(yaw / 2.0)


def quaternion_to_yaw(x: float, y: float, z: float, w: float) -> float:
    """Yaw [rad] of the quaternion (x, y, z, w)."""
    return math.atan2(2.0 * (w * z + x * y), 1.0 - 2.0 * (y * y + z * z))
