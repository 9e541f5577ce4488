"""The simulated front camera: what it shows where (ground, lines, ball on the ground and in the air, robots),
determinism from the sensors' seed, its cost, and the simulator's front_camera_frame."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import OmniCameraParams
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator
from sim_visual.world import BallState, RobotState

SCENE = OmniCameraParams()
ME = RobotState(1.0, -2.0, 0.0, 0.0, 0.0, 0.0)  # facing +x


@pytest.fixture(scope="module")
def clean() -> FrontCameraRenderer:
    """No noise: pixels keep the scene's colours."""
    return FrontCameraRenderer(WorldDescription(), FrontCameraParams(noise_std=0.0), SCENE)


def _ball(x: float, y: float, z: float = 0.11) -> BallState:
    return BallState(ME.x + x, ME.y + y, z, 0.0, 0.0, 0.0)


def _is_orange(rgb: np.ndarray) -> bool:
    r, g, b = (int(c) for c in rgb)
    return r > 120 and r > 1.8 * g and g > 1.5 * b


@pytest.mark.parametrize("z", [0.11, 0.3, 0.45])
def test_the_ball_shows_where_its_centre_projects_on_the_ground_and_in_the_air(clean, z: float) -> None:
    image = clean.render(ME, _ball(1.2, 0.2, z), [], 0.0, np.random.default_rng(0))
    uv, ahead = clean.camera.project(np.array([[1.2, 0.2, z]]))
    u, v = (int(round(c)) for c in uv[0])
    assert ahead[0] and 0 <= u < 320 and 0 <= v < 240
    assert _is_orange(image[v, u]), f"the ball's centre pixel ({u}, {v}) is {image[v, u]}"
    assert not _is_orange(image[v, min(u + 40, 319)]), "and 40 px beside it is no ball"


def test_the_ground_shows_carpet_and_the_lines_where_they_lie(clean) -> None:
    me = RobotState(-1.0, 0.0, 0.0, 0.0, 0.0, 0.0)  # the halfway line 1 m ahead, across the image
    image = clean.render(me, BallState(-5.0, 3.0, 0.11, 0, 0, 0), [], 0.0, np.random.default_rng(0))
    on_line, _ = clean.camera.project(np.array([[1.0, 0.0, 0.0], [1.5, 0.0, 0.0]]))
    (u0, v0), (u1, v1) = np.round(on_line).astype(int)
    assert image[v0, u0].min() > 180, "the halfway line is white"
    assert image[v1, u1][1] > image[v1, u1][0] + 40, "the carpet beyond is green"


def test_a_robot_hides_the_ground_behind_it(clean) -> None:
    other = RobotState(ME.x + 1.8, ME.y, 0.0, 0.0, 0.0, 0.0)
    image = clean.render(ME, _ball(-3.0, 0.0), [other], 0.0, np.random.default_rng(0))
    uv, _ = clean.camera.project(np.array([[1.8 - 0.26, 0.0, 0.3]]))
    u, v = (int(round(c)) for c in uv[0])
    assert image[v, u].max() < 60, "a dark robot"


def test_a_ball_partly_out_of_view_behind_or_at_the_lens_renders_without_error(clean) -> None:
    rng = np.random.default_rng(0)
    for x, y, z in [(0.45, 0.0, 0.11), (1.0, 0.6, 0.11), (0.2, 0.0, 0.55), (-1.0, 0.0, 0.11), (0.3, 0.0, 2.0)]:
        image = clean.render(ME, _ball(x, y, z), [], 0.0, rng)
        assert image.shape == (240, 320, 3) and image.dtype == np.uint8


def test_the_same_seed_gives_the_same_frames_and_noise_is_drawn_from_the_generator() -> None:
    renderer = FrontCameraRenderer(WorldDescription(), FrontCameraParams(), SCENE)
    frames = [renderer.render(ME, _ball(1.0, 0.0), [], 0.5, np.random.default_rng(9)) for _ in range(2)]
    assert np.array_equal(*frames)
    other = renderer.render(ME, _ball(1.0, 0.0), [], 0.5, np.random.default_rng(10))
    assert not np.array_equal(frames[0], other)


def test_the_simulator_renders_each_robots_front_camera_from_the_sensors_generator() -> None:
    def frame(seed: int) -> np.ndarray:
        sim = Simulator(SimConfig(robots=(RobotSpawn("nubot2", -1.0, 0.0, 0.0),), ball_start=(0.0, 0.0), seed=seed))
        sim.step()
        return sim.front_camera_frame("nubot2")

    a, b = frame(4), frame(4)
    assert a.shape == (240, 320, 3) and np.array_equal(a, b)
    assert not np.array_equal(a, frame(5))
    centre = a[:, :, 0].astype(int) - a[:, :, 1]  # the ball 1 m ahead: red over green
    assert (centre > 80).sum() > 500


def test_front_camera_parameters_are_read_from_the_simulator_configuration() -> None:
    config = from_mapping(SimConfig, {"sensors": {"front_camera": {"noise_std": 1.0, "camera": {"pitch_deg": 30.0}}}})
    assert config.sensors.front_camera.noise_std == 1.0 and config.sensors.front_camera.camera.pitch_deg == 30.0
    with pytest.raises(NubotCommonError, match="pitch_deg"):
        from_mapping(SimConfig, {"sensors": {"front_camera": {"camera": {"pitch_deg": 120.0}}}})
    with pytest.raises(ValueError, match="max_range"):
        FrontCameraParams(max_range=0.1)
    with pytest.raises(NubotCommonError, match="fx"):
        replace(FrontCameraParams().camera, fx=0.0)
    assert math.isfinite(FrontCameraParams().camera.fx)
