"""sensor_msgs/CameraInfo <-> ``PinholeCamera``, for the simulator's front camera and its readers (no rospy).

Provides ``camera_info_msg`` (a CameraInfo with the camera's intrinsics: ``plumb_bob`` distortion D = k1 k2 p1 p2
k3, K, R = identity, P = [K | 0]) and ``camera_intrinsics`` (a CameraInfo's size, K and D back, checked, as the
keyword arguments ``PinholeCamera`` takes; the mount is not in a CameraInfo). The FrontBallInfo message has its
converters in ``nubot_common.conversions`` (``front_ball_info_msg``, ``front_ball``).
"""

from __future__ import annotations

import math
from typing import Any

from nubot_common import NubotCommonError
from nubot_common.camera_model import PinholeCamera


def camera_info_msg(camera: PinholeCamera, msg_type: type[Any], stamp: Any, frame_id: str = "") -> Any:
    """A ``msg_type`` (sensor_msgs/CameraInfo) of ``camera``'s intrinsics."""
    msg = msg_type()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = camera.height, camera.width
    msg.distortion_model = "plumb_bob"
    msg.D = list(camera.distortion)
    msg.K = [camera.fx, 0.0, camera.cx, 0.0, camera.fy, camera.cy, 0.0, 0.0, 1.0]
    msg.R = [1.0, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0]
    msg.P = [camera.fx, 0.0, camera.cx, 0.0, 0.0, camera.fy, camera.cy, 0.0, 0.0, 0.0, 1.0, 0.0]
    return msg


def camera_intrinsics(msg: Any) -> dict[str, object]:  # a sensor_msgs/CameraInfo
    """The intrinsics of a CameraInfo (width, height, fx, fy, cx, cy, distortion); raise ``NubotCommonError`` for
    another distortion model or values that are no camera."""
    if msg.distortion_model not in ("plumb_bob", "") or len(msg.D) not in (0, 5) or len(msg.K) != 9:
        raise NubotCommonError(f"camera info: need plumb_bob distortion (5 values) and a 3 x 3 K, got "
                               f"{msg.distortion_model!r} with {len(msg.D)} and {len(msg.K)} values")
    values = [float(v) for v in list(msg.K) + list(msg.D)]
    if not all(math.isfinite(v) for v in values):
        raise NubotCommonError("camera info: K and D must be finite")
    d = tuple(float(v) for v in msg.D) if len(msg.D) == 5 else (0.0,) * 5
    return {"width": int(msg.width), "height": int(msg.height), "fx": float(msg.K[0]), "fy": float(msg.K[4]),
            "cx": float(msg.K[2]), "cy": float(msg.K[5]), "distortion": d}
