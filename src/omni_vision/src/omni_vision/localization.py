"""Self-localization from white line points, wheel odometry and the inertial heading (chapter 4.1).

Requires, per camera frame (30 Hz): the white line points [m] in the robot's body frame (x forward,
y left) and the inertial heading [rad] in the team frame (0 faces the goal the team attacks); per
odometry message (50 Hz): the body velocity (vx, vy [m/s], w [rad/s]); the field
(``nubot_common.field.FieldGeometry``).
Provides: ``SelfLocator``, the agent (``reset``, ``predict`` per odometry message, ``correct`` per
frame, ``update`` for both), whose answers are ``LocalizationEstimate`` (team-frame pose, its std,
``LocalizationState``, matching error, points used); ``LocalizationParams`` (frozen, validated, SI units;
see each field). The distance map and the matching error's optimiser live in ``field_map``.

The method: a point p_i (body) seen from the pose (x, y, theta) lies at the team-frame point
q_i = R(theta) p_i + (x, y); d_i is the distance map's value there (``field_map``). The matching
error E = sum_i w_i (1 - c^2 / (c^2 + d_i^2)) counts a point on a line as 0 and a point far from
every line (an outlier, a point off the map) as w_i at most, so outliers cannot drag the pose.
w_i = 1 / (1 + (r_i / far_weight_distance)^2) lowers far points, whose error grows with range r_i.
E / sum(w_i), in [0, 1], is the ``matching_error`` every threshold uses, so none depends on the
point count. A sign-based adaptive-step descent (RPROP) minimises E with the analytic gradient.
Global localization scores a grid of candidates with theta from the inertial heading, refines the
best few and accepts a clear winner. Tracking predicts with odometry, matches from the prediction
and fuses per axis in a Kalman filter whose measurement variances come from the matching error's
curvature (Gauss-Newton Hessian); the inertial heading (less a slowly learnt drift) is a heading
measurement and the arbiter between the two point-symmetric poses of the field.
"""

from __future__ import annotations

import math
from collections import deque
from dataclasses import dataclass, fields
from enum import Enum

import numpy as np
import numpy.typing as npt

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, wrap_angle
from omni_vision import OmniVisionError
from omni_vision.field_map import PoseMatcher, distance_map_for

FloatArray = npt.NDArray[np.float64]


