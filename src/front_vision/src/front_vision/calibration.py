"""Offline calibration of the front camera from chessboard images (OpenCV), pure: images in, camera out.

Requires: RGB images (uint8) of a ``Chessboard``: views of the board held anywhere in front of the camera
(for the intrinsics) and views of a board lying flat on the ground at a known place in the robot's body
frame (``GroundPlacement``: its centre [m] and the direction of its x axis [deg]; for the extrinsics).
Provides:

- ``Chessboard``: the pattern (inner corners, square size [m], white margin [squares]), its corners in its
  own frame and its picture (``texture``) for printing or rendering;
- ``find_corners(image, board)``: the inner corners (sub-pixel, in the board's order: the 180-degree
  ambiguity of a detection is settled by the colour of the square beyond the first corner, which is black);
- ``calibrate_intrinsics``: K and the distortion (``cv2.calibrateCamera``) and the RMS reprojection error;
- ``solve_mount``: the camera's pose in the body frame (``cv2.solvePnP`` over every ground corner at its known
  body-frame position) and its RMS reprojection error;
- ``calibrate``: both, as a ``PinholeCamera`` with a ``CalibrationReport``.

The board frame (OpenCV's): origin at the picture's top-left corner, x along its columns, y along its rows,
z = x cross y pointing into the board (its face is seen from -z; a board lying face up has z down).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import cv2
import numpy as np

from front_vision import FrontVisionError
from nubot_common.camera_model import PinholeCamera

_SUBPIX = (cv2.TERM_CRITERIA_EPS | cv2.TERM_CRITERIA_MAX_ITER, 50, 1e-4)


@dataclass(frozen=True)
class Chessboard:
    columns: int = 9  # inner corners along the board's x
    rows: int = 6  # inner corners along its y (columns + rows odd: the pattern is not symmetric under 180 deg)
    square: float = 0.03  # [m]
    margin: float = 1.0  # [squares] the white border around the squares

    def __post_init__(self) -> None:
        counts = (self.columns, self.rows)
        if not (all(isinstance(n, int) for n in counts) and 3 <= self.rows <= self.columns <= 40):
            raise FrontVisionError(f"the board needs 3 <= rows <= columns <= 40 inner corners, got "
                                   f"{self.columns} x {self.rows}")
        if (self.columns + self.rows) % 2 == 0:
            raise FrontVisionError(f"columns + rows must be odd (an asymmetric board), got "
                                   f"{self.columns} + {self.rows}")
        if not (math.isfinite(self.square) and 0.005 <= self.square <= 1.0):
            raise FrontVisionError(f"square must be in [0.005, 1] m, got {self.square}")
        if not (math.isfinite(self.margin) and 0.5 <= self.margin <= 5.0):
            raise FrontVisionError(f"margin must be in [0.5, 5] squares, got {self.margin}")

    @property
    def pattern_size(self) -> tuple[int, int]:
        return self.columns, self.rows

    @property
    def size(self) -> tuple[float, float]:
        """The whole board (x, y) [m], margin included."""
        return ((self.columns + 1 + 2 * self.margin) * self.square, (self.rows + 1 + 2 * self.margin) * self.square)

    def object_points(self) -> np.ndarray:
        """The inner corners in the board frame (columns x rows, 3) [m], row by row (OpenCV's order)."""
        j, i = np.mgrid[0:self.rows, 0:self.columns].astype(np.float64)
        first = (self.margin + 1.0) * self.square
        return np.column_stack([first + i.ravel() * self.square, first + j.ravel() * self.square,
                                np.zeros(i.size)])

    def texture(self, pixels_per_square: int = 16) -> np.ndarray:
        """The board's picture (RGB uint8): black squares where (column + row) of the square is even, white margin."""
        n = pixels_per_square
        m = int(round(self.margin * n))
        squares = (np.add.outer(np.arange(self.rows + 1), np.arange(self.columns + 1)) % 2 == 1)
        grid = np.kron(squares, np.ones((n, n), bool))
        picture = np.full((grid.shape[0] + 2 * m, grid.shape[1] + 2 * m), 255, np.uint8)
        picture[m:m + grid.shape[0], m:m + grid.shape[1]] = np.where(grid, 255, 0)
        return np.repeat(picture[..., None], 3, axis=2)


@dataclass(frozen=True)
class GroundPlacement:
    """Where a board lies flat on the ground (face up), in the robot's body frame: yaw -90 deg puts its columns
    to the robot's right and its rows towards the robot, as a camera looking ahead sees it upright."""

    x: float  # [m] the board's centre
    y: float  # [m]
    yaw_deg: float  # [deg] the direction of its x axis (its columns)

    def rotation(self) -> np.ndarray:
        """body <- board: x along ``yaw_deg``, y to its right (the picture seen from above), z into the ground."""
        c, s = math.cos(math.radians(self.yaw_deg)), math.sin(math.radians(self.yaw_deg))
        return np.array([[c, s, 0.0], [s, -c, 0.0], [0.0, 0.0, -1.0]])

    def origin(self, board: Chessboard) -> np.ndarray:
        """The board frame's origin in the body frame [m]."""
        sx, sy = board.size
        return np.array([self.x, self.y, 0.0]) - self.rotation() @ np.array([sx / 2.0, sy / 2.0, 0.0])

    def corners(self, board: Chessboard) -> np.ndarray:
        """The board's inner corners in the body frame (N x 3) [m]."""
        return board.object_points() @ self.rotation().T + self.origin(board)


@dataclass(frozen=True)
class CalibrationReport:
    views: int  # images whose corners were found, for the intrinsics
    intrinsics_rms: float  # [px] calibrateCamera's RMS reprojection error
    ground_views: int
    mount_rms: float  # [px] the ground corners' RMS reprojection error through the calibrated camera


def _grey(image: np.ndarray) -> np.ndarray:
    image = np.asarray(image)
    if image.dtype != np.uint8 or image.ndim not in (2, 3) or image.size == 0:
        raise FrontVisionError(f"a calibration image must be uint8 grey or RGB, got {image.dtype} {image.shape}")
    return image if image.ndim == 2 else cv2.cvtColor(np.ascontiguousarray(image), cv2.COLOR_RGB2GRAY)


def find_corners(image: np.ndarray, board: Chessboard) -> np.ndarray | None:
    """The board's inner corners in ``image`` (N x 2 [px], the order of ``board.object_points``), or None."""
    grey = _grey(image)
    flags = cv2.CALIB_CB_ADAPTIVE_THRESH | cv2.CALIB_CB_NORMALIZE_IMAGE
    found, corners = cv2.findChessboardCorners(grey, board.pattern_size, flags=flags)
    if not found:
        return None
    corners = cv2.cornerSubPix(grey, corners, (3, 3), (-1, -1), _SUBPIX).reshape(-1, 2)
    # The square diagonally beyond corner 0 is black in the board's own order; if it is white, the detection
    # started at the opposite corner.
    beyond = corners[0] + 0.5 * (corners[0] - corners[board.columns + 1])
    u, v = int(round(beyond[0])), int(round(beyond[1]))
    if 0 <= v < grey.shape[0] and 0 <= u < grey.shape[1]:
        level = float(grey[v, u])
        middle = float(np.median(grey[np.clip(corners[:, 1].astype(int), 0, grey.shape[0] - 1),
                                      np.clip(corners[:, 0].astype(int), 0, grey.shape[1] - 1)]))
        if level > middle:
            corners = corners[::-1].copy()
    return corners


def calibrate_intrinsics(corner_sets: Sequence[np.ndarray], board: Chessboard, image_size: tuple[int, int],
                         fix_k3: bool = True, zero_tangential: bool = True) -> tuple[np.ndarray, np.ndarray, float]:
    """(K, distortion (k1 k2 p1 p2 k3), RMS [px]) from the corners of at least three views; ``image_size`` is
    (width, height)."""
    if len(corner_sets) < 3:
        raise FrontVisionError(f"the intrinsics need the board found in at least 3 views, got {len(corner_sets)}")
    objects = [board.object_points().astype(np.float32)] * len(corner_sets)
    images = [np.asarray(c, np.float32).reshape(-1, 1, 2) for c in corner_sets]
    flags = (cv2.CALIB_FIX_K3 if fix_k3 else 0) | (cv2.CALIB_ZERO_TANGENT_DIST if zero_tangential else 0)
    rms, k, dist, _, _ = cv2.calibrateCamera(objects, images, image_size, None, None, flags=flags)
    return k, dist.ravel()[:5], float(rms)


def solve_mount(corner_sets: Sequence[np.ndarray], placements: Sequence[GroundPlacement], board: Chessboard,
                camera_matrix: np.ndarray, dist: np.ndarray) -> tuple[np.ndarray, np.ndarray, float]:
    """(rotation body <- camera, optical centre [m] in the body frame, RMS [px]) from the corners of boards lying
    at known ``placements`` (one per corner set)."""
    if not corner_sets or len(corner_sets) != len(placements):
        raise FrontVisionError(f"the mount needs one placement per ground view, got {len(corner_sets)} views and "
                               f"{len(placements)} placements")
    body = np.concatenate([p.corners(board) for p in placements])
    pixels = np.concatenate([np.asarray(c, np.float64).reshape(-1, 2) for c in corner_sets])
    ok, rvec, tvec = cv2.solvePnP(body, pixels, camera_matrix, dist, flags=cv2.SOLVEPNP_ITERATIVE)
    if not ok:
        raise FrontVisionError("solvePnP found no camera pose for the ground views")
    rvec, tvec = cv2.solvePnPRefineLM(body, pixels, camera_matrix, dist, rvec, tvec)
    r_cb, _ = cv2.Rodrigues(rvec)
    projected, _ = cv2.projectPoints(body, rvec, tvec, camera_matrix, dist)
    rms = float(np.sqrt(np.mean(np.sum((projected.reshape(-1, 2) - pixels) ** 2, axis=1))))
    rotation = r_cb.T
    return rotation, -rotation @ tvec.ravel(), rms


def calibrate(views: Sequence[np.ndarray], board: Chessboard, ground_views: Sequence[np.ndarray],
              placements: Sequence[GroundPlacement], ground_board: Chessboard) -> tuple[PinholeCamera,
                                                                                          CalibrationReport]:
    """The camera from images: intrinsics from ``views`` of ``board``, the mount from ``ground_views`` of
    ``ground_board`` lying at ``placements``. Views without the board found are skipped; every ground view must
    show it."""
    if not views:
        raise FrontVisionError("no views of the board for the intrinsics")
    height, width = np.asarray(views[0]).shape[:2]
    for n, image in enumerate(list(views) + list(ground_views)):
        if np.asarray(image).shape[:2] != (height, width):
            raise FrontVisionError(f"image {n} is {np.asarray(image).shape[1]} x {np.asarray(image).shape[0]} px, "
                                   f"the first {width} x {height}: one camera, one size")
    found = [c for c in (find_corners(v, board) for v in views) if c is not None]
    k, dist, rms = calibrate_intrinsics(found, board, (width, height))
    ground = []
    for n, image in enumerate(ground_views):
        corners = find_corners(image, ground_board)
        if corners is None:
            raise FrontVisionError(f"ground view {n}: the board lying at {placements[n]} was not found")
        ground.append(corners)
    rotation, origin, mount_rms = solve_mount(ground, placements, ground_board, k, dist)
    camera = PinholeCamera.from_rotation(rotation, origin, width=int(width), height=int(height), fx=float(k[0, 0]),
                                         fy=float(k[1, 1]), cx=float(k[0, 2]), cy=float(k[1, 2]),
                                         distortion=tuple(float(d) for d in dist))
    return camera, CalibrationReport(len(found), rms, len(ground), mount_rms)
