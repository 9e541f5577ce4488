"""Unit tests of omni_vision.debug: the debug image drawn over a rendered camera frame."""

import math
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from nubot_common.params import load_yaml
from nubot_common.world_description import load_world
from omni_vision.colors import ColorTable
from omni_vision.debug import draw_debug_image
from omni_vision.pipeline import OmniVision, OmniVisionParams, VisionFrame
from sim_visual.sensors import RobotSensors, SensorParams
from sim_visual.world import BallState, RobotState

CONFIG = Path(__file__).resolve().parents[2] / "config"
WORLD = load_world("18x12")
PARAMS = load_yaml(OmniVisionParams, CONFIG / "omni_vision.yaml")
RED, YELLOW = (255, 0, 0), (255, 255, 0)
ME = RobotState(2.0, -1.0, 0.5, 0.0, 0.0, 0.0)
BALL = (3.5, 0.2)  # world frame [m], 1.9 m ahead-left


@pytest.fixture(scope="module")
def scene() -> tuple[np.ndarray, VisionFrame, OmniVision]:
    """A localized frame with lines, the ball and one robot in view."""
    sensors = RobotSensors(WORLD, SensorParams(), seed=2)
    vision = OmniVision(WORLD, PARAMS, ColorTable.load(CONFIG / "colors_sim.npz"), agent_id=1)
    ball = BallState(*BALL, WORLD.ball.radius, 0.0, 0.0, 0.0)
    others = [RobotState(0.0, -3.0, 0.0, 0.0, 0.0, 0.0)]
    for k in range(3):
        t = k / 30.0
        vision.odometry(t, 0.0, 0.0, 0.0)
        vision.inertial(t, ME.theta)
        image = sensors.camera(t, ME, ball, others).image
        frame = vision.process(t, image)
    assert frame.localized and frame.ball is not None and len(frame.lines.pixels) > 50
    return image, frame, vision


def test_the_debug_image_is_rgb_of_the_frames_size_and_leaves_the_frame_alone(scene):
    """The debug image is an RGB uint8 image as large as the camera frame, differs from it, and drawing it does
    not change the frame."""
    image, frame, vision = scene
    before = image.copy()
    out = draw_debug_image(image, frame, vision)
    assert out.shape == image.shape and out.dtype == np.uint8
    assert not np.array_equal(out, image)
    np.testing.assert_array_equal(image, before)


def test_line_points_are_drawn_red_where_they_were_found(scene):
    """Each white line point shows as a red dot at its pixel (bar the few the ball, robot marks or text cover)."""
    image, frame, vision = scene
    out = draw_debug_image(image, frame, vision)
    u = np.rint(frame.lines.pixels[:, 0]).astype(int)
    v = np.rint(frame.lines.pixels[:, 1]).astype(int)
    red = np.all(out[v, u] == RED, axis=1)
    assert red.mean() > 0.95, f"only {red.mean():.0%} of the line points are red"
    assert not np.all(image[v, u] == RED, axis=1).any(), "the frame itself has no pure red there"


def test_the_ball_is_circled_in_yellow_around_it(scene):
    """A yellow circle is drawn around the detected ball, and nowhere else."""
    image, frame, vision = scene
    out = draw_debug_image(image, frame, vision)
    yellow = (out[..., 0] > 230) & (out[..., 1] > 230) & (out[..., 2] < 60)
    assert yellow.sum() > 20
    # where the ball truly is in the image (its ground contact, through the mirror model)
    c, s = math.cos(ME.theta), math.sin(ME.theta)
    dx, dy = BALL[0] - ME.x, BALL[1] - ME.y
    u, v = vision.mirror.body_to_pixel(c * dx + s * dy, -s * dx + c * dy)
    rows, cols = np.nonzero(yellow)
    distance = np.hypot(cols - float(u), rows - float(v))
    assert distance.max() < 14.0, f"yellow {distance.max():.0f} px from the ball"
    assert yellow.sum() < 0.2 * yellow.size, "not painted over the whole image"


def test_no_ball_no_yellow_circle(scene):
    """Without a detected ball no circle is drawn (the yellow marks the ball, nothing else)."""
    image, frame, vision = scene
    out = draw_debug_image(image, replace(frame, ball=None), vision)
    yellow = (out[..., 0] > 230) & (out[..., 1] > 230) & (out[..., 2] < 60)
    assert not yellow.any()
