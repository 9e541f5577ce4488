"""Unit tests of sim_visual.rgbd_camera: the goalie's simulated RGB-D clouds (geometry, colours, range, missing
returns, noise growing with depth) and Simulator.rgbd_frames (deterministic per seed)."""

import dataclasses

import numpy as np
import pytest

from nubot_common.kinect_mount import GOALIE_MOUNTS
from nubot_common.world_description import WorldDescription
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.rgbd_camera import BALL, GOAL, GROUND, LINE, NONE, ROBOT, RgbdCameraParams, RgbdCameraRenderer
from sim_visual.sensors import SensorParams
from sim_visual.simulator import Simulator
from sim_visual.world import BallState, RobotState

WORLD = WorldDescription()
GOALIE = RobotState(-8.0, 0.0, 0.0, 0.0, 0.0, 0.0)
QUIET = RgbdCameraParams(depth_noise_constant=0.0, depth_noise_quadratic=0.0, dropout=0.0, edge_dropout=0.0,
                         color_noise_std=0.0)


def world_points(frame, mount, me=GOALIE):
    """A frame's points in the world frame (the goalie faces +x at its pose)."""
    p = frame.points.reshape(-1, 3)
    ok = np.isfinite(p).all(axis=1)
    body = mount.to_body(p[ok])
    return body + np.array([me.x, me.y, 0.0]), frame.labels.reshape(-1)[ok], frame.rgb.reshape(-1, 3)[ok]


def render(ball, others=(), params=QUIET, seed=0, me=GOALIE):
    return RgbdCameraRenderer(WORLD, params).render(me, ball, list(others), 1.0, np.random.default_rng(seed))


def test_noise_free_returns_lie_on_what_they_hit():
    ball = BallState(-5.0, 1.0, 1.2, 0, 0, 0)
    rival = RobotState(-4.5, -1.5, 0.0, 0, 0, 0)
    for frame in render(ball, [rival]):
        points, labels, rgb = world_points(frame, GOALIE_MOUNTS.by_name(frame.camera))
        ground = points[(labels == GROUND) | (labels == LINE)]
        assert np.allclose(ground[:, 2], 0.0, atol=1e-5)  # float32 points
        on_ball = points[labels == BALL]
        if len(on_ball):
            assert np.allclose(np.linalg.norm(on_ball - [ball.x, ball.y, ball.z], axis=1), WORLD.ball.radius,
                               atol=1e-5)
            assert (rgb[labels == BALL] == QUIET.ball_rgb).all()
        on_robot = points[labels == ROBOT]
        if len(on_robot):
            radial = np.hypot(on_robot[:, 0] - rival.x, on_robot[:, 1] - rival.y)
            assert np.all(radial <= WORLD.robot.radius + 1e-5) and np.all(on_robot[:, 2] <= WORLD.robot.height + 1e-5)
    left, right = render(ball, [rival])
    assert (left.labels == BALL).sum() > 20 and (right.labels == ROBOT).sum() > 100
    assert (left.labels == LINE).any(), "the penalty area's lines in view"


def test_depth_is_limited_to_the_sensors_range():
    left, right = render(BallState(3.0, 0.0, 0.11, 0, 0, 0))
    for frame in (left, right):
        depth = frame.points[..., 0]
        finite = depth[np.isfinite(depth)]
        assert finite.min() >= QUIET.min_range and finite.max() <= QUIET.max_range
        assert not (frame.labels == BALL).any(), "the ball 10.8 m away (9 m deep in either view): beyond the range"
        assert (frame.labels == NONE).sum() == np.isnan(depth).sum()


def test_the_goal_frame_is_drawn():
    facing_goal = RobotState(-5.0, 0.0, np.pi, 0, 0, 0)
    left, right = render(BallState(0.0, 0.0, 0.11, 0, 0, 0), me=facing_goal)
    assert (left.labels == GOAL).sum() + (right.labels == GOAL).sum() > 20


def test_noise_grows_with_depth_and_returns_go_missing():
    params = dataclasses.replace(QUIET, depth_noise_constant=0.002, depth_noise_quadratic=0.0003, dropout=0.05,
                                 edge_dropout=0.5)
    quiet, noisy = render(BallState(-5.0, 1.0, 1.2, 0, 0, 0), params=QUIET)[0], render(
        BallState(-5.0, 1.0, 1.2, 0, 0, 0), params=params)[0]
    both = np.isfinite(quiet.points[..., 0]) & np.isfinite(noisy.points[..., 0])
    depth = quiet.points[..., 0][both]
    error = np.linalg.norm(noisy.points[both] - quiet.points[both], axis=1)
    near, far = error[depth < 3.0], error[depth > 6.0]
    assert np.std(far) > 3 * np.std(near)
    lost = np.isfinite(quiet.points[..., 0]) & ~np.isfinite(noisy.points[..., 0])
    share = lost.sum() / np.isfinite(quiet.points[..., 0]).sum()
    assert 0.05 < share < 0.2, "random dropouts plus more at edges"


def test_simulator_frames_are_deterministic_per_seed():
    def frames(seed):
        config = SimConfig(robots=(RobotSpawn("nubot1", -8.0, 0.0, 0.0, 1), RobotSpawn("rival2", -5.0, 1.0, 3.0, -1)),
                           ball_start=(-5.5, 0.5), seed=seed, sensors=SensorParams())
        sim = Simulator(config)
        sim.step()
        return sim.rgbd_frames("nubot1")
    a, b, c = frames(4), frames(4), frames(5)
    assert all(np.array_equal(x.points, y.points, equal_nan=True) and np.array_equal(x.rgb, y.rgb)
               for x, y in zip(a, b))
    assert not np.array_equal(a[0].points, c[0].points, equal_nan=True)
    assert (a[0].camera, a[1].camera) == ("left", "right") and a[0].points.shape == (106, 128, 3)


def test_parameters_are_checked():
    with pytest.raises(ValueError, match="min_range 9.0 must be below max_range 8.0"):
        RgbdCameraParams(min_range=9.0)
    with pytest.raises(ValueError, match="width must lie in"):
        RgbdCameraParams(width=4)


def test_rendering_the_rgbd_cameras_draws_nothing_from_the_other_sensors_generator():
    """The simulator node renders the clouds only while someone listens: that must not change the omni camera's,
    the odometry's or the inertial sensor's noise."""
    config = SimConfig(robots=(RobotSpawn("nubot1", -8.0, 0.0, 0.0, 1),), seed=2)
    sim, other = Simulator(config), Simulator(config)
    sim.rgbd_frames("nubot1")
    assert sim.sensors.rng.bit_generator.state == other.sensors.rng.bit_generator.state
