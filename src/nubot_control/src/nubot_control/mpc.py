"""Trajectory tracking by model predictive control with Laguerre-parameterised control increments.

Requires: the measured position, the velocity commanded last cycle and a sampled reference
(positions and velocities), all in the world frame; numpy and DAQP (a dual active-set QP solver).
Provides: ``laguerre_basis`` (discrete Laguerre functions, Wang 2009 ch. 3), ``MpcParams`` and
``LaguerreMpc.command`` -> world-frame velocity (ux, uy) for this cycle.
Units SI: m, s, m/s, m/s^2. No ROS: the node rotates the command into the body frame and
controls the heading separately.

Model (omnidirectional robot, control period dt): p_{k+1} = p_k + dt * u_k, so the tracking
error e = p - r obeys e_{k+1} = e_k + dt * (u_k - r'_k), with r'_k the reference's mean velocity
over the step, (r_{k+1} - r_k) / dt. The prediction is written with the sampled reference
positions, e_{k+i} = p_k + dt * (u_k + ... + u_{k+i-1}) - r_{k+i}, which is this model exactly
(with the sampled r'_k instead, a curved path would be predicted to drift outwards by
dt^2 v^2 / 2R per step). ``ref_velocities`` is checked but not needed by the prediction.

Decision variables: the control increments du_{k+i} = u_{k+i} - u_{k+i-1}, per axis
du_{k+i} = L(i)^T eta with N Laguerre functions L(i), so the QP has 2N variables however long
the horizon. Cost: position_weight * sum_{i=1..H} |e_{k+i}|^2 + effort_weight * |eta|^2
(|eta|^2 = sum of |du|^2 over an infinite horizon). On the first ``constrained_steps``
predicted steps |u| <= max_speed and |du| <= max_accel * dt, each disc replaced by its
inscribed regular polygon (linear in eta, never looser than the disc). The Hessian and
constraint matrix are constant and built once; each cycle only q and the speed bounds change.
When the unconstrained optimum satisfies every constraint it is the QP's solution and the
solver is not called; else DAQP solves the small dense QP exactly (about 20 us here, an
ADMM solver to 1e-3 took 250 us and its first move was up to 0.1 m/s off).

Safety: the command always satisfies |u - u_{k-1}| <= max_accel * dt, and |u| <= max_speed
unless |u_{k-1}| > max_speed + max_accel * dt (the limit was lowered by more than one step can
shed); the solver's first move is projected onto both discs to remove tolerance-sized
violations. Fallback, when the QP is infeasible or the solver fails: move u_{k-1} by at most
max_accel * dt straight towards the velocity within max_speed nearest the unconstrained
optimum's first move, i.e. brake as hard as allowed when the limit was lowered (e.g. on
starting to dribble); if one step can reach the speed disc, the velocity within both limits
nearest that target is used instead. Such calls are counted in ``fallbacks``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import daqp
import numpy as np
from numpy.typing import ArrayLike

from nubot_common.params import require_non_negative, require_positive

# DAQP's exit flags: 1 optimal, 2 optimal with soft constraints violated (none here); the rest fall back.
_DAQP_STATUS = {1: "solved", 2: "solved", -1: "infeasible", -2: "cycling", -3: "unbounded",
                -4: "iteration limit", -5: "not convex", -6: "initial working set overdetermined"}
_UNBOUNDED = 1e30  # DAQP's infinity: a bound beyond it is no bound


def laguerre_basis(pole: float, terms: int, steps: int) -> np.ndarray:
    """Discrete Laguerre functions: row i is L(i)^T, shape (steps, terms).

    L(0) = sqrt(1 - a^2) [1, -a, a^2, ..., (-a)^(N-1)] and L(i+1) = A_l L(i) (Wang 2009, ch. 3),
    A_l having a on the diagonal and (1 - a^2) (-a)^(r-c-1) below it. The columns are orthonormal
    over an infinite horizon; with pole 0 they are unit pulses at steps 0 .. N-1.
    """
    if not 0.0 <= pole < 1.0:
        raise ValueError(f"pole must lie in [0, 1), got {pole}")
    if terms < 1 or steps < 1:
        raise ValueError(f"terms and steps must be >= 1, got {terms} and {steps}")
    beta = 1.0 - pole * pole
    a_l = np.zeros((terms, terms))
    for r in range(terms):
        a_l[r, r] = pole
        for c in range(r):
            a_l[r, c] = beta * (-pole) ** (r - c - 1)
    basis = np.empty((steps, terms))
    basis[0] = math.sqrt(beta) * (-pole) ** np.arange(terms)
    for i in range(1, steps):
        basis[i] = a_l @ basis[i - 1]
    return basis


@dataclass(frozen=True)
class MpcParams:
    dt: float = 0.03  # control period [s]
    horizon: int = 20  # prediction steps
    laguerre_terms: int = 5  # N per axis
    laguerre_pole: float = 0.7  # a, 0 <= a < 1: slow enough to hold an acceleration over the horizon
    position_weight: float = 1.0  # on the predicted position errors [1/m^2]
    effort_weight: float = 0.1  # on |eta|^2 ~ sum of |du|^2 [s^2/m^2]
    max_speed: float = 3.25  # [m/s]
    max_accel: float = 3.0  # [m/s^2]
    polygon_sides: int = 16
    constrained_steps: int = 8  # steps of the horizon on which the limits are imposed (>=1, <= horizon)

    def __post_init__(self) -> None:
        require_positive(self, "dt", "position_weight", "max_speed", "max_accel")
        require_non_negative(self, "effort_weight", "laguerre_pole")
        for name in ("horizon", "laguerre_terms", "polygon_sides", "constrained_steps"):
            value = getattr(self, name)
            if isinstance(value, bool) or not isinstance(value, int):
                raise ValueError(f"{name} must be an integer, got {value!r}")
        if not self.laguerre_pole < 1.0:
            raise ValueError(f"laguerre_pole must be below 1, got {self.laguerre_pole}")
        if not 1 <= self.laguerre_terms <= self.horizon:
            raise ValueError(f"laguerre_terms must lie in 1..horizon, got {self.laguerre_terms}")
        if self.polygon_sides < 3:
            raise ValueError(f"polygon_sides must be >= 3, got {self.polygon_sides}")
        if not 1 <= self.constrained_steps <= self.horizon:
            raise ValueError(f"constrained_steps must lie in 1..horizon, got {self.constrained_steps}")


def _array(value: ArrayLike, shape: tuple[int, ...], name: str) -> np.ndarray:
    """``value`` as a finite float array of ``shape``, else ValueError (a float array is used as it is: only read)."""
    if isinstance(value, np.ndarray) and value.dtype == np.float64:
        array = value
    else:
        try:
            array = np.array(value, dtype=float)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"{name} must be numbers of shape {shape}: {exc}") from exc
    if array.shape != shape:
        raise ValueError(f"{name} must have shape {shape}, got {array.shape}")
    # A finite sum means every element is finite (it is the cheaper test); an infinite one may only have overflowed.
    if not math.isfinite(array.sum()) and not np.isfinite(array).all():
        raise ValueError(f"{name} must be finite, got {array.tolist()}")
    return array


def _clip_norm(v: np.ndarray, radius: float) -> np.ndarray:
    """``v`` shortened to length ``radius`` if it is longer."""
    norm = math.hypot(v[0], v[1])
    return v if norm <= radius else v * (radius / norm)


def _project_two_discs(x: np.ndarray, speed: float, centre: np.ndarray, step: float) -> np.ndarray | None:
    """Nearest point to ``x`` in {|v| <= speed} and {|v - centre| <= step}; None if they do not meet."""
    p = _clip_norm(x, speed)
    if math.hypot(p[0] - centre[0], p[1] - centre[1]) <= step:
        return p
    p = centre + _clip_norm(x - centre, step)
    if math.hypot(p[0], p[1]) <= speed:
        return p
    # Neither single projection lies in both discs: the answer is a point where the two circles cross.
    d = math.hypot(centre[0], centre[1])
    if d == 0.0 or d > speed + step or d < abs(speed - step):
        return None
    along = (speed * speed - step * step + d * d) / (2.0 * d)
    across = math.sqrt(max(speed * speed - along * along, 0.0))
    unit = centre / d
    normal = np.array([-unit[1], unit[0]])
    corners = (along * unit + across * normal, along * unit - across * normal)
    return min(corners, key=lambda c: math.hypot(c[0] - x[0], c[1] - x[1]))


class LaguerreMpc:
    """Laguerre-parameterised MPC for a planar integrator: one QP with 2N variables per control cycle."""

    def __init__(self, params: MpcParams) -> None:
        self.params = p = params
        h, n, nc, m = p.horizon, p.laguerre_terms, p.constrained_steps, p.polygon_sides
        basis = laguerre_basis(p.laguerre_pole, n, h)  # du_{k+i} = basis[i] @ eta_axis
        self._first = basis[0].copy()
        cumulative = np.cumsum(basis, axis=0)  # u_{k+i} - u_{k-1} = cumulative[i] @ eta_axis
        # Per axis, e_{k+1..k+H} = free response + phi @ eta_axis with phi[i-1] = dt * sum_{j<i} cumulative[j].
        phi = p.dt * np.cumsum(cumulative, axis=0)
        self._carry = p.dt * np.arange(1, h + 1)[:, None]  # how far u_{k-1} held constant carries the robot by step i
        hessian = p.position_weight * phi.T @ phi + p.effort_weight * np.eye(n)  # same for both axes
        # Per axis, q_axis = position_weight * phi.T @ free_axis and the unconstrained optimum is -H^-1 q_axis. Both
        # axes are one product each, with the axes as rows: (2, H) @ (H, N), then (2, N) @ (N, N).
        self._gradient_t = np.ascontiguousarray(p.position_weight * phi)
        self._hessian_inv_t = np.ascontiguousarray(np.linalg.inv(hessian).T)

        # Inscribed polygon, a vertex at angle 0 (on both axes if 4 divides M): side normals n_j, sides at
        # cos(pi/M) of the radius.
        # With M even, opposite sides share a normal and make one two-sided row.
        self._two_sided = m % 2 == 0
        count = m // 2 if self._two_sided else m
        angles = (np.arange(count) + 0.5) * (2.0 * math.pi / m)
        self._normals = np.column_stack((np.cos(angles), np.sin(angles)))
        self._apothem = math.cos(math.pi / m)

        def rows(vectors: np.ndarray) -> np.ndarray:
            # Row (i, j): n_j . (vectors[i] @ eta_x, vectors[i] @ eta_y), for the constrained steps i.
            return np.vstack([np.concatenate((nx * vectors[i], ny * vectors[i]))
                              for i in range(nc) for nx, ny in self._normals])

        self._a_speed, self._a_accel = rows(cumulative), rows(basis)
        self._per_step = np.tile(np.arange(count), nc)  # a side's bound repeated for each constrained step
        accel = p.max_accel * p.dt * self._apothem
        self._accel_upper = np.full(nc * count, accel)
        self._accel_lower = -self._accel_upper if self._two_sided else np.full(nc * count, -_UNBOUNDED)
        self._qp_hessian = np.ascontiguousarray(np.kron(np.eye(2), hessian))
        self._qp_rows = np.ascontiguousarray(np.vstack((self._a_speed, self._a_accel)))
        self._qp_sense = np.zeros(len(self._qp_rows), dtype=np.intc)  # every row an inequality
        # The rows' bounds, filled in each call (so one instance serves one control loop at a time): the speed sides
        # first (they move with u_{k-1}), then the acceleration sides. One side only (M odd): the other bound is
        # DAQP's "none".
        self._upper = np.full(len(self._qp_rows), _UNBOUNDED)
        self._lower = np.full(len(self._qp_rows), -_UNBOUNDED)
        speed_rows = len(self._a_speed)
        self._upper_speed, self._lower_speed = self._upper[:speed_rows], self._lower[:speed_rows]
        self._upper_accel, self._lower_accel = self._upper[speed_rows:], self._lower[speed_rows:]
        self._fallbacks = 0
        self._last_status = "not run"

    @property
    def fallbacks(self) -> int:
        """How many calls used the fallback rule instead of the QP's answer."""
        return self._fallbacks

    @property
    def last_status(self) -> str:
        """How the last command was found: 'unconstrained', 'solved' (by the QP solver), or 'fallback: <reason>'."""
        return self._last_status

    def _move(self, previous: np.ndarray, eta: np.ndarray) -> np.ndarray:
        """The first command u_k = u_{k-1} + du_k of the plan ``eta`` ([eta_x, eta_y])."""
        return previous + eta.reshape(2, -1) @ self._first

    def command(self, position: ArrayLike, previous: ArrayLike, ref_positions: ArrayLike,
                ref_velocities: ArrayLike, max_speed: float | None = None,
                max_accel: float | None = None) -> np.ndarray:
        """World-frame velocity (2,) for this cycle.

        position: measured position (2,) [m] at the current time k;
        previous: the velocity commanded last cycle (2,) [m/s] (u_{k-1});
        ref_positions: (horizon + 1, 2) reference positions at times k, k+1, ..., k+horizon;
        ref_velocities: (horizon, 2) reference velocities at k .. k+horizon-1;
        max_speed: a lower speed limit for this call (e.g. while dribbling), None = params.max_speed;
        the limit may not exceed params.max_speed (ValueError);
        max_accel: likewise a lower acceleration limit for this call, None = params.max_accel.
        """
        p = self.params
        h = p.horizon
        position = _array(position, (2,), "position")
        previous = _array(previous, (2,), "previous")
        ref_positions = _array(ref_positions, (h + 1, 2), "ref_positions")
        _array(ref_velocities, (h, 2), "ref_velocities")
        speed = p.max_speed if max_speed is None else float(max_speed)
        if not (math.isfinite(speed) and 0.0 < speed <= p.max_speed):
            raise ValueError(f"max_speed must lie in (0, {p.max_speed}], got {max_speed}")
        accel = p.max_accel if max_accel is None else float(max_accel)
        if not (math.isfinite(accel) and 0.0 < accel <= p.max_accel):
            raise ValueError(f"max_accel must lie in (0, {p.max_accel}], got {max_accel}")
        step = accel * p.dt

        # Predicted errors e_{k+1..k+H} if u stayed u_{k-1} (eta = 0), shape (H, 2); per axis (rows x, y) the QP
        # gradient and the unconstrained optimum. This runs every cycle of every robot, where numpy's per-call
        # overhead outweighs the arithmetic: both axes in one product each, the bounds filled in place.
        free = position + self._carry * previous - ref_positions[1:]
        gradient = free.T @ self._gradient_t
        optimum = gradient @ self._hessian_inv_t  # -eta per axis
        q, eta = gradient.ravel(), -optimum.ravel()  # [q_x, q_y], [eta_x, eta_y]
        unconstrained = previous - optimum @ self._first

        # Speed: n_j . (u_{k-1} + du_k + ... + du_{k+i}) within the polygon of ``speed``; acceleration: n_j . du.
        offset = (self._normals @ previous)[self._per_step]
        np.subtract(speed * self._apothem, offset, out=self._upper_speed)
        if self._two_sided:
            np.subtract(-speed * self._apothem, offset, out=self._lower_speed)
        scale = accel / p.max_accel
        np.multiply(self._accel_upper, scale, out=self._upper_accel)
        np.multiply(self._accel_lower, scale, out=self._lower_accel)
        rows = self._qp_rows @ eta
        if (rows <= self._upper).all() and (rows >= self._lower).all():
            status = "unconstrained"
            command = _project_two_discs(unconstrained, speed, previous, step)  # inside already, bar rounding
        else:
            x, _, flag, _ = daqp.solve(self._qp_hessian, q, self._qp_rows, self._upper, self._lower, self._qp_sense)
            status = _DAQP_STATUS.get(flag, f"exit flag {flag}")
            command = None
            if status == "solved" and np.isfinite(x).all():
                command = _project_two_discs(self._move(previous, np.asarray(x)), speed, previous, step)
                if command is None:
                    status = "limits unreachable in one step"
        if command is not None:
            self._last_status = status
            return command
        # Fallback: head for the velocity within the limit nearest the unconstrained choice, by at most one step
        # (keeping within the limit too when one step can reach it).
        self._fallbacks += 1
        self._last_status = f"fallback: {status}"
        target = _clip_norm(unconstrained, speed)
        command = _project_two_discs(target, speed, previous, step)
        return previous + _clip_norm(target - previous, step) if command is None else command