@dataclass(frozen=True)
class LocalizationParams:
    # Matching error
    matching_scale: float = 0.25  # c [m]: points within ~c pull quadratically, beyond ~3c barely count
    far_weight_distance: float = 4.0  # a point this far [m] has weight 1/2 (its error grows with range)
    min_point_distance: float = 0.3  # closer points [m] are the robot itself (the vision gives none < 0.47)
    max_point_distance: float = 10.0  # farther points [m] are dropped (beyond the mirror's 9 m)
    max_points: int = 400  # more points are thinned evenly (the vision orders them by scan angle)
    map_resolution: float = 0.01  # distance map cell [m]
    # RPROP
    step_increase: float = 1.2  # step factor while the gradient's sign holds
    step_decrease: float = 0.5  # step factor when it flips (the optimum was overshot)
    min_step_xy: float = 0.001  # [m] a search ends when every step is at its minimum (below the points' noise)
    min_step_theta: float = 0.001  # [rad] (4 mm at 4 m)
    max_step_xy: float = 0.5  # [m]
    max_step_theta: float = 0.2  # [rad]
    track_max_iterations: int = 30
    coarse_to_fine_std: float = 0.1  # prediction std [m] above which tracking first matches at global_scale
    # Global localization
    global_grid_step: float = 0.5  # candidate spacing [m]: within 0.35 m of any pose, inside global_scale
    global_grid_margin: float = 0.5  # candidates reach this far [m] outside the lines
    global_scale: float = 0.5  # c [m] for scoring the grid and the first refinement (a wider basin)
    global_max_points: int = 120  # points used to score the grid and refine (thinned evenly)
    global_min_points: int = 40  # fewer points: no global search this frame
    global_candidates: int = 8  # best distinct grid candidates refined per search
    global_distinct_distance: float = 1.0  # candidates closer [m] are the same hypothesis
    global_initial_step_xy: float = 0.1  # [m]
    global_initial_step_theta: float = 0.05  # [rad] (the heading may be a few degrees off)
    global_max_iterations: int = 40  # per refinement stage
    global_accept_error: float = 0.3  # the winner's matching error must be below this
    global_ambiguity_ratio: float = 1.2  # ... and every distinct runner-up's this many times larger
    # Tracking and loss
    min_points: int = 20  # fewer points: no vision correction this frame (prediction only)
    track_accept_error: float = 0.4  # a match with a larger matching error is not fused (a bad frame)
    lost_after_bad_frames: int = 15  # consecutive bad frames before the pose is lost (0.5 s at 30 Hz)
    lost_position_std: float = 0.5  # [m] a larger position std (long without vision) means lost
    # Kalman filter: measurements
    point_noise_std: float = 0.05  # [m] effective error of one point, correlations included
    min_measurement_std_xy: float = 0.01  # [m] floor of a match's std (systematic mirror errors)
    min_measurement_std_theta: float = 0.005  # [rad]
    max_measurement_std_xy: float = 2.0  # [m] cap: an axis the lines do not fix (one line in view)
    max_measurement_std_theta: float = 0.5  # [rad]
    heading_std: float = 0.035  # [rad] inertial heading as a measurement, drift left after the bias
    heading_bias_gain: float = 0.02  # per frame: how fast the inertial drift is learnt (tracking only)
    heading_disagreement: float = 0.6  # [rad] a larger pose-vs-inertial difference is a bad heading frame
    lost_after_heading_frames: int = 3  # consecutive bad heading frames before the pose is lost
    # Kalman filter: process noise of the odometry prediction (random walks)
    position_noise_floor: float = 0.01  # [m/sqrt(s)] even at rest
    position_noise_per_metre: float = 0.05  # [m/sqrt(m)] wheel slip: std after driving L m is this * sqrt(L)
    heading_noise_floor: float = 0.005  # [rad/sqrt(s)]
    heading_noise_per_radian: float = 0.05  # [rad/sqrt(rad)] turned
    heading_noise_per_metre: float = 0.02  # [rad/sqrt(m)] driven
    max_odometry_gap: float = 0.5  # [s] a velocity is integrated at most this long (a stale message)
    max_frame_latency: float = 0.3  # [s] a frame older than the latest odometry by more is stale (dropped)
    initial_std_xy: float = 0.3  # [m] std of a pose given to ``reset``
    initial_std_theta: float = 0.1  # [rad]

    def __post_init__(self) -> None:
        for f in fields(self):
            value = getattr(self, f.name)
            if f.type == "int":
                if isinstance(value, bool) or not isinstance(value, int) or value < 1:
                    raise ValueError(f"{f.name} must be a positive integer, got {value!r}")
            elif isinstance(value, bool) or not isinstance(value, (int, float)) or not math.isfinite(value):
                raise ValueError(f"{f.name} must be a finite number, got {value!r}")
        non_negative = {"min_point_distance", "global_grid_margin", "heading_bias_gain",
                        "position_noise_floor", "position_noise_per_metre", "heading_noise_floor",
                        "heading_noise_per_radian", "heading_noise_per_metre"}
        for f in fields(self):
            value = getattr(self, f.name)
            if f.type == "float" and not (value >= 0.0 if f.name in non_negative else value > 0.0):
                kind = "non-negative" if f.name in non_negative else "positive"
                raise ValueError(f"{f.name} must be {kind}, got {value}")
        for name in ("global_accept_error", "track_accept_error", "heading_bias_gain"):
            if getattr(self, name) > 1.0:
                raise ValueError(f"{name} must lie in (0, 1] (it is a fraction), got {getattr(self, name)}")
        if self.global_ambiguity_ratio <= 1.0:
            raise ValueError(f"global_ambiguity_ratio must exceed 1, got {self.global_ambiguity_ratio}")
        if self.step_increase <= 1.0:
            raise ValueError(f"step_increase must exceed 1, got {self.step_increase}")
        if self.step_decrease >= 1.0:
            raise ValueError(f"step_decrease must lie in (0, 1), got {self.step_decrease}")
        for low, high in (("min_point_distance", "max_point_distance"), ("min_step_xy", "max_step_xy"),
                          ("min_step_theta", "max_step_theta"), ("min_points", "max_points"),
                          ("min_measurement_std_xy", "max_measurement_std_xy"),
                          ("min_measurement_std_theta", "max_measurement_std_theta")):
            if getattr(self, low) >= getattr(self, high):
                raise ValueError(f"{low} must be below {high}, got {getattr(self, low)} >= {getattr(self, high)}")
        if self.heading_disagreement >= math.pi:
            raise ValueError(f"heading_disagreement must be below pi, got {self.heading_disagreement}")
        if not 0.01 <= self.map_resolution <= 0.1:
            raise ValueError(f"map_resolution must lie in [0.01, 0.1] m, got {self.map_resolution}")


