"""sensor_msgs/Image <-> numpy (no rospy): what the simulator's cameras publish and the vision nodes read.

Provides ``image_to_array`` (an RGB ``uint8`` H x W x 3 array from an ``rgb8``, ``bgr8`` or ``yuv422`` image
message, with a clear ``NubotCommonError`` for any other encoding or a size that does not match its data) and
``array_to_image`` (an ``rgb8`` or ``mono8`` message from an array).
"""

from __future__ import annotations

from typing import Any

import numpy as np

from nubot_common import NubotCommonError
from nubot_common.arrays import ByteArray

SUPPORTED_ENCODINGS = ("rgb8", "bgr8", "yuv422")


def image_to_array(msg: Any) -> ByteArray:  # a sensor_msgs/Image
    """The image as RGB ``uint8`` (height x width x 3); raise ``NubotCommonError`` saying what is wrong."""
    encoding = msg.encoding.lower()
    if encoding not in SUPPORTED_ENCODINGS:
        raise NubotCommonError(f"image encoding {msg.encoding!r} unsupported; "
                                f"use one of {', '.join(SUPPORTED_ENCODINGS)}")
    channels = 2 if encoding == "yuv422" else 3
    h, w, step = int(msg.height), int(msg.width), int(msg.step)
    if h <= 0 or w <= 0 or step < w * channels:
        raise NubotCommonError(f"image of {w} x {h} px with row step {step} B: not a {encoding} image")
    data = np.frombuffer(msg.data, dtype=np.uint8)
    if data.size < h * step:
        raise NubotCommonError(f"image of {w} x {h} px ({encoding}) needs {h * step} B, got {data.size}")
    rows = data[:h * step].reshape(h, step)[:, :w * channels]
    import cv2

    if encoding == "rgb8":
        return np.ascontiguousarray(rows.reshape(h, w, 3))
    code = cv2.COLOR_BGR2RGB if encoding == "bgr8" else cv2.COLOR_YUV2RGB_UYVY
    rgb: ByteArray = cv2.cvtColor(rows.reshape(h, w, 3 if encoding == "bgr8" else 2), code)
    return rgb


def array_to_image(array: ByteArray, msg_type: type[Any], stamp: Any, frame_id: str = "") -> Any:
    """A ``msg_type`` (sensor_msgs/Image) holding ``array``: H x W x 3 as ``rgb8``, H x W as ``mono8``."""
    array = np.ascontiguousarray(array, dtype=np.uint8)
    if array.ndim == 3 and array.shape[2] == 3:
        encoding = "rgb8"
    elif array.ndim == 2:
        encoding = "mono8"
    else:
        raise NubotCommonError(f"an image must be H x W x 3 (RGB) or H x W (grey), got shape {array.shape}")
    msg = msg_type()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = array.shape[:2]
    msg.encoding = encoding
    msg.is_bigendian = 0
    msg.step = array.strides[0]
    msg.data = array.tobytes()
    return msg
