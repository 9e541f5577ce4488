"""Where the goalie's RGB-D cameras sit on the robot: the fixed transform camera frame -> body frame.

Provides: ``CameraMount`` (position [m] and yaw/pitch [deg] of one camera in the robot's body frame: x ahead,
y left, z up from the ground under the robot's centre), ``RgbdMounts`` (the left and the right camera) and
``GOALIE_MOUNTS``, the default both the simulator and kinect_ball use. A camera's own frame is REP 103's body
convention (x along the optical axis, y left, z up), not the optical one (z forward), so a cloud's points
turn into the robot's body frame with one rotation and one offset.

The default mount: both cameras 0.60 m above the ground on the robot's front (0.20 m ahead of its centre,
0.10 m left and right), yawed 32 deg left and right so their 70.6 deg wide views overlap by about 7 deg in the
middle and together see 135 deg of the field ahead of the goal; pitched 15 deg up (60 deg tall view: from 15 deg
below to 45 deg above the horizon), since a goalie must see a lob high overhead more than the ground at its feet
(which the omni camera covers): the ground comes into view 2.2 m ahead, a ball 2 m high at 1.5 m.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as dc_field

import numpy as np

from nubot_common.arrays import FloatArray

MAX_MOUNT_OFFSET = 1.0  # [m] a camera further than this from the robot's centre is no camera on the robot


@dataclass(frozen=True)
class CameraMount:
    x: float = 0.20  # [m] ahead of the robot's centre
    y: float = 0.0  # [m] to its left
    z: float = 0.60  # [m] above the ground
    yaw_deg: float = 0.0  # [deg] counter-clockwise from the robot's front
    pitch_deg: float = 15.0  # [deg] up from the horizon

    def __post_init__(self) -> None:
        for name in ("x", "y"):
            if not abs(getattr(self, name)) <= MAX_MOUNT_OFFSET:
                raise ValueError(f"{name} must lie within +-{MAX_MOUNT_OFFSET:g} m, got {getattr(self, name)}")
        if not 0.0 < self.z <= 2.0:
            raise ValueError(f"z must lie in (0, 2] m, got {self.z}")
        if not abs(self.yaw_deg) <= 180.0:
            raise ValueError(f"yaw_deg must lie in [-180, 180], got {self.yaw_deg}")
        if not abs(self.pitch_deg) < 90.0:
            raise ValueError(f"pitch_deg must lie in (-90, 90), got {self.pitch_deg}")

    def rotation(self) -> FloatArray:
        """The 3 x 3 rotation taking camera-frame vectors to body-frame vectors (yaw about z, then pitch up)."""
        yaw, pitch = math.radians(self.yaw_deg), math.radians(self.pitch_deg)
        cy, sy, cp, sp = math.cos(yaw), math.sin(yaw), math.cos(pitch), math.sin(pitch)
        yaw_m = np.array([[cy, -sy, 0.0], [sy, cy, 0.0], [0.0, 0.0, 1.0]])
        pitch_m = np.array([[cp, 0.0, -sp], [0.0, 1.0, 0.0], [sp, 0.0, cp]])  # x tips up towards +z
        rotation: FloatArray = yaw_m @ pitch_m
        return rotation

    @property
    def offset(self) -> FloatArray:
        return np.array([self.x, self.y, self.z])

    def to_body(self, points: FloatArray) -> FloatArray:
        """Camera-frame points (N x 3) [m] in the body frame."""
        return np.asarray(points, dtype=float) @ self.rotation().T + self.offset


@dataclass(frozen=True)
class RgbdMounts:
    left: CameraMount = dc_field(default_factory=lambda: CameraMount(y=0.10, yaw_deg=32.0))
    right: CameraMount = dc_field(default_factory=lambda: CameraMount(y=-0.10, yaw_deg=-32.0))

    def by_name(self, name: str) -> CameraMount:
        if name not in CAMERAS:
            raise ValueError(f"no camera named {name!r}; cameras: {', '.join(CAMERAS)}")
        return self.left if name == "left" else self.right


CAMERAS = ("left", "right")
GOALIE_MOUNTS = RgbdMounts()


def body_to_team(points: FloatArray, x: float, y: float, theta: float) -> FloatArray:
    """Body-frame points (N x 3) [m] of a robot at (x, y) [m] heading ``theta`` [rad] in the team (or world)
    frame."""
    c, s = math.cos(theta), math.sin(theta)
    p = np.asarray(points, dtype=float)
    out = np.empty_like(p)
    out[:, 0] = x + c * p[:, 0] - s * p[:, 1]
    out[:, 1] = y + s * p[:, 0] + c * p[:, 1]
    out[:, 2] = p[:, 2]
    return out
