"""The front camera's model: a pinhole camera with radial/tangential distortion, mounted on the robot.

Requires: the camera's intrinsics (focal lengths and principal point [px]), OpenCV's distortion coefficients
(k1, k2, p1, p2, k3) and its mount in the robot's body frame (x forward, y left, z up; optical centre [m],
yaw, pitch and roll [deg]; pitch positive looks down). Provides ``PinholeCamera`` (frozen, validated; read
from and written to YAML with ``load_camera`` / ``camera_yaml``) with the maps between image and robot:

- ``pixel_rays(uv)`` / ``pixel_grid_rays()``: body-frame unit rays of pixels (distortion removed);
- ``project(points)``: body-frame points -> pixels (distortion applied), and which lie ahead of the lens;
- ``plane_points(uv, z)``: where the pixels' rays meet the horizontal plane at height z [m] (a ball's
  centre: z = its radius), NaN where they do not (at or above the horizon);
- ``camera_matrix``, ``dist_coeffs``, ``rotation`` (body <- camera), ``from_rotation`` (a mount from a matrix).

Frames: OpenCV's camera frame (x right, y down, z along the optical axis); pixel (u, v) = column, row, pixel
centres at integers. The mount's rotation is Rz(yaw) Ry(pitch) Rx(roll) applied to a camera looking straight
ahead (optical axis = body x). OpenCV is imported on first use: reading a configuration does not load it.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from functools import cached_property
from pathlib import Path

import numpy as np
import numpy.typing as npt
import yaml

from nubot_common import NubotCommonError
from nubot_common.arrays import FloatArray
from nubot_common.params import from_mapping, to_mapping

# A camera looking straight ahead: columns are the camera's x (right), y (down), z (optical axis) in the body.
_AHEAD = np.array([[0.0, 0.0, 1.0], [-1.0, 0.0, 0.0], [0.0, -1.0, 0.0]])
_UNDISTORT = (3, 40, 1e-10)  # OpenCV's TERM_CRITERIA_COUNT | TERM_CRITERIA_EPS, iterations, epsilon
_MIN_DEPTH = 1e-6  # [m] camera-frame depth below which a point is not ahead of the lens


def _rz(a: float) -> FloatArray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]])


def _ry(a: float) -> FloatArray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[c, 0.0, s], [0.0, 1.0, 0.0], [-s, 0.0, c]])


def _rx(a: float) -> FloatArray:
    c, s = math.cos(a), math.sin(a)
    return np.array([[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]])


@dataclass(frozen=True)
class PinholeCamera:
    width: int = 320  # [px]
    height: int = 240  # [px]
    fx: float = 230.0  # [px] focal length along u (about 70 deg of horizontal field of view)
    fy: float = 230.0  # [px]
    cx: float = 159.5  # [px] principal point (the image centre)
    cy: float = 119.5  # [px]
    distortion: tuple[float, float, float, float, float] = (-0.06, 0.02, 0.0, 0.0, 0.0)  # OpenCV k1 k2 p1 p2 k3
    position: tuple[float, float, float] = (0.20, 0.0, 0.55)  # [m] optical centre, body frame
    yaw_deg: float = 0.0  # [deg] left of the robot's front
    pitch_deg: float = 33.0  # [deg] down from the horizontal
    roll_deg: float = 0.0  # [deg] about the optical axis

    def __post_init__(self) -> None:
        for name in ("width", "height"):
            value = getattr(self, name)
            if not (isinstance(value, int) and 16 <= value <= 4096):
                raise NubotCommonError(f"{name} must be an integer in [16, 4096] px, got {value!r}")
        for name in ("fx", "fy"):
            if not (math.isfinite(getattr(self, name)) and getattr(self, name) > 0.0):
                raise NubotCommonError(f"{name} must be a positive focal length [px], got {getattr(self, name)}")
        if not (0.0 <= self.cx <= self.width and 0.0 <= self.cy <= self.height):
            raise NubotCommonError(f"the principal point ({self.cx}, {self.cy}) must lie in the image")
        if len(self.distortion) != 5 or not all(math.isfinite(k) and abs(k) < 10.0 for k in self.distortion):
            raise NubotCommonError(f"distortion must be five finite coefficients (k1 k2 p1 p2 k3), |k| < 10, got "
                                   f"{self.distortion}")
        if len(self.position) != 3 or not all(math.isfinite(p) and abs(p) <= 5.0 for p in self.position):
            raise NubotCommonError(f"position must be three finite values within 5 m, got {self.position}")
        if not self.position[2] > 0.0:
            raise NubotCommonError(f"the camera must be above the ground (position z > 0), got {self.position[2]}")
        for name, bound in (("yaw_deg", 180.0), ("pitch_deg", 89.0), ("roll_deg", 180.0)):
            value = getattr(self, name)
            if not (math.isfinite(value) and -bound <= value <= bound):
                raise NubotCommonError(f"{name} must lie in [-{bound:g}, {bound:g}] deg, got {value}")

    # --- the model's matrices ------------------------------------------------------------------
    @cached_property
    def camera_matrix(self) -> FloatArray:
        """The 3 x 3 intrinsic matrix K."""
        return np.array([[self.fx, 0.0, self.cx], [0.0, self.fy, self.cy], [0.0, 0.0, 1.0]])

    @cached_property
    def dist_coeffs(self) -> FloatArray:
        """OpenCV's distortion vector (k1, k2, p1, p2, k3)."""
        return np.array(self.distortion, np.float64)

    @cached_property
    def rotation(self) -> FloatArray:
        """The 3 x 3 rotation body <- camera (its columns: the camera's axes in the body frame)."""
        yaw, pitch, roll = (math.radians(a) for a in (self.yaw_deg, self.pitch_deg, self.roll_deg))
        rotation: FloatArray = _rz(yaw) @ _ry(pitch) @ _rx(roll) @ _AHEAD
        return rotation

    @cached_property
    def origin(self) -> FloatArray:
        """The optical centre in the body frame [m]."""
        return np.array(self.position, np.float64)

    @cached_property
    def extrinsics(self) -> tuple[FloatArray, FloatArray]:
        """(rvec, tvec): body -> camera, as OpenCV's projectPoints takes them."""
        import cv2

        r_cb = self.rotation.T
        rvec, _ = cv2.Rodrigues(r_cb)
        return rvec, -r_cb @ self.origin

    @property
    def angle_per_pixel(self) -> float:
        """[rad] the angle one pixel spans near the image centre."""
        return 2.0 / (self.fx + self.fy)

    @classmethod
    def from_rotation(cls, rotation: FloatArray, position: FloatArray, **intrinsics: object) -> PinholeCamera:
        """A camera mounted at ``position`` [m] with the rotation body <- camera ``rotation``; the rest from
        ``intrinsics`` (width, height, fx, fy, cx, cy, distortion)."""
        m = np.asarray(rotation, np.float64) @ _AHEAD.T  # Rz(yaw) Ry(pitch) Rx(roll)
        pitch = math.asin(max(-1.0, min(1.0, -m[2, 0])))
        yaw = math.atan2(m[1, 0], m[0, 0])
        roll = math.atan2(m[2, 1], m[2, 2])
        return cls(position=tuple(float(p) for p in position),  # type: ignore[arg-type]
                   yaw_deg=math.degrees(yaw), pitch_deg=math.degrees(pitch), roll_deg=math.degrees(roll),
                   **intrinsics)  # type: ignore[arg-type]

    def intrinsics(self) -> dict[str, object]:
        """The intrinsic fields (for ``from_rotation``)."""
        return {"width": self.width, "height": self.height, "fx": self.fx, "fy": self.fy, "cx": self.cx,
                "cy": self.cy, "distortion": self.distortion}

    # --- pixels, rays and the ground -----------------------------------------------------------
    def normalized(self, uv: FloatArray) -> FloatArray:
        """Pixels (N x 2) as undistorted normalized image points (N x 2): x/z, y/z of the camera frame."""
        import cv2

        uv = np.asarray(uv, np.float64).reshape(-1, 1, 2)
        if uv.size == 0:
            return np.zeros((0, 2))
        points: FloatArray = cv2.undistortPointsIter(uv, self.camera_matrix, self.dist_coeffs, None, None,
                                                     _UNDISTORT).reshape(-1, 2)
        return points

    def pixel_rays(self, uv: FloatArray) -> FloatArray:
        """Body-frame unit rays (N x 3) through the pixels ``uv`` (N x 2)."""
        xy = self.normalized(uv)
        rays = np.column_stack([xy, np.ones(len(xy))]) @ self.rotation.T
        unit: FloatArray = rays / np.linalg.norm(rays, axis=1, keepdims=True)
        return unit

    def pixel_grid_rays(self) -> FloatArray:
        """The body-frame unit ray of every pixel (height x width x 3, float64), row v, column u."""
        v, u = np.mgrid[0:self.height, 0:self.width].astype(np.float64)
        return self.pixel_rays(np.column_stack([u.ravel(), v.ravel()])).reshape(self.height, self.width, 3)

    def project(self, points: FloatArray) -> tuple[FloatArray, npt.NDArray[np.bool_]]:
        """Body-frame points (N x 3) [m] -> (pixels N x 2, ahead N bool: in front of the lens; pixels of the
        others are meaningless)."""
        points = np.asarray(points, np.float64).reshape(-1, 3)
        if len(points) == 0:
            return np.zeros((0, 2)), np.zeros(0, bool)
        import cv2

        depth = (points - self.origin) @ self.rotation[:, 2]
        rvec, tvec = self.extrinsics
        uv, _ = cv2.projectPoints(points, rvec, tvec, self.camera_matrix, self.dist_coeffs)
        pixels: FloatArray = uv.reshape(-1, 2)
        return pixels, depth > _MIN_DEPTH

    def ray_plane_points(self, rays: FloatArray, z: float) -> FloatArray:
        """Where body-frame rays (N x 3) from the optical centre meet the plane at height ``z`` [m]: body (x, y)
        N x 2 [m]; NaN for rays that do not reach it ahead."""
        rays = np.asarray(rays, np.float64).reshape(-1, 3)
        dz = rays[:, 2]
        with np.errstate(divide="ignore", invalid="ignore"):
            t = (z - self.origin[2]) / dz
        t = np.where(np.isfinite(t) & (t > 0.0), t, np.nan)
        points: FloatArray = self.origin[None, :2] + t[:, None] * rays[:, :2]
        return points

    def plane_points(self, uv: FloatArray, z: float = 0.0) -> FloatArray:
        """Where the rays of pixels ``uv`` (N x 2) meet the plane at height ``z`` [m] (body (x, y), N x 2 [m];
        NaN where they do not)."""
        return self.ray_plane_points(self.pixel_rays(uv), z)


def load_camera(path: str | Path) -> PinholeCamera:
    """Read a camera file (``camera_yaml``'s format); raise ``NubotCommonError`` naming the file and the problem."""
    where = f"camera file {path}"
    try:
        with open(path, encoding="utf-8") as handle:
            data = yaml.safe_load(handle)
    except OSError as exc:
        raise NubotCommonError(f"{where}: cannot read it ({exc.strerror or exc})") from exc
    except yaml.YAMLError as exc:
        raise NubotCommonError(f"{where}: not YAML: {exc}") from exc
    if not isinstance(data, dict):
        raise NubotCommonError(f"{where}: expected a mapping of the camera's parameters")
    data = data.get("camera", data)
    return from_mapping(PinholeCamera, data, where)


def camera_yaml(camera: PinholeCamera, comment: str = "") -> str:
    """The camera as YAML (``load_camera`` reads it back), headed by ``comment`` (each line a YAML comment)."""
    lines = [f"# {line}".rstrip() for line in comment.splitlines()]
    body = yaml.safe_dump({"camera": to_mapping(camera)}, sort_keys=False, default_flow_style=None)
    return "\n".join(lines + [body.rstrip()]) + "\n"
