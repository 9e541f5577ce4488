"""The simulated front camera's parameters (``FrontCameraParams``), apart from its renderer so that reading a
simulator configuration does not load OpenCV's scene drawing.

Parameters: the true camera (``nubot_common.camera_model.PinholeCamera``: intrinsics, distortion, mount on the
robot), pixel noise [grey levels, 0-255], the ground texture's resolution [m/texel], how far the camera sees
the ground [m] (beyond: the surroundings' colour), and the shading of the ball and the robots (the light
comes from above: brightness ``ambient`` + (1 - ``ambient``) x the surface normal's upward component). The
scene's colours and lighting are the omni camera's (``OmniCameraParams``): one world, one palette.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common.camera_model import PinholeCamera
from sim_visual.camera_params import MAX_NOISE_STD


@dataclass(frozen=True)
class FrontCameraParams:
    camera: PinholeCamera = dc_field(default_factory=PinholeCamera)  # the true camera and its mount
    noise_std: float = 3.0  # [grey levels] per pixel and channel
    texture_resolution: float = 0.01  # [m] per texel of the ground texture
    max_range: float = 8.0  # [m] from the camera: the ground beyond shows the surroundings' colour
    ball_ambient: float = 0.55  # the ball's darkest side (its underside) relative to its lit top
    robot_ambient: float = 0.7  # a robot's sides relative to its top

    def __post_init__(self) -> None:
        if not 0.0 <= self.noise_std <= MAX_NOISE_STD:
            raise ValueError(f"noise_std must lie in [0, {MAX_NOISE_STD:g}] grey levels, got {self.noise_std}")
        if not 0.002 <= self.texture_resolution <= 0.05:
            raise ValueError(f"texture_resolution must lie in [0.002, 0.05] m, got {self.texture_resolution}")
        if not (math.isfinite(self.max_range) and 0.5 <= self.max_range <= 30.0):
            raise ValueError(f"max_range must lie in [0.5, 30] m, got {self.max_range}")
        for name in ("ball_ambient", "robot_ambient"):
            if not 0.0 <= getattr(self, name) <= 1.0:
                raise ValueError(f"{name} must lie in [0, 1], got {getattr(self, name)}")
