"""Front camera scenes for the unit tests: sim_visual's renderer (built once) with the ball at a body-frame place."""

from __future__ import annotations

import math
from dataclasses import replace
from functools import lru_cache
from pathlib import Path

import numpy as np

from nubot_common.world_description import WorldDescription
from omni_vision.colors import ColorTable
from sim_visual.camera_params import OmniCameraParams
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.world import BallState, RobotState

PARAMS = FrontCameraParams()
CAMERA = PARAMS.camera  # the simulated camera's truth
BALL_RADIUS = 0.11
ROBOT = RobotState(-2.0, 1.0, 0.4, 0.0, 0.0, 0.0)  # the viewer, off the field's centre, turned
ROOT = Path(__file__).resolve().parents[3]
TABLE_FILE = ROOT / "omni_vision" / "config" / "colors_sim.npz"
CAMERA_FILE = ROOT / "front_vision" / "config" / "front_camera_sim.yaml"


@lru_cache(maxsize=2)
def renderer(noise_std: float = PARAMS.noise_std) -> FrontCameraRenderer:
    return FrontCameraRenderer(WorldDescription(), replace(PARAMS, noise_std=noise_std), OmniCameraParams())


@lru_cache(maxsize=1)
def table() -> ColorTable:
    return ColorTable.load(TABLE_FILE)


def world_point(bx: float, by: float, me: RobotState = ROBOT) -> tuple[float, float]:
    """The world point of body-frame (bx, by) [m] of robot ``me``."""
    c, s = math.cos(me.theta), math.sin(me.theta)
    return me.x + c * bx - s * by, me.y + s * bx + c * by


def render_ball(bx: float, by: float, z: float = BALL_RADIUS, others: tuple[tuple[float, float], ...] = (),
                seed: int = 0, noise_std: float = PARAMS.noise_std) -> np.ndarray:
    """The front camera's image with the ball centred at body-frame (bx, by, z) [m] and robots at body (x, y)."""
    x, y = world_point(bx, by)
    robots = [RobotState(*world_point(ox, oy), 0.0, 0.0, 0.0, 0.0) for ox, oy in others]
    return renderer(noise_std).render(ROBOT, BallState(x, y, z, 0.0, 0.0, 0.0), robots, 1.0,
                                      np.random.default_rng(seed))


def render_empty(seed: int = 0) -> np.ndarray:
    """The front camera's image with the ball far behind the robot."""
    return render_ball(-4.0, 0.0, seed=seed)
