"""FrontBallInfo and CameraInfo messages: round trips, the polar convention, unknown and non-finite balls."""

from __future__ import annotations

import math

import pytest
from sensor_msgs.msg import CameraInfo

from nubot_common import NubotCommonError
from nubot_common.camera_info import camera_info_msg, camera_intrinsics
from nubot_common.camera_model import PinholeCamera
from nubot_common.conversions import front_ball, front_ball_info_msg, stamp
from nubot_common.percepts import BallPercept


def test_front_ball_info_is_polar_from_the_robots_front() -> None:
    msg = front_ball_info_msg(BallPercept(4.5, 1.0, 1.0), 0.0, "nubot2/base_link")
    assert msg.pos_known and msg.header.frame_id == "nubot2/base_link"
    assert msg.real_pos.angle == pytest.approx(math.pi / 4) and msg.real_pos.radius == pytest.approx(math.sqrt(2))
    back = front_ball(msg, 0.0)
    assert back is not None and (back.stamp, back.x, back.y) == pytest.approx((4.5, 1.0, 1.0), abs=1e-6)


def test_an_unknown_ball_is_pos_known_false_at_the_frames_time() -> None:
    msg = front_ball_info_msg(None, 7.25)
    assert not msg.pos_known and msg.header.stamp == stamp(7.25)
    assert front_ball(msg, 0.0) is None
    assert not front_ball_info_msg(BallPercept(1.0, math.nan, 0.0), 1.0).pos_known
    msg.pos_known, msg.real_pos.radius = True, math.inf
    assert front_ball(msg, 0.0) is None


def test_camera_info_carries_the_true_intrinsics() -> None:
    camera = PinholeCamera(fx=231.0, cy=118.0, distortion=(-0.06, 0.02, 0.001, 0.0, 0.0))
    msg = camera_info_msg(camera, CameraInfo, stamp(2.0), "nubot2/front_camera")
    assert (msg.width, msg.height, msg.distortion_model) == (320, 240, "plumb_bob")
    assert PinholeCamera(**camera_intrinsics(msg)) == PinholeCamera(fx=231.0, cy=118.0,
                                                                   distortion=(-0.06, 0.02, 0.001, 0.0, 0.0))
    msg.distortion_model = "equidistant"
    with pytest.raises(NubotCommonError, match="plumb_bob"):
        camera_intrinsics(msg)
