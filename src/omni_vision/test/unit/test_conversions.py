"""Unit tests of omni_vision.conversions: sensor_msgs/Image and Imu <-> numpy, and LocalizationError, with the
generated message classes."""

import io
import math

import genpy
import numpy as np
import pytest
from sensor_msgs.msg import Image, Imu

from nubot_common import NubotCommonError
from nubot_common.geometry import Pose2D, yaw_to_quaternion
from nubot_common.images import array_to_image, image_to_array
from nubot_common.msg import LocalizationError
from nubot_common.percepts import RobotReport, RobotView
from omni_vision import OmniVisionError
from omni_vision.conversions import imu_yaw, localization_error_msg

RGB = np.array([[[200, 30, 40], [30, 200, 40], [40, 30, 200]],
                [[128, 128, 128], [40, 130, 50], [245, 110, 20]]], np.uint8)  # 3 x 2 px


def image_msg(encoding: str, height: int, width: int, step: int, data: bytes) -> Image:
    return Image(height=height, width=width, encoding=encoding, is_bigendian=0, step=step, data=data)


def uyvy_bytes(rgb: np.ndarray) -> bytes:
    """``rgb`` as UYVY (ROS yuv422, BT.601 video range), each pixel doubled so a pair shares its chroma."""
    f = rgb.astype(np.float64)
    r, g, b = f[..., 0], f[..., 1], f[..., 2]
    y = 16 + 0.257 * r + 0.504 * g + 0.098 * b
    u = 128 - 0.148 * r - 0.291 * g + 0.439 * b
    v = 128 + 0.439 * r - 0.368 * g - 0.071 * b
    quads = np.stack([u, y, v, y], axis=-1)  # one U Y V Y quad per (doubled) pixel
    return np.clip(np.rint(quads), 0, 255).astype(np.uint8).tobytes()


def test_an_rgb8_image_is_read_as_it_is():
    """An rgb8 frame comes out as the same H x W x 3 uint8 RGB array."""
    out = image_to_array(image_msg("rgb8", 2, 3, 9, RGB.tobytes()))
    assert out.dtype == np.uint8 and out.shape == (2, 3, 3)
    np.testing.assert_array_equal(out, RGB)


def test_a_bgr8_image_gets_its_channels_swapped_back_to_rgb():
    """A bgr8 camera (OpenCV's order) gives the same RGB array as an rgb8 one of the same scene."""
    out = image_to_array(image_msg("bgr8", 2, 3, 9, RGB[..., ::-1].tobytes()))
    np.testing.assert_array_equal(out, RGB)


def test_a_yuv422_uyvy_image_gives_close_colours():
    """A yuv422 (UYVY) camera gives RGB within a few grey levels of the scene's colours."""
    out = image_to_array(image_msg("yuv422", 2, 6, 12, uyvy_bytes(RGB)))
    assert out.shape == (2, 6, 3)
    error = np.abs(out[:, ::2].astype(int) - RGB.astype(int))
    assert error.max() <= 3, f"colours off by up to {error.max()} grey levels"
    np.testing.assert_array_equal(out[:, ::2], out[:, 1::2])


def test_a_padded_row_step_skips_the_padding():
    """Rows padded beyond width x 3 bytes (a driver's aligned rows) are read without the padding bytes."""
    rows = [row.tobytes() + b"\xff\xee\xdd\xcc" for row in RGB]  # 9 B of pixels, 4 B of padding per row
    out = image_to_array(image_msg("rgb8", 2, 3, 13, b"".join(rows)))
    np.testing.assert_array_equal(out, RGB)


@pytest.mark.parametrize("encoding", ["mono8", "rgba8", "bayer_rggb8", "16UC1", ""])
def test_an_unsupported_encoding_is_refused_naming_it_and_the_supported_ones(encoding):
    """A grey, Bayer or depth camera is refused with a message naming its encoding and what would work."""
    msg = image_msg(encoding, 2, 3, 9, bytes(18))
    with pytest.raises(NubotCommonError, match=rf"image encoding '{encoding}' unsupported; use one of rgb8, bgr8, "
                                              r"yuv422"):
        image_to_array(msg)


def test_a_data_buffer_shorter_than_the_image_is_refused_with_the_sizes():
    """A truncated message is refused saying how many bytes were needed and how many came."""
    msg = image_msg("rgb8", 2, 3, 9, RGB.tobytes()[:-1])
    with pytest.raises(NubotCommonError, match=r"image of 3 x 2 px \(rgb8\) needs 18 B, got 17"):
        image_to_array(msg)


@pytest.mark.parametrize(("height", "width", "step"), [(0, 3, 9), (2, 0, 9), (0, 0, 0), (2, 3, 8)])
def test_an_empty_image_or_a_row_step_below_the_width_is_refused(height, width, step):
    """A zero-size image, or a row step too short for its pixels, is refused with its size and step."""
    msg = image_msg("rgb8", height, width, step, bytes(64))
    with pytest.raises(NubotCommonError, match=rf"image of {width} x {height} px with row step {step} B: "
                                              r"not a rgb8 image"):
        image_to_array(msg)


