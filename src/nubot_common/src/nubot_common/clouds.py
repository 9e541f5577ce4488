"""sensor_msgs/PointCloud2 <-> numpy for the RGB-D cameras (no rospy: the message classes are passed in).

Provides ``Cloud`` (a cloud's points N x 3 [m] in the camera frame, NaN where a return is missing, their colours
N x 3 uint8 RGB, and the organised shape height x width), ``cloud_from_msg`` (any little-endian PointCloud2 with
float32 or float64 ``x``, ``y``, ``z`` and a packed ``rgb``/``rgba`` field, float32 or uint32 0x00RRGGBB as PCL
writes it; a clear ``NubotCommonError`` for anything else) and ``cloud_msg`` (the organised x, y, z, rgb float32
cloud the simulator publishes, 16 B a point).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Any

import numpy as np

from nubot_common import NubotCommonError
from nubot_common.arrays import FloatArray

FLOAT32, FLOAT64, UINT32 = 7, 8, 6  # sensor_msgs/PointField datatypes
_XYZ_TYPES = {FLOAT32: "<f4", FLOAT64: "<f8"}
_COLOR_FIELDS = ("rgb", "rgba")
MAX_POINTS = 640 * 480  # a cloud with more points is refused, before any is read (a Kinect gives 307 k at most, a
# Kinect 2 217 k, the simulated goalie's cameras 13.6 k): a peer cannot make the node hold hundreds of MiB


@dataclass(frozen=True)
class Cloud:
    points: FloatArray  # N x 3 float [m], camera frame; NaN: no return
    rgb: FloatArray  # N x 3 uint8
    shape: tuple[int, int]  # (height, width); height 1 for an unorganised cloud

    def __post_init__(self) -> None:
        if self.points.ndim != 2 or self.points.shape[1] != 3 or self.rgb.shape != self.points.shape:
            raise NubotCommonError(f"a cloud needs N x 3 points and colours, got {self.points.shape} and "
                                  f"{self.rgb.shape}")

    @classmethod
    def from_arrays(cls, points: FloatArray, rgb: FloatArray) -> Cloud:
        """A cloud from organised (H x W x 3) or flat (N x 3) arrays."""
        p, c = np.asarray(points), np.asarray(rgb)
        shape = (p.shape[0], p.shape[1]) if p.ndim == 3 else (1, p.shape[0])
        return cls(p.reshape(-1, 3), c.reshape(-1, 3).astype(np.uint8, copy=False), shape)

    def __len__(self) -> int:
        return len(self.points)


def cloud_from_msg(msg: Any) -> Cloud:
    """The points and colours of a sensor_msgs/PointCloud2; raise ``NubotCommonError`` saying what is wrong."""
    if msg.is_bigendian:
        raise NubotCommonError("big-endian point clouds are unsupported")
    fields = {f.name: f for f in msg.fields}
    missing = [name for name in ("x", "y", "z") if name not in fields]
    color = next((fields[n] for n in _COLOR_FIELDS if n in fields), None)
    if missing or color is None:
        raise NubotCommonError(f"a cloud needs fields x, y, z and rgb (or rgba); it has "
                              f"{', '.join(fields) or 'none'}")
    height, width, step, row_step = int(msg.height), int(msg.width), int(msg.point_step), int(msg.row_step)
    n = height * width
    if n > MAX_POINTS:
        raise NubotCommonError(f"a cloud of {n} points is over the limit of {MAX_POINTS}")
    layout: dict[str, Any] = {"names": [], "formats": [], "offsets": [], "itemsize": step}
    for name in ("x", "y", "z"):
        f = fields[name]
        if f.datatype not in _XYZ_TYPES or f.count != 1:
            raise NubotCommonError(f"field {name}: datatype {f.datatype} x {f.count} unsupported; "
                                  "use float32 (7) or float64 (8), count 1")
        layout["names"].append(name)
        layout["formats"].append(_XYZ_TYPES[f.datatype])
        layout["offsets"].append(int(f.offset))
    if color.datatype not in (FLOAT32, UINT32) or color.count != 1:
        raise NubotCommonError(f"field {color.name}: datatype {color.datatype} x {color.count} unsupported; "
                              "use a packed float32 (7) or uint32 (6)")
    layout["names"].append("rgb")
    layout["formats"].append("<u4")
    layout["offsets"].append(int(color.offset))
    sizes = [np.dtype(fmt).itemsize for fmt in layout["formats"]]
    if any(off < 0 or off + size > step for off, size in zip(layout["offsets"], sizes)):
        raise NubotCommonError(f"fields at offsets {layout['offsets']} do not fit a point of {step} B")
    if n == 0:
        return Cloud(np.zeros((0, 3)), np.zeros((0, 3), np.uint8), (height, width))
    if row_step < width * step:
        raise NubotCommonError(f"row_step {row_step} B is shorter than {width} points of {step} B")
    data = np.frombuffer(msg.data, dtype=np.uint8)
    if data.size < height * row_step:
        raise NubotCommonError(f"a cloud of {width} x {height} points needs {height * row_step} B, got {data.size}")
    rows = data[:height * row_step].reshape(height, row_step)[:, :width * step]
    record = np.dtype({"names": layout["names"], "formats": layout["formats"], "offsets": layout["offsets"],
                       "itemsize": step})
    records = np.ascontiguousarray(rows).view(record).reshape(-1)
    points = np.stack([records["x"], records["y"], records["z"]], axis=1).astype(float)
    packed = records["rgb"]
    rgb = np.stack([(packed >> 16) & 0xFF, (packed >> 8) & 0xFF, packed & 0xFF], axis=1).astype(np.uint8)
    return Cloud(points, rgb, (height, width))


def cloud_msg(points: FloatArray, rgb: FloatArray, msg_type: Any, field_type: Any, stamp: Any,
              frame_id: str) -> Any:
    """An organised ``msg_type`` (sensor_msgs/PointCloud2) of H x W x 3 points [m] (NaN: no return) and their
    H x W x 3 uint8 colours: fields x, y, z float32 and rgb packed in a float32 (PCL's layout)."""
    points, rgb = np.asarray(points), np.asarray(rgb, dtype=np.uint8)
    if points.ndim != 3 or points.shape[2] != 3 or rgb.shape != points.shape:
        raise NubotCommonError(f"a cloud needs H x W x 3 points and colours, got {points.shape} and {rgb.shape}")
    h, w = points.shape[:2]
    record = np.empty((h, w), dtype=np.dtype({"names": ["x", "y", "z", "rgb"], "formats": ["<f4"] * 3 + ["<u4"],
                                              "offsets": [0, 4, 8, 12], "itemsize": 16}))
    record["x"], record["y"], record["z"] = points[..., 0], points[..., 1], points[..., 2]
    c = rgb.astype(np.uint32)
    record["rgb"] = (c[..., 0] << 16) | (c[..., 1] << 8) | c[..., 2]
    msg = msg_type()
    msg.header.stamp = stamp
    msg.header.frame_id = frame_id
    msg.height, msg.width = h, w
    msg.fields = [field_type(name=name, offset=4 * k, datatype=FLOAT32, count=1)
                  for k, name in enumerate(("x", "y", "z", "rgb"))]
    msg.is_bigendian = False
    msg.point_step = 16
    msg.row_step = 16 * w
    msg.is_dense = bool(np.isfinite(points).all())
    msg.data = record.tobytes()
    return msg
