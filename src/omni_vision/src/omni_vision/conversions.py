"""sensor_msgs/Image and sensor_msgs/Imu <-> numpy, for the omni camera's nodes (no rospy).

Provides ``image_to_array`` (an RGB ``uint8`` H x W x 3 array from an ``rgb8``, ``bgr8`` or ``yuv422``
image message, with a clear ``OmniVisionError`` for any other encoding or a size that does not match
its data), ``array_to_image`` (an ``rgb8`` or ``mono8`` message from an array) and
``imu_yaw`` (the heading [rad] of an Imu message's orientation) and ``localization_error_msg`` (a frame's
self-localization against the simulator's truth).
"""

from __future__ import annotations

import math

import numpy as np

from nubot_common.geometry import Pose2D, quaternion_to_yaw, wrap_angle
from nubot_common.percepts import RobotView
from omni_vision import OmniVisionError

SUPPORTED_ENCODINGS = ("rgb8", "bgr8", "yuv422")


def image_to_array(msg) -> np.ndarray:  # noqa: ANN001 (a sensor_msgs/Image)
    """The image as RGB ``uint8`` (height x width x 3); raise ``OmniVisionError`` saying what is wrong."""
    encoding = msg.encoding.lower()
    if encoding not in SUPPORTED_ENCODINGS:
        raise OmniVisionError(f"image encoding {msg.encoding!r} unsupported; "
                              f"use one of {', '.join(SUPPORTED_ENCODINGS)}")
    channels = 2 if encoding == "yuv422" else 3
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    if h <= 0 or w <= 0 or step < w * channels:
        raise OmniVisionError(f"image of {w} x {h} px with row step {step} B: not a {encoding} image")
    data = np.frombuffer(msg.data, dtype=np.uint8)
    if data.size < h * step:
        raise OmniVisionError(f"image of {w} x {h} px ({encoding}) needs {h * step} B, got {data.size}")
    rows = data[:h * step].reshape(h, step)[:, :w * channels]
    import cv2

    if encoding == "rgb8":
        return np.ascontiguousarray(rows.reshape(h, w, 3))
    if encoding == "bgr8":
        return cv2.cvtColor(rows.reshape(h, w, 3), cv2.COLOR_BGR2RGB)
    return cv2.cvtColor(rows.reshape(h, w, 2), cv2.COLOR_YUV2RGB_UYVY)


def array_to_image(array: np.ndarray, msg_type, stamp, frame_id: str = ""):  # noqa: ANN001, ANN201
    """A ``msg_type`` (sensor_msgs/Image) holding ``array``: H x W x 3 as ``rgb8``, H x W as ``mono8``."""
    array = np.ascontiguousarray(array, dtype=np.uint8)
    if array.ndim == 3 and array.shape[2] == 3:
        encoding = "rgb8"
    elif array.ndim == 2:
        encoding = "mono8"
    else:
        raise OmniVisionError(f"an image must be H x W x 3 (RGB) or H x W (grey), got shape {array.shape}")
    msg = msg_type()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = array.shape[:2]
    msg.encoding = encoding
    msg.is_bigendian = 0
    msg.step = array.strides[0]
    msg.data = array.tobytes()
    return msg


def imu_yaw(msg) -> float:  # noqa: ANN001 (a sensor_msgs/Imu)
    """The heading [rad] of the Imu message's orientation; raise ``OmniVisionError`` for a non-finite one."""
    q = msg.orientation
    values = (q.x, q.y, q.z, q.w)
    norm2 = sum(v * v for v in values)
    if not all(math.isfinite(v) for v in values) or norm2 < 1e-6:
        raise OmniVisionError(f"inertial orientation {values} is not a rotation")
    # quaternion_to_yaw assumes a unit quaternion: a driver's unnormalised one would skew the yaw
    norm = math.sqrt(norm2)
    return quaternion_to_yaw(*(v / norm for v in values))


def localization_error_msg(view: RobotView, localized: bool, truth: Pose2D, msg_type):  # noqa: ANN001, ANN201
    """A nubot_common/LocalizationError of the frame ``view`` against the true pose ``truth`` (team frame)."""
    from nubot_common.conversions import stamp  # generated messages: only where a node converts them

    est = view.robot.pose
    msg = msg_type()
    msg.header.stamp = stamp(view.stamp)
    msg.estimate.x, msg.estimate.y, msg.estimate_heading = est.x, est.y, est.theta
    msg.truth.x, msg.truth.y, msg.true_heading = truth.x, truth.y, truth.theta
    msg.position_error = math.hypot(est.x - truth.x, est.y - truth.y)
    msg.heading_error = abs(wrap_angle(est.theta - truth.theta))
    msg.localized = localized
    return msg
