"""A ball in flight without drag: its height, where it comes down, where it crosses a line.

One home for the parabola every package uses: the simulator aims its lob shots with it, kinect_ball and
the world model predict where a lofted ball lands, the goalie decides where to meet it. Positions [m]
(z of the ball's centre), velocities [m/s], times [s], ``gravity`` [m/s^2] along z (negative: down).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

GRAVITY = -9.8  # the simulator's default, and close enough to any field on Earth [m/s^2]


@dataclass(frozen=True)
class Landing:
    """Where and when a flying ball's centre comes down to a given height."""

    x: float  # [m]
    y: float  # [m]
    t: float  # from now [s]; 0 when it is already at or below that height


def height_at(distance: float, horizontal_speed: float, vz: float, z0: float, gravity: float = GRAVITY) -> float:
    """Height [m] of the ball after travelling ``distance`` horizontally at ``horizontal_speed``."""
    t = distance / horizontal_speed
    return z0 + vz * t + 0.5 * gravity * t * t


def landing(x: float, y: float, z: float, vx: float, vy: float, vz: float, ground_z: float,
            gravity: float = GRAVITY) -> Landing:
    """Where and when the ball starting at (x, y, z) with (vx, vy, vz) comes down to ``ground_z`` (later root).

    A ball at or below ``ground_z`` that does not rise lands where it is, now."""
    if z <= ground_z and vz <= 0.0:
        return Landing(x, y, 0.0)
    a, b, c = 0.5 * gravity, vz, z - ground_z
    t = (-b - math.sqrt(max(b * b - 4.0 * a * c, 0.0))) / (2.0 * a)
    return Landing(x + vx * t, y + vy * t, max(t, 0.0))


def time_to_x(x: float, vx: float, line_x: float) -> float | None:
    """Time [s] until the ball's x reaches ``line_x``; None when it moves away from it (or not along x)."""
    if abs(vx) < 1e-9:
        return None
    t = (line_x - x) / vx
    return t if t >= 0.0 else None
