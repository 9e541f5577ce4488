"""The distance map of the field's white lines, the lookup behind self-localization (chapter 4.1).

Requires: a ``nubot_common.field.FieldGeometry`` (its ``line_segments``, ``arcs``, ``spots`` and
``border``).
Provides: ``FieldDistanceMap``: on a grid of ``resolution`` [m] covering the field and its border,
the distance [m] from each node to the nearest line centre (lines, arcs and spot centres
rasterised one cell wide, then an exact Euclidean distance transform) and its gradient maps
d/dx, d/dy [m/m]. ``lookup`` interpolates all three bilinearly at arrays of team-frame points;
``lookup_distance`` is the cheap nearest-node variant for scoring many candidate poses at once.
``distance_map_for`` caches one map per (field, resolution): a 22 x 14 m field at 1 cm takes about
60 MB and 0.1-0.3 s to build, so every locator of the same field shares it.
Points off the map count as far: distance ``OFF_MAP_DISTANCE`` [m], gradient zero.
``PoseMatcher``: the matching error of body-frame points seen from candidate poses, its analytic
gradient, an RPROP minimiser (batched over poses) and the match's information matrix.
Distances are to the centre of a line (a white point from the vision is the centre of a white run),
so the map is 0 along each line's middle and line_width / 2 at its edges.
"""

from __future__ import annotations

import functools
import math

import cv2
import numpy as np
import numpy.typing as npt

from nubot_common.field import FieldGeometry

FloatArray = npt.NDArray[np.float64]

OFF_MAP_DISTANCE = 10.0  # [m] a point off the map: far beyond any matching scale, so its cost saturates
_REMAP_MAX_COLUMNS = 4096  # OpenCV's remap takes fewer than 32767 columns
_SAMPLES_PER_CELL = 4  # samples per cell along each marking when rasterising: no gaps in the drawn line