class LocalizationState(Enum):
    GLOBAL_SEARCH = "global_search"  # never localized since start or reset: searching the whole field
    TRACKING = "tracking"  # localized: odometry prediction corrected by matching
    LOST = "lost"  # was localized, lost it: the pose follows odometry while a global search runs


@dataclass(frozen=True)
class LocalizationEstimate:
    t: float  # time of the estimate [s]
    pose: Pose2D  # team frame [m, m, rad]; (0, 0, 0) in GLOBAL_SEARCH; odometry's prediction when LOST
    std: tuple[float, float, float]  # std of x [m], y [m], theta [rad]; inf when nothing is known
    localized: bool  # True only while TRACKING
    state: LocalizationState
    matching_error: float  # E / sum(w) of this frame's match in [0, 1]; nan when no match ran
    points_used: int  # this frame's points after dropping invalid ones and thinning to max_points (0: none)


@dataclass
class _Match:
    pose: FloatArray  # (3,) team frame
    variance: FloatArray  # (3,) per-axis measurement variance
    error: float  # matching error E / sum(w)


def _thin(points: FloatArray, count: int) -> FloatArray:
    """At most ``count`` of the points, evenly spread over their order (the vision's scan order)."""
    if len(points) <= count:
        return points
    return points[np.linspace(0, len(points) - 1, count).astype(np.intp)]


def _inverse_3x3(m: FloatArray) -> FloatArray:
    """Inverse of a 3 x 3 matrix by cofactors (numpy.linalg's call overhead costs ~0.3 ms on a loaded core)."""
    cof = np.array([[m[1, 1] * m[2, 2] - m[1, 2] * m[2, 1], m[0, 2] * m[2, 1] - m[0, 1] * m[2, 2],
                     m[0, 1] * m[1, 2] - m[0, 2] * m[1, 1]],
                    [m[1, 2] * m[2, 0] - m[1, 0] * m[2, 2], m[0, 0] * m[2, 2] - m[0, 2] * m[2, 0],
                     m[0, 2] * m[1, 0] - m[0, 0] * m[1, 2]],
                    [m[1, 0] * m[2, 1] - m[1, 1] * m[2, 0], m[0, 1] * m[2, 0] - m[0, 0] * m[2, 1],
                     m[0, 0] * m[1, 1] - m[0, 1] * m[1, 0]]])
    return cof / (m[0, 0] * cof[0, 0] + m[0, 1] * cof[1, 0] + m[0, 2] * cof[2, 0])


Motion = tuple[float, float, float]  # a pose or a displacement (x [m], y [m], theta [rad])


def _as_motion(pose: FloatArray) -> Motion:
    return float(pose[0]), float(pose[1]), float(pose[2])


def _compose(a: Motion, b: Motion) -> Motion:
    """The pose a followed by the displacement b (given in a's body frame)."""
    cos, sin = math.cos(a[2]), math.sin(a[2])
    return a[0] + cos * b[0] - sin * b[1], a[1] + sin * b[0] + cos * b[1], wrap_angle(a[2] + b[2])


def _between(a: Motion, b: Motion) -> Motion:
    """The displacement from pose a to pose b, in a's body frame (so that _compose(a, it) = b)."""
    cos, sin = math.cos(a[2]), math.sin(a[2])
    dx, dy = b[0] - a[0], b[1] - a[1]
    return cos * dx + sin * dy, -sin * dx + cos * dy, wrap_angle(b[2] - a[2])


