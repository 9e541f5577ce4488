"""sensor_msgs/Imu and the localization error <-> numpy, for the omni camera's nodes (no rospy); images are
``nubot_common.images``'.

Provides ``imu_yaw`` (the heading [rad] of an Imu message's orientation) and ``localization_error_msg`` (a frame's
self-localization against the simulator's truth).
"""

from __future__ import annotations

import math

from nubot_common.geometry import Pose2D, quaternion_to_yaw, wrap_angle
from nubot_common.percepts import RobotView
from omni_vision import OmniVisionError


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