def test_array_to_image_round_trips_through_a_serialised_message():
    """An RGB array sent as a message (serialised and read back as a subscriber would) comes back unchanged."""
    big = np.random.default_rng(3).integers(0, 256, (5, 7, 3), dtype=np.uint8)
    msg = array_to_image(big, Image, genpy.Time(12, 500), "nubot1/camera")
    assert (msg.encoding, msg.height, msg.width, msg.step) == ("rgb8", 5, 7, 21)
    assert (msg.header.stamp, msg.header.frame_id) == (genpy.Time(12, 500), "nubot1/camera")
    buffer = io.BytesIO()
    msg.serialize(buffer)
    received = Image()
    received.deserialize(buffer.getvalue())
    np.testing.assert_array_equal(image_to_array(received), big)


def test_array_to_image_of_a_strided_view_and_of_labels():
    """A non-contiguous view is packed densely (step = width x 3); a 2-D array becomes a mono8 image."""
    big = np.random.default_rng(4).integers(0, 256, (6, 8, 3), dtype=np.uint8)
    view = big[::2, 1::2]
    msg = array_to_image(view, Image, genpy.Time())
    assert (msg.height, msg.width, msg.step, len(msg.data)) == (3, 4, 12, 36)
    np.testing.assert_array_equal(image_to_array(msg), view)
    labels = np.arange(12, dtype=np.uint8).reshape(3, 4)
    mono = array_to_image(labels, Image, genpy.Time())
    assert (mono.encoding, mono.step, mono.data) == ("mono8", 4, labels.tobytes())


@pytest.mark.parametrize("shape", [(4, 4, 4), (4, 4, 1), (16,)])
def test_array_to_image_refuses_shapes_that_are_no_rgb_or_grey_image(shape):
    """An RGBA, one-channel 3-D or flat array is refused naming its shape."""
    with pytest.raises(NubotCommonError, match=r"an image must be H x W x 3 \(RGB\) or H x W \(grey\), got shape"):
        array_to_image(np.zeros(shape, np.uint8), Image, genpy.Time())


@pytest.mark.parametrize("yaw", [0.0, 0.7, -1.2, math.pi / 2, 3.0, -3.0])
def test_imu_yaw_reads_the_heading_of_a_yaw_quaternion(yaw):
    """The inertial heading is the yaw of the Imu's orientation, in (-pi, pi]."""
    msg = Imu()
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = yaw_to_quaternion(yaw)
    assert imu_yaw(msg) == pytest.approx(yaw, abs=1e-9)


def test_imu_yaw_of_a_quaternion_that_is_not_normalised():
    """A driver's slightly or grossly unnormalised quaternion still gives its yaw (only the direction counts)."""
    for scale in (0.999, 0.5, 3.0):
        msg = Imu()
        x, y, z, w = yaw_to_quaternion(1.2)
        msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = (scale * x, scale * y,
                                                                                      scale * z, scale * w)
        assert imu_yaw(msg) == pytest.approx(1.2, abs=1e-6), f"scale {scale}"


@pytest.mark.parametrize("quaternion", [(0.0, 0.0, 0.0, 0.0), (0.0, 0.0, math.nan, 1.0), (0.0, 0.0, 0.0, math.inf),
                                        (1e-4, 0.0, 0.0, 0.0)])
def test_imu_yaw_refuses_an_orientation_that_is_no_rotation(quaternion):
    """A zero (no orientation: Imu's default), NaN or infinite quaternion is refused naming its values."""
    msg = Imu()
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = quaternion
    with pytest.raises(OmniVisionError, match=r"inertial orientation \(.*\) is not a rotation"):
        imu_yaw(msg)


def view_at(pose: Pose2D, stamp: float = 12.5) -> RobotView:
    return RobotView(stamp, RobotReport(2, pose))


def test_localization_error_msg_gives_position_and_wrapped_heading_errors():
    """The message carries estimate, truth, the position error [m] and the heading error wrapped to [0, pi]."""
    msg = localization_error_msg(view_at(Pose2D(1.0, 2.0, 3.1)), True, Pose2D(1.3, 2.4, -3.1), LocalizationError)
    assert isinstance(msg, LocalizationError)
    assert msg.header.stamp == genpy.Time(12, 500_000_000)
    assert (msg.estimate.x, msg.estimate.y, msg.estimate_heading) == (1.0, 2.0, 3.1)
    assert (msg.truth.x, msg.truth.y, msg.true_heading) == (1.3, 2.4, -3.1)
    assert msg.position_error == pytest.approx(0.5)
    assert msg.heading_error == pytest.approx(2 * math.pi - 6.2), "3.1 and -3.1 rad are 0.08 rad apart, not 6.2"
    assert msg.localized is True
    buffer = io.BytesIO()
    msg.serialize(buffer)  # every field has a type the message accepts
    assert LocalizationError().deserialize(buffer.getvalue()).position_error == pytest.approx(0.5)


def test_localization_error_msg_of_a_search_frame():
    """A frame still searching reports localized False, and a negative heading error never appears."""
    msg = localization_error_msg(view_at(Pose2D(0.0, 0.0, -0.5), stamp=0.0), False, Pose2D(3.0, 4.0, 0.5),
                                 LocalizationError)
    assert (msg.position_error, msg.localized) == (pytest.approx(5.0), False)
    assert msg.heading_error == pytest.approx(1.0)
    assert msg.header.stamp == genpy.Time(), "time 0 gives an unstamped header"
