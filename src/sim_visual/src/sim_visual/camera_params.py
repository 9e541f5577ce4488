"""The simulated omni camera's parameters (``OmniCameraParams``), apart from its renderer so that reading a
simulator configuration does not load OpenCV.

Parameters: lighting across the field (world-fixed: relative amplitude, wavelength [m]), lighting over time
(relative amplitude, period [s]), pixel noise [grey levels, 0-255], the ground texture's resolution
[m/texel], the RGB colours of carpet, lines (and goal frame), goal inside, ball, robots (and the own body)
and surroundings, and the mirror holder's struts' bearings [deg] and width [px]. ``omni_camera`` renders
with them.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np

from nubot_common.params import require_positive

RGB = tuple[int, int, int]

MAX_NOISE_STD = 40.0  # [grey levels]; the noise table reaches 2.7 std, which must stay inside 0-255


@dataclass(frozen=True)
class OmniCameraParams:
    lighting_field_amplitude: float = 0.25  # brightness 1 +- this across the field (world-fixed)
    lighting_wavelength: float = 8.0  # [m] period of the field's lighting pattern along x and y
    lighting_time_amplitude: float = 0.10  # brightness 1 +- this over time
    lighting_period: float = 60.0  # [s]
    noise_std: float = 4.0  # [grey levels] per pixel and channel
    texture_resolution: float = 0.02  # [m] per texel of the field's ground texture
    carpet_rgb: RGB = (40, 130, 50)
    line_rgb: RGB = (235, 235, 235)  # lines, goal posts and the goals' ground frames
    goal_inside_rgb: RGB = (45, 50, 45)  # the ground inside a goal
    ball_rgb: RGB = (245, 110, 20)
    robot_rgb: RGB = (30, 30, 30)  # other robots and the own body (mirror holder included)
    surround_rgb: RGB = (110, 100, 90)  # beyond the arena (lines plus border)
    strut_angles_deg: tuple[float, ...] = (60.0, 180.0, 300.0)  # struts' bearings, 0 ahead, counter-clockwise
    strut_width: float = 4.0  # [px]; 0: no struts

    def __post_init__(self) -> None:
        for name in ("lighting_field_amplitude", "lighting_time_amplitude"):
            if not 0.0 <= getattr(self, name) < 1.0:
                raise ValueError(f"{name} must lie in [0, 1), got {getattr(self, name)}")
        require_positive(self, "lighting_wavelength", "lighting_period")
        if not 0.0 <= self.noise_std <= MAX_NOISE_STD:
            raise ValueError(f"noise_std must lie in [0, {MAX_NOISE_STD:g}] grey levels, got {self.noise_std}")
        if not 0.005 <= self.texture_resolution <= 0.1:
            raise ValueError(f"texture_resolution must lie in [0.005, 0.1] m, got {self.texture_resolution}")
        for name in ("carpet_rgb", "line_rgb", "goal_inside_rgb", "ball_rgb", "robot_rgb", "surround_rgb"):
            value = getattr(self, name)
            if len(value) != 3 or not all(isinstance(c, int) and 0 <= c <= 255 for c in value):
                raise ValueError(f"{name} must be three integers in [0, 255], got {value}")
        if len(self.strut_angles_deg) > 12 or not all(math.isfinite(a) for a in self.strut_angles_deg):
            raise ValueError(f"strut_angles_deg must be at most 12 finite angles, got {self.strut_angles_deg}")
        if not 0.0 <= self.strut_width <= 40.0:
            raise ValueError(f"strut_width must lie in [0, 40] px, got {self.strut_width}")

    def field_lighting(self, x: np.ndarray | float, y: np.ndarray | float) -> np.ndarray:
        """Relative brightness at the world point (x, y) [m]: brightest at the centre spot."""
        k = 2.0 * math.pi / self.lighting_wavelength
        return 1.0 + self.lighting_field_amplitude * np.cos(k * np.asarray(x)) * np.cos(k * np.asarray(y))

    def time_lighting(self, t: float) -> float:
        """Relative brightness at the time ``t`` [s]."""
        return 1.0 + self.lighting_time_amplitude * math.sin(2.0 * math.pi * t / self.lighting_period)
