"""Unit tests of kinect_ball.pipeline: both cameras fused in the team frame through their mounts and the robot's
pose, a lob tracked to its touchdown, bad input and determinism."""

import math

import numpy as np
import pytest

from kinect_ball.pipeline import KinectBall, KinectBallParams
from nubot_common.ball_flight import GRAVITY, landing
from nubot_common.clouds import Cloud
from nubot_common.geometry import Pose2D
from nubot_common.kinect_mount import GOALIE_MOUNTS, CameraMount, body_to_team

from .scenes import RADIUS, render

POSE = Pose2D(-8.2, 0.5, 0.3)  # the goalie, team frame


def in_camera(team_point: np.ndarray, mount: CameraMount, pose: Pose2D = POSE) -> np.ndarray:
    """A team-frame point in a camera's frame (the inverse of mount.to_body and body_to_team)."""
    c, s = math.cos(pose.theta), math.sin(pose.theta)
    dx, dy = team_point[0] - pose.x, team_point[1] - pose.y
    body = np.array([c * dx + s * dy, -s * dx + c * dy, team_point[2]])
    return mount.rotation().T @ (body - mount.offset)


def frames(ball: np.ndarray, seed: int = 0, pose: Pose2D = POSE) -> dict[str, Cloud]:
    out = {}
    for k, name in enumerate(("left", "right")):
        mount = GOALIE_MOUNTS.by_name(name)
        centre = in_camera(ball, mount, pose)
        visible = centre[0] > 0.3
        out[name] = render([tuple(centre)] if visible else [], camera_height=5.0, noise=0.003, dropout=0.02,
                           seed=seed * 2 + k)  # the floor far below: the tilted camera's ground is not modelled
    return out


def test_the_inverse_transform_of_the_tests_is_the_pipelines():
    point = np.array([-6.0, 1.0, 1.2])
    mount = GOALIE_MOUNTS.left
    back = body_to_team(mount.to_body(in_camera(point, mount)[None, :]), POSE.x, POSE.y, POSE.theta)[0]
    assert np.allclose(back, point)


def test_a_ball_both_cameras_see_is_fused_in_the_team_frame():
    """Straight ahead of the goalie, in the overlap of both views: each camera's sighting and the fused one lie
    within a centimetre of the truth."""
    ahead = np.array([POSE.x + 3.0 * math.cos(POSE.theta), POSE.y + 3.0 * math.sin(POSE.theta), 0.9])
    clouds = frames(ahead)
    core = KinectBall(KinectBallParams(), RADIUS)
    both = core.process(1.0, POSE, clouds)
    assert all(r.detection is not None for r in both.reports.values()), both.reason
    assert np.linalg.norm([both.percept.x - ahead[0], both.percept.y - ahead[1], both.percept.z - ahead[2]]) < 0.01
    for name in ("left", "right"):
        one = KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, {name: clouds[name]}).percept
        assert np.linalg.norm([one.x - ahead[0], one.y - ahead[1], one.z - ahead[2]]) < 0.015


def test_a_ball_to_one_side_is_seen_by_that_camera_only():
    left_of_goalie = np.array([POSE.x + 1.5, POSE.y + 2.5, 0.5])
    result = KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, frames(left_of_goalie))
    assert result.reports["left"].detection is not None and result.reports["right"].detection is None
    assert np.linalg.norm([result.percept.x - left_of_goalie[0], result.percept.y - left_of_goalie[1]]) < 0.015


def test_two_far_apart_sightings_keep_the_better_supported():
    near, far = np.array([-6.9, 2.0, 0.5]), np.array([-4.3, -0.5, 0.5])  # in the left and the right view
    clouds = frames(near)
    clouds["right"] = frames(far)["right"]
    result = KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, clouds)
    assert all(r.detection is not None for r in result.reports.values())
    assert np.linalg.norm([result.percept.x - near[0], result.percept.y - near[1]]) < 0.02


def test_a_lob_is_tracked_to_its_touchdown():
    """A lob towards the goalie, seen at 30 Hz: the touchdown predicted 0.3 s before it lands is within 10 cm."""
    start, v = np.array([-3.0, 1.5, 0.12]), np.array([-5.5, -0.6, 4.2])
    core = KinectBall(KinectBallParams(), RADIUS)
    truth = landing(*start, *v, RADIUS)
    down = None
    for t in np.arange(0.0, truth.t - 0.3, 1 / 30):
        p = start + v * t
        p[2] += 0.5 * GRAVITY * t * t
        result = core.process(float(t), POSE, frames(p, seed=int(t * 30)))
        down = result.touchdown or down
    assert down is not None
    assert math.hypot(down.x - truth.x, down.y - truth.y) < 0.10


def test_without_a_pose_a_seen_ball_is_no_percept_and_says_why():
    result = KinectBall(KinectBallParams(), RADIUS).process(1.0, None, frames(np.array([-6.0, 0.6, 0.5])))
    assert result.percept is None and result.reason == "seen, but no self-localization yet"


def test_bad_and_empty_input_give_no_percept_and_the_reasons():
    empty = Cloud(np.zeros((0, 3)), np.zeros((0, 3), np.uint8), (0, 0))
    nan = Cloud(np.full((10, 3), np.nan), np.zeros((10, 3), np.uint8), (2, 5))
    result = KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, {"left": empty, "right": nan})
    assert result.percept is None and result.reason == "left: empty cloud; right: no finite points"
    result = KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, {})
    assert result.percept is None and result.reason == "no cloud"
    with pytest.raises(ValueError, match="no camera named 'top'"):
        KinectBall(KinectBallParams(), RADIUS).process(1.0, POSE, {"top": empty})


def test_the_same_seed_gives_the_same_results():
    clouds = frames(np.array([-5.0, 0.8, 1.0]))
    a = KinectBall(KinectBallParams(seed=3), RADIUS).process(1.0, POSE, clouds).percept
    b = KinectBall(KinectBallParams(seed=3), RADIUS).process(1.0, POSE, clouds).percept
    assert a == b
