"""Unit tests of nubot_common.kinect_mount: the cameras' fixed transforms into the body frame and the team frame."""

import math

import numpy as np
import pytest

from nubot_common.kinect_mount import GOALIE_MOUNTS, CameraMount, body_to_team


def test_the_optical_axis_points_along_yaw_and_pitch():
    mount = CameraMount(x=0.2, y=0.1, z=0.6, yaw_deg=30.0, pitch_deg=15.0)
    axis = mount.rotation() @ np.array([1.0, 0.0, 0.0])
    c = math.cos(math.radians(15.0))
    assert np.allclose(axis, [c * math.cos(math.radians(30)), c * math.sin(math.radians(30)),
                              math.sin(math.radians(15.0))])
    assert np.allclose(mount.to_body(np.zeros((1, 3))), [[0.2, 0.1, 0.6]])
    assert np.allclose(mount.rotation() @ mount.rotation().T, np.eye(3))


def test_the_goalie_cameras_look_left_and_right_of_its_front():
    assert GOALIE_MOUNTS.left.yaw_deg > 0 > GOALIE_MOUNTS.right.yaw_deg
    assert GOALIE_MOUNTS.by_name("left") is GOALIE_MOUNTS.left
    with pytest.raises(ValueError, match="no camera named 'middle'"):
        GOALIE_MOUNTS.by_name("middle")


def test_body_points_turn_with_the_robot():
    out = body_to_team(np.array([[1.0, 0.0, 0.5]]), -8.0, 1.0, math.pi / 2)
    assert np.allclose(out, [[-8.0, 2.0, 0.5]])


def test_a_mount_off_the_robot_is_refused():
    with pytest.raises(ValueError, match="z must lie in"):
        CameraMount(z=0.0)
