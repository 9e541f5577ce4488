"""Unit tests of nubot_common.clouds (sensor_msgs/PointCloud2 <-> arrays, with the generated message classes)
and of the BallInfo3d <-> Ball3dPercept converters of nubot_common.conversions."""

import math

import genpy
import numpy as np
import pytest
from sensor_msgs.msg import PointCloud2, PointField

from nubot_common import NubotCommonError
from nubot_common.clouds import FLOAT32, FLOAT64, UINT32, cloud_from_msg, cloud_msg
from nubot_common.conversions import ball3d_percept, ball_info3d_msg
from nubot_common.msg import BallInfo3d
from nubot_common.percepts import Ball3dPercept


def organised(h=3, w=4, seed=0):
    rng = np.random.default_rng(seed)
    points = rng.uniform(-5, 5, (h, w, 3)).astype(np.float32)
    points[0, 1] = np.nan
    return points, rng.integers(0, 256, (h, w, 3)).astype(np.uint8)


def test_a_cloud_round_trips_with_its_missing_returns():
    points, rgb = organised()
    msg = cloud_msg(points, rgb, PointCloud2, PointField, genpy.Time(3, 0), "nubot1/kinect_left")
    assert (msg.height, msg.width, msg.point_step, msg.row_step, msg.is_dense) == (3, 4, 16, 64, False)
    cloud = cloud_from_msg(msg)
    assert cloud.shape == (3, 4)
    assert np.array_equal(cloud.points, points.reshape(-1, 3).astype(float), equal_nan=True)
    assert np.array_equal(cloud.rgb, rgb.reshape(-1, 3))


def test_float64_coordinates_a_uint32_colour_padding_and_row_gaps_are_read():
    points, rgb = organised(2, 3)
    rec = np.zeros((2, 4), dtype=[("x", "<f8"), ("y", "<f8"), ("z", "<f8"), ("pad", "<u4"), ("rgba", "<u4")])
    rec["x"][:, :3], rec["y"][:, :3], rec["z"][:, :3] = points[..., 0], points[..., 1], points[..., 2]
    c = rgb.astype(np.uint32)
    rec["rgba"][:, :3] = (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2] | (255 << 24)
    msg = PointCloud2(height=2, width=3, is_bigendian=False, point_step=32, row_step=128, data=rec.tobytes(),
                      fields=[PointField("x", 0, FLOAT64, 1), PointField("y", 8, FLOAT64, 1),
                              PointField("z", 16, FLOAT64, 1), PointField("rgba", 28, UINT32, 1)])
    cloud = cloud_from_msg(msg)
    assert np.array_equal(cloud.points, points.reshape(-1, 3).astype(float), equal_nan=True)
    assert np.array_equal(cloud.rgb, rgb.reshape(-1, 3))


def _msg(**changes):
    points, rgb = organised()
    msg = cloud_msg(points, rgb, PointCloud2, PointField, genpy.Time(0), "")
    for key, value in changes.items():
        setattr(msg, key, value)
    return msg


@pytest.mark.parametrize("changes, match", [
    ({"fields": [PointField("x", 0, FLOAT32, 1), PointField("y", 4, FLOAT32, 1), PointField("z", 8, FLOAT32, 1)]},
     "needs fields x, y, z and rgb"),
    ({"fields": [PointField("x", 0, 2, 1), PointField("y", 4, FLOAT32, 1), PointField("z", 8, FLOAT32, 1),
                 PointField("rgb", 12, FLOAT32, 1)]}, "field x: datatype 2"),
    ({"fields": [PointField("x", 0, FLOAT32, 1), PointField("y", 4, FLOAT32, 1), PointField("z", 8, FLOAT32, 1),
                 PointField("rgb", 14, FLOAT32, 1)]}, "do not fit a point of 16 B"),
    ({"is_bigendian": True}, "big-endian"),
    ({"data": b"\x00" * 100}, "needs 192 B, got 100"),
    ({"row_step": 10}, "row_step 10 B is shorter"),
    ({"height": 3000, "width": 3000}, "over the limit"),
    ({"height": 1000, "width": 2000}, "cloud of 2000000 points is over the limit of 307200"),  # once taken (676 MiB)
])
def test_a_bad_cloud_is_refused_with_its_reason(changes, match):
    with pytest.raises(NubotCommonError, match=match):
        cloud_from_msg(_msg(**changes))


def test_an_empty_cloud_is_read_as_empty():
    cloud = cloud_from_msg(_msg(height=0, width=0, data=b""))
    assert len(cloud) == 0


def test_ball_info3d_round_trips_a_percept():
    percept = Ball3dPercept(12.5, -7.0, 1.0, 1.25, -5.0, 0.5, -2.0, True)
    msg = ball_info3d_msg(percept, 0.0)
    assert msg.pos_known_3d and msg.pos_known_2d and msg.velocity_known
    back = ball3d_percept(msg, 0.0)
    assert back.stamp == pytest.approx(12.5) and back.velocity_known
    assert np.allclose([back.x, back.y, back.z, back.vx, back.vy, back.vz], [-7, 1, 1.25, -5, 0.5, -2], atol=1e-6)


def test_ball_info3d_without_a_ball_or_with_nan_knows_nothing():
    msg = ball_info3d_msg(None, 3.0)
    assert not (msg.pos_known_3d or msg.pos_known_2d or msg.velocity_known) and msg.header.stamp.to_sec() == 3.0
    assert ball3d_percept(msg, 0.0) is None
    msg = BallInfo3d(pos_known_3d=True, velocity_known=True)
    msg.pos.x, msg.velocity.z = 1.0, math.nan
    percept = ball3d_percept(msg, 7.0)
    assert percept.stamp == 7.0 and not percept.velocity_known
    msg.pos.y = math.nan
    assert ball3d_percept(msg, 7.0) is None