class FieldDistanceMap:
    """Distance [m] from any team-frame point to the nearest line centre, with its gradient."""

    def __init__(self, field: FieldGeometry, resolution: float = 0.01) -> None:
        if not (math.isfinite(resolution) and 0.001 <= resolution <= 0.2):
            raise ValueError(f"resolution must lie in [0.001, 0.2] m, got {resolution}")
        self.field = field
        self.resolution = resolution
        self.x_min = -(field.half_length + field.border)
        self.y_min = -(field.half_width + field.border)
        self.nx = int(round(2.0 * (field.half_length + field.border) / resolution)) + 1
        self.ny = int(round(2.0 * (field.half_width + field.border) / resolution)) + 1
        lines = np.full((self.ny, self.nx), 255, dtype=np.uint8)
        px, py = self._marking_samples()
        cols = np.clip(np.rint((px - self.x_min) / resolution).astype(np.intp), 0, self.nx - 1)
        rows = np.clip(np.rint((py - self.y_min) / resolution).astype(np.intp), 0, self.ny - 1)
        lines[rows, cols] = 0
        # DIST_MASK_PRECISE is the exact Euclidean transform (Felzenszwalb), in cells.
        distance = cv2.distanceTransform(lines, cv2.DIST_L2, cv2.DIST_MASK_PRECISE).astype(np.float32)
        distance *= np.float32(resolution)
        grad_y, grad_x = np.gradient(distance, np.float32(resolution))
        # One (ny, nx, 3) array: one remap call interpolates the distance and both gradients.
        self._maps = np.ascontiguousarray(np.stack([distance, grad_x, grad_y], axis=-1), dtype=np.float32)
        self._flat_distance = np.ascontiguousarray(distance).reshape(-1)

    @property
    def distance(self) -> npt.NDArray[np.float32]:
        """The distance map [m], rows along y from ``y_min``, columns along x from ``x_min`` (a view)."""
        return self._maps[..., 0]

    @property
    def x_max(self) -> float:
        return self.x_min + (self.nx - 1) * self.resolution

    @property
    def y_max(self) -> float:
        return self.y_min + (self.ny - 1) * self.resolution

    def _marking_samples(self) -> tuple[FloatArray, FloatArray]:
        """Points along every marking's centre, ``_SAMPLES_PER_CELL`` per cell."""
        spacing = self.resolution / _SAMPLES_PER_CELL
        xs: list[FloatArray] = []
        ys: list[FloatArray] = []
        for (x0, y0), (x1, y1) in self.field.line_segments():
            t = np.linspace(0.0, 1.0, int(math.hypot(x1 - x0, y1 - y0) / spacing) + 2)
            xs.append(x0 + t * (x1 - x0))
            ys.append(y0 + t * (y1 - y0))
        for arc in self.field.arcs():
            a = np.linspace(arc.start, arc.end, int(arc.radius * (arc.end - arc.start) / spacing) + 2)
            xs.append(arc.x + arc.radius * np.cos(a))
            ys.append(arc.y + arc.radius * np.sin(a))
        for sx, sy in self.field.spots():
            xs.append(np.array([sx]))
            ys.append(np.array([sy]))
        return np.concatenate(xs), np.concatenate(ys)

    def lookup(self, xs: npt.ArrayLike, ys: npt.ArrayLike) -> tuple[FloatArray, FloatArray, FloatArray]:
        """Return (d [m], dd/dx, dd/dy) at the team-frame points (xs, ys) [m], bilinearly interpolated.

        OpenCV's remap interpolates at 1/32 of a cell (0.3 mm at 1 cm), five times faster than numpy's
        gather for a frame's few hundred points. Non-finite points are off the map.
        """
        x = np.asarray(xs, dtype=np.float64)
        y = np.asarray(ys, dtype=np.float64)
        if x.shape != y.shape:
            x, y = np.broadcast_arrays(x, y)
        shape = x.shape
        count = x.size
        if count == 0:
            return np.zeros(shape), np.zeros(shape), np.zeros(shape)
        cols = ((x - self.x_min) * (1.0 / self.resolution)).astype(np.float32).reshape(-1)
        rows = ((y - self.y_min) * (1.0 / self.resolution)).astype(np.float32).reshape(-1)
        width = min(count, _REMAP_MAX_COLUMNS)
        padded = -(-count // width) * width
        if padded != count:  # remap takes at most SHRT_MAX columns: fold long inputs into rows
            cols = np.concatenate([cols, np.full(padded - count, -1.0e4, dtype=np.float32)])
            rows = np.concatenate([rows, np.full(padded - count, -1.0e4, dtype=np.float32)])
        values = cv2.remap(self._maps, cols.reshape(-1, width), rows.reshape(-1, width), cv2.INTER_LINEAR,
                           borderMode=cv2.BORDER_CONSTANT, borderValue=(OFF_MAP_DISTANCE, 0.0, 0.0))
        values = values.reshape(-1, 3)[:count].astype(np.float64)
        return values[:, 0].reshape(shape), values[:, 1].reshape(shape), values[:, 2].reshape(shape)

    def lookup_distance(self, xs: npt.ArrayLike, ys: npt.ArrayLike) -> FloatArray:
        """Return d [m] at the nearest map node to each point (xs, ys) [m]; off the map ``OFF_MAP_DISTANCE``."""
        x = np.asarray(xs, dtype=np.float64)
        y = np.asarray(ys, dtype=np.float64)
        col = np.rint((x - self.x_min) * (1.0 / self.resolution))
        row = np.rint((y - self.y_min) * (1.0 / self.resolution))
        on_map = (col >= 0.0) & (col <= self.nx - 1) & (row >= 0.0) & (row <= self.ny - 1)
        index = np.where(on_map, np.nan_to_num(row) * self.nx + np.nan_to_num(col), 0.0).astype(np.intp)
        return np.where(on_map, self._flat_distance[index], OFF_MAP_DISTANCE)


@functools.lru_cache(maxsize=4)
def distance_map_for(field: FieldGeometry, resolution: float = 0.01) -> FieldDistanceMap:
    """The shared distance map of ``field`` at ``resolution`` [m] (built once per process, then cached)."""
    return FieldDistanceMap(field, resolution)


class PoseMatcher:
    """The matching error of body-frame points against the distance map, its gradient and its minimiser.

    E(x, y, theta) = sum_i w_i rho(d_i), rho(d) = d^2 / (c^2 + d^2) = 1 - c^2 / (c^2 + d^2), with
    d_i the map's value at the point i seen from the pose and c the ``scale`` [m] of each call.
    Parameters (keyword, SI): ``far_weight_distance`` [m] (a point this far weighs 1/2),
    ``point_noise_std`` [m] (for ``information``), RPROP's ``min_step`` and ``max_step``
    ((xy [m], theta [rad]) each), ``step_increase`` (> 1) and ``step_decrease`` (in (0, 1)).
    """

    def __init__(self, distance_map: FieldDistanceMap, *, far_weight_distance: float, point_noise_std: float,
                 min_step: tuple[float, float], max_step: tuple[float, float], step_increase: float,
                 step_decrease: float) -> None:
        self.map = distance_map
        self.far_weight_distance = far_weight_distance
        self.point_noise_std = point_noise_std
        self.min_step = (min_step[0], min_step[0], min_step[1])
        self.max_step = (max_step[0], max_step[0], max_step[1])
        self.step_increase = step_increase
        self.step_decrease = step_decrease
        self._min_step = np.array(self.min_step)
        self._max_step = np.array(self.max_step)
        self._step_factor = np.array([step_decrease, 1.0, step_increase])  # by the gradient's sign agreement

    def weights(self, points: FloatArray) -> FloatArray:
        """Weight of each body-frame point (N, 2) [m]: 1 at the robot, 1/2 at ``far_weight_distance``."""
        r2 = np.einsum("ij,ij->i", points, points)
        return 1.0 / (1.0 + r2 * (1.0 / self.far_weight_distance**2))

    @staticmethod
    def _offsets(poses: FloatArray, points: FloatArray) -> tuple[FloatArray, FloatArray]:
        """The points rotated by each of the K poses' heading (K, N): team-frame offsets from the robot."""
        cos = np.cos(poses[:, 2:3])
        sin = np.sin(poses[:, 2:3])
        bx, by = points[:, 0], points[:, 1]
        return cos * bx - sin * by, sin * bx + cos * by

    def cost(self, poses: FloatArray, points: FloatArray, weights: FloatArray,
             scale: float) -> tuple[FloatArray, FloatArray]:
        """Return E (K,) and dE/d(x, y, theta) (K, 3) at the K poses (K, 3) [m, m, rad]."""
        rx, ry = self._offsets(poses, points)
        d, gx, gy = self.map.lookup(rx + poses[:, 0:1], ry + poses[:, 1:2])
        c2 = scale * scale
        d2 = d * d
        inverse = 1.0 / (c2 + d2)
        energy = (d2 * inverse) @ weights
        # d rho / d d = 2 c^2 d / (c^2 + d^2)^2; the rotation's chain rule: dq/dtheta = (-ry, rx).
        slope = d * inverse * inverse * ((2.0 * c2) * weights)
        ax = slope * gx
        ay = slope * gy
        grad = np.empty((poses.shape[0], 3))
        grad[:, 0] = ax.sum(axis=1)
        grad[:, 1] = ay.sum(axis=1)
        grad[:, 2] = (ay * rx - ax * ry).sum(axis=1)
        return energy, grad

    def _cost_single(self, pose: list[float], points: FloatArray, weights: FloatArray,
                     c2: float) -> tuple[float, list[float]]:
        """``cost`` for one pose in plain floats: tracking's inner loop, twice as fast as the batch form."""
        cos, sin = math.cos(pose[2]), math.sin(pose[2])
        bx, by = points[:, 0], points[:, 1]
        rx = cos * bx - sin * by
        ry = sin * bx + cos * by
        d, gx, gy = self.map.lookup(rx + pose[0], ry + pose[1])
        d2 = d * d
        inverse = 1.0 / (c2 + d2)
        slope = d * inverse * inverse * ((2.0 * c2) * weights)
        ax = slope * gx
        ay = slope * gy
        return float((d2 * inverse) @ weights), [float(ax.sum()), float(ay.sum()), float(ay @ rx - ax @ ry)]

    def energy_nearest(self, poses: FloatArray, points: FloatArray, weights: FloatArray, scale: float) -> FloatArray:
        """E (K,) at many poses at once, with the nearest-node lookup (for scoring a candidate grid)."""
        rx, ry = self._offsets(poses, points)
        d2 = self.map.lookup_distance(rx + poses[:, 0:1], ry + poses[:, 1:2]) ** 2
        return (d2 / (scale * scale + d2)) @ weights

    def optimise(self, poses: FloatArray, points: FloatArray, weights: FloatArray, scale: float,
                 initial_step: npt.ArrayLike, max_iterations: int) -> tuple[FloatArray, FloatArray]:
        """Minimise E from each of the K poses (K, 3) by RPROP; return the best poses (K, 3) and their E (K,).

        Only the gradient's sign moves a coordinate, by its own step (``initial_step`` (3,), clipped):
        grown while the sign holds, shrunk (and the move skipped, iRPROP-) when it flips. So the map's
        kinks and the mixed units of x, y and theta need no learning rate. A search ends when every
        step is at its minimum, or after ``max_iterations`` evaluations.
        """
        poses = np.array(poses, dtype=np.float64).reshape(-1, 3)
        start = np.minimum(np.maximum(np.asarray(initial_step, dtype=np.float64), self._min_step), self._max_step)
        if poses.shape[0] == 1:
            pose, single_energy = self._optimise_single(poses[0].tolist(), points, weights, scale, start.tolist(),
                                                        max_iterations)
            return np.array([pose]), np.array([single_energy])
        step = np.broadcast_to(start, poses.shape).copy()
        previous = np.zeros_like(poses)
        best_poses = poses.copy()
        best_energy = np.full(poses.shape[0], np.inf)
        for _ in range(max_iterations):
            energy, grad = self.cost(poses, points, weights, scale)
            better = energy < best_energy
            best_energy = np.where(better, energy, best_energy)
            best_poses[better] = poses[better]
            sign = np.sign(grad)
            agreement = sign * previous
            step *= self._step_factor[agreement.astype(np.intp) + 1]  # agreement is -1, 0 or 1
            step = np.minimum(np.maximum(step, self._min_step), self._max_step)  # np.clip is slower here
            if np.all(step <= self._min_step):
                break
            sign[agreement < 0.0] = 0.0
            poses -= sign * step
            previous = sign
        return best_poses, best_energy

    def _optimise_single(self, pose: list[float], points: FloatArray, weights: FloatArray, scale: float,
                         step: list[float], max_iterations: int) -> tuple[list[float], float]:
        """``optimise`` for one pose, the same steps in plain floats."""
        c2 = scale * scale
        previous = [0, 0, 0]
        best_pose, best_energy = list(pose), math.inf
        for _ in range(max_iterations):
            energy, grad = self._cost_single(pose, points, weights, c2)
            if energy < best_energy:
                best_pose, best_energy = list(pose), energy
            sign = [(g > 0.0) - (g < 0.0) for g in grad]
            for k in range(3):
                agreement = sign[k] * previous[k]
                if agreement > 0:
                    step[k] = min(step[k] * self.step_increase, self.max_step[k])
                elif agreement < 0:
                    step[k] = max(step[k] * self.step_decrease, self.min_step[k])
                    sign[k] = 0
            if all(s <= low for s, low in zip(step, self.min_step)):
                break
            pose = [v - g * s for v, g, s in zip(pose, sign, step)]
            previous = sign
        return best_pose, best_energy

    def information(self, pose: npt.ArrayLike, points: FloatArray, weights: FloatArray, scale: float) -> FloatArray:
        """The 3 x 3 information matrix of a match at ``pose`` (3,): its Gauss-Newton Hessian over the point noise.

        Near its minimum E ~ sum w d^2 / c^2, so E's Hessian, sum w 2 c^2 / (c^2 + d^2)^2 J J^T with
        J = dd/d(x, y, theta), times c^2 / (2 sigma^2) is the log-likelihood's curvature for points
        of error ``point_noise_std`` (sigma); the robust factor drops the outliers.
        """
        x, y, theta = np.asarray(pose, dtype=np.float64).tolist()
        cos, sin = math.cos(theta), math.sin(theta)
        rx = cos * points[:, 0] - sin * points[:, 1]
        ry = sin * points[:, 0] + cos * points[:, 1]
        d, gx, gy = self.map.lookup(rx + x, ry + y)
        c2 = scale * scale
        robust = weights * (c2 / (c2 + d * d)) ** 2
        jac = np.stack([gx, gy, gy * rx - gx * ry], axis=1)
        return (jac.T * robust) @ jac / self.point_noise_std**2