def _axis_grid(half_extent: float, step: float) -> FloatArray:
    """Multiples of ``step`` in [-half_extent, half_extent], symmetric about 0."""
    n = int(math.floor(half_extent / step + 1e-9))
    return np.arange(-n, n + 1) * step


class SelfLocator:
    """Estimates the robot's team-frame pose from line points, odometry and the inertial heading.

    Call ``predict`` per odometry message and ``correct`` per camera frame (or ``update`` for both);
    every call returns the current ``LocalizationEstimate``. Deterministic: no randomness.
    """

    def __init__(self, field: FieldGeometry, params: LocalizationParams | None = None) -> None:
        self.field = field
        self.params = params if params is not None else LocalizationParams()
        p = self.params
        self.matcher = PoseMatcher(distance_map_for(field, p.map_resolution),
                                   far_weight_distance=p.far_weight_distance, point_noise_std=p.point_noise_std,
                                   min_step=(p.min_step_xy, p.min_step_theta),
                                   max_step=(p.max_step_xy, p.max_step_theta),
                                   step_increase=p.step_increase, step_decrease=p.step_decrease)
        xs = _axis_grid(field.half_length + p.global_grid_margin, p.global_grid_step)
        ys = _axis_grid(field.half_width + p.global_grid_margin, p.global_grid_step)
        grid_x, grid_y = np.meshgrid(xs, ys)
        self._grid = np.column_stack([grid_x.ravel(), grid_y.ravel()])
        self._global_step = np.array([p.global_initial_step_xy, p.global_initial_step_xy,
                                      p.global_initial_step_theta])
        self._min_var = np.array([p.min_measurement_std_xy, p.min_measurement_std_xy,
                                  p.min_measurement_std_theta]) ** 2
        self._max_var = np.array([p.max_measurement_std_xy, p.max_measurement_std_xy,
                                  p.max_measurement_std_theta]) ** 2
        self.reset()

    # --- public API -------------------------------------------------------------------------------
    def reset(self, pose: Pose2D | None = None, std: tuple[float, float, float] | None = None) -> None:
        """Forget everything; with ``pose`` (team frame) start tracking there with ``std`` (or the defaults)."""
        p = self.params
        self._t: float | None = None
        self._velocity = (0.0, 0.0, 0.0)
        # Dead reckoning from odometry alone, with its recent history: the motion since a frame's time.
        self._odometry: Motion = (0.0, 0.0, 0.0)
        self._history: deque[tuple[float, Motion]] = deque()
        self._bad_frames = 0
        self._bad_heading_frames = 0
        self._heading_bias = 0.0  # inertial heading minus the pose's heading, learnt while tracking
        if pose is None:
            self._state = LocalizationState.GLOBAL_SEARCH
            self._mean = np.zeros(3)
            self._var = np.full(3, np.inf)
        else:
            sx, sy, st = std if std is not None else (p.initial_std_xy, p.initial_std_xy, p.initial_std_theta)
            self._state = LocalizationState.TRACKING
            self._mean = np.array([pose.x, pose.y, wrap_angle(pose.theta)])
            self._var = np.array([sx, sy, st], dtype=np.float64) ** 2
        self._estimate = self._publish(0.0, math.nan, 0)

    @property
    def estimate(self) -> LocalizationEstimate:
        """The latest estimate."""
        return self._estimate

    def predict(self, t: float, vx: float, vy: float, w: float) -> LocalizationEstimate:
        """Integrate the body velocity (vx, vy [m/s], w [rad/s]) measured over the time since the last call up to t [s].

        A non-finite velocity is ignored (the last one is held).
        """
        if all(math.isfinite(v) for v in (vx, vy, w)):
            self._velocity = (float(vx), float(vy), float(w))
        self._advance(t)
        self._estimate = self._publish(self._time(t), math.nan, 0)
        return self._estimate

    def correct(self, t: float, points: npt.ArrayLike, heading: float | None = None,
                heading_reliable: bool = True) -> LocalizationEstimate:
        """Correct with one frame: line points (N, 2) [m] in the body frame, inertial heading [rad] (team frame).

        Non-finite points and points outside [min_point_distance, max_point_distance] are dropped; an
        empty frame is allowed. ``heading_reliable`` False: the heading is neither fused nor trusted to
        tell the two symmetric poses apart. Raises ``OmniVisionError`` for points not shaped (N, 2).
        """
        p = self.params
        self._advance(t)
        body = self._usable_points(points)
        weights = self.matcher.weights(body)
        motion = self._motion_since(t)
        error = math.nan
        if motion is None:  # stale: the odometry has moved on by more than max_frame_latency
            self._estimate = self._publish(self._time(t), error, len(body))
            return self._estimate
        # The heading at the frame's time, carried to now by the odometry's turn since.
        now_heading = wrap_angle(heading + motion[2]) if heading is not None and math.isfinite(heading) else None
        if self._state is not LocalizationState.TRACKING:
            if heading is not None and math.isfinite(heading) and len(body) >= p.global_min_points:
                match, error = self._global_search(body, weights, heading, heading_reliable)
                if match is not None:
                    self._mean = np.array(_compose(_as_motion(match.pose), motion))
                    self._var = match.variance.copy()
                    self._state = LocalizationState.TRACKING
                    self._bad_frames = self._bad_heading_frames = 0
        else:
            fused = False
            if len(body) >= p.min_points:
                match = self._track(body, weights, motion)
                error = match.error
                if error <= p.track_accept_error:
                    for axis in range(3):
                        self._fuse(axis, float(match.pose[axis]), float(match.variance[axis]))
                    self._bad_frames = 0
                    fused = True
                else:
                    self._bad_frames += 1
            if now_heading is not None and heading_reliable:
                self._use_heading(now_heading, fused)
            if self._bad_frames >= p.lost_after_bad_frames or self._bad_heading_frames >= p.lost_after_heading_frames:
                self._state = LocalizationState.LOST
            self._check_position_std()
        self._estimate = self._publish(self._time(t), error, len(body))
        return self._estimate

    def update(self, t: float, points: npt.ArrayLike | None, odometry: tuple[float, float, float] | None = None,
               heading: float | None = None, heading_reliable: bool = True) -> LocalizationEstimate:
        """``predict`` with ``odometry`` (vx, vy, w) if given, then ``correct`` with the frame if there is one."""
        if odometry is not None:
            self.predict(t, *odometry)
        if points is None:
            self._advance(t)
            self._estimate = self._publish(self._time(t), math.nan, 0)
            return self._estimate
        return self.correct(t, points, heading, heading_reliable)

    # --- prediction -------------------------------------------------------------------------------
    def _time(self, t: float) -> float:
        return self._t if self._t is not None else float(t)

    def _advance(self, t: float) -> None:
        """Move the pose to time t with the held velocity; a time not after the last one changes nothing."""
        if not math.isfinite(t):
            return
        if self._t is None:
            self._t = float(t)
            self._history.append((self._t, self._odometry))
            return
        dt = float(t) - self._t
        if dt <= 0.0:
            return
        self._t = float(t)
        p = self.params
        vx, vy, w = self._velocity
        span = min(dt, p.max_odometry_gap)
        half_turn = 0.5 * w * span  # constant-twist motion, to second order: along the mean heading
        step = ((math.cos(half_turn) * vx - math.sin(half_turn) * vy) * span,
                (math.sin(half_turn) * vx + math.cos(half_turn) * vy) * span, w * span)
        self._odometry = _compose(self._odometry, step)
        self._history.append((self._t, self._odometry))
        while len(self._history) > 2 and self._history[1][0] <= self._t - p.max_frame_latency:
            self._history.popleft()
        if self._state is LocalizationState.GLOBAL_SEARCH:
            return
        self._mean = np.array(_compose(_as_motion(self._mean), step))
        driven = math.hypot(vx, vy) * span
        self._var[:2] += p.position_noise_floor**2 * dt + p.position_noise_per_metre**2 * driven
        self._var[2] += (p.heading_noise_floor**2 * dt + p.heading_noise_per_radian**2 * abs(w) * span
                         + p.heading_noise_per_metre**2 * driven)
        self._check_position_std()

    def _motion_since(self, t: float) -> Motion | None:
        """The odometry's displacement from time t to now (identity for t now or later); None when t is stale."""
        if self._t is None or not t < self._t:
            return 0.0, 0.0, 0.0
        if self._t - t > self.params.max_frame_latency:
            return None
        history = self._history
        then = history[0][1]  # older than the history (just started): no odometry known before
        for (t0, pose0), (t1, pose1) in zip(history, list(history)[1:]):
            if t0 <= t <= t1:
                fraction = (t - t0) / (t1 - t0) if t1 > t0 else 1.0
                step = _between(pose0, pose1)
                then = _compose(pose0, (fraction * step[0], fraction * step[1], fraction * step[2]))
                break
        return _between(then, self._odometry)

    def _check_position_std(self) -> None:
        if (self._state is LocalizationState.TRACKING
                and max(self._var[0], self._var[1]) > self.params.lost_position_std**2):
            self._state = LocalizationState.LOST

    # --- correction -------------------------------------------------------------------------------
    def _usable_points(self, points: npt.ArrayLike) -> FloatArray:
        p = self.params
        body = np.asarray(points, dtype=np.float64)
        if body.size == 0:
            return np.empty((0, 2))
        if body.ndim != 2 or body.shape[1] != 2:
            raise OmniVisionError(f"points must be an (N, 2) array of body-frame x, y [m], got shape {body.shape}")
        r2 = np.einsum("ij,ij->i", body, body)
        with np.errstate(invalid="ignore"):
            keep = (r2 >= p.min_point_distance**2) & (r2 <= p.max_point_distance**2)  # NaN compares False
        return _thin(body[keep], p.max_points)

    def _measurement_variance(self, information: FloatArray) -> FloatArray:
        """Per-axis variance of a match: the marginals of its covariance (the inverse information).

        The cap acts as a prior, so an axis the lines leave open (one line in view) gets a large
        variance instead of a singular matrix.
        """
        covariance = _inverse_3x3(information + np.diag(1.0 / self._max_var))
        return np.minimum(np.maximum(np.diag(covariance), self._min_var), self._max_var)

    def _track(self, body: FloatArray, weights: FloatArray, motion: Motion) -> _Match:
        """Match from the pose predicted for the frame's time, carry it to now by ``motion``.

        A wide prediction first matches at ``global_scale``.
        """
        p = self.params
        start = np.array([_compose(_as_motion(self._mean), _between(motion, (0.0, 0.0, 0.0)))])
        std = np.sqrt(self._var)
        if max(std[0], std[1]) > p.coarse_to_fine_std:
            start, _ = self.matcher.optimise(start, body, weights, p.global_scale, std, p.track_max_iterations)
        poses, energy = self.matcher.optimise(start, body, weights, p.matching_scale, std, p.track_max_iterations)
        information = self.matcher.information(poses[0], body, weights, p.matching_scale)
        pose = np.array(_compose(_as_motion(poses[0]), motion))
        return _Match(pose, self._measurement_variance(information), float(energy[0] / weights.sum()))

    def _fuse(self, axis: int, measured: float, variance: float) -> None:
        """One axis's Kalman update (theta's innovation wrapped)."""
        innovation = measured - float(self._mean[axis])
        if axis == 2:
            innovation = wrap_angle(innovation)
        gain = self._var[axis] / (self._var[axis] + variance)
        self._mean[axis] += gain * innovation
        self._var[axis] *= 1.0 - gain
        if axis == 2:
            self._mean[2] = wrap_angle(float(self._mean[2]))

    def _use_heading(self, heading: float, vision_fused: bool) -> None:
        """Check the pose's heading against the inertial one, learn the inertial drift, fuse the heading."""
        p = self.params
        innovation = wrap_angle(heading - self._heading_bias - float(self._mean[2]))
        if abs(innovation) > p.heading_disagreement:
            self._bad_heading_frames += 1  # a half-time turn of the team frame, or a wrong symmetric pose
            return
        self._bad_heading_frames = 0
        if vision_fused:  # the drift is only observable while the lines fix the heading
            self._heading_bias = wrap_angle(self._heading_bias + p.heading_bias_gain * innovation)
        self._fuse(2, wrap_angle(heading - self._heading_bias), p.heading_std**2)

    # --- global localization ----------------------------------------------------------------------
    def _global_search(self, body: FloatArray, weights: FloatArray, heading: float,
                       heading_reliable: bool) -> tuple[_Match | None, float]:
        """Search the whole field; return the accepted match (or None) and the best matching error.

        Candidates: the grid's positions with theta = the inertial heading less its learnt drift (and,
        with an unreliable heading, also theta + pi). The grid is scored at ``global_scale``; the
        ``global_candidates`` best distinct ones are refined (RPROP at ``global_scale``, then at
        ``matching_scale``) and scored with every point. Accepted when the best matching error is
        below ``global_accept_error`` and every distinct runner-up's is ``global_ambiguity_ratio`` times larger
        (the outliers' and the noise's share of the error scales both);
        the best's point-mirror twin (possible only with an unreliable heading) does not count as a
        runner-up: the pose nearest the last known pose wins (else the one nearest the heading).
        """
        p = self.params
        sub = _thin(body, p.global_max_points)
        sub_weights = self.matcher.weights(sub)
        theta = wrap_angle(heading - self._heading_bias)
        thetas = [theta] if heading_reliable else [theta, wrap_angle(theta + math.pi)]
        candidates = np.concatenate([np.column_stack([self._grid, np.full(len(self._grid), th)]) for th in thetas])
        scores = self.matcher.energy_nearest(candidates, sub, sub_weights, p.global_scale)
        chosen: list[list[float]] = []
        for index in np.argsort(scores, kind="stable"):
            pose = candidates[index].tolist()
            if all(self._distinct(pose, other) for other in chosen):
                chosen.append(pose)
                if len(chosen) == p.global_candidates:
                    break
        poses, _ = self.matcher.optimise(np.array(chosen), sub, sub_weights, p.global_scale, self._global_step,
                                         p.global_max_iterations)
        poses, _ = self.matcher.optimise(poses, sub, sub_weights, p.matching_scale,
                                         self._global_step * p.step_decrease, p.global_max_iterations)
        energy, _ = self.matcher.cost(poses, body, weights, p.matching_scale)
        errors = energy / weights.sum()
        best = int(np.argmin(errors))
        if errors[best] > p.global_accept_error:
            return None, float(errors[best])
        rivals = [i for i in range(len(poses)) if errors[i] < p.global_ambiguity_ratio * errors[best]
                  and self._distinct(poses[i].tolist(), poses[best].tolist())]
        twins = [i for i in rivals if self._mirrored(poses[i].tolist(), poses[best].tolist())]
        if len(twins) < len(rivals):
            return None, float(errors[best])  # two different places fit about equally: wait for a clearer frame
        if twins:
            best = min([best, *twins], key=lambda i: self._twin_preference(poses[i], theta))
        pose = poses[best].copy()
        pose[2] = wrap_angle(float(pose[2]))
        information = self.matcher.information(pose, body, weights, p.matching_scale)
        return _Match(pose, self._measurement_variance(information), float(errors[best])), float(errors[best])

    def _distinct(self, a: list[float], b: list[float]) -> bool:
        """Two poses are different hypotheses when apart by the distinct distance or by the heading threshold."""
        return (math.hypot(a[0] - b[0], a[1] - b[1]) >= self.params.global_distinct_distance
                or abs(wrap_angle(a[2] - b[2])) >= self.params.heading_disagreement)

    def _mirrored(self, a: list[float], b: list[float]) -> bool:
        """True when a is b's point-mirror image (-x, -y, theta + pi), which the lines cannot tell apart."""
        return not self._distinct(a, [-b[0], -b[1], wrap_angle(b[2] + math.pi)])

    def _twin_preference(self, pose: FloatArray, heading: float) -> float:
        """Sort key among mirror twins: the distance to the last known pose, else the heading difference."""
        if self._state is LocalizationState.LOST:
            return math.hypot(float(pose[0] - self._mean[0]), float(pose[1] - self._mean[1]))
        return abs(wrap_angle(float(pose[2]) - heading))

    def _publish(self, t: float, error: float, points_used: int) -> LocalizationEstimate:
        std = np.sqrt(self._var)
        return LocalizationEstimate(
            t=t, pose=Pose2D(float(self._mean[0]), float(self._mean[1]), float(self._mean[2])),
            std=(float(std[0]), float(std[1]), float(std[2])),
            localized=self._state is LocalizationState.TRACKING, state=self._state,
            matching_error=error, points_used=points_used)
