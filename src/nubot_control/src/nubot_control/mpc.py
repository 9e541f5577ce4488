"""Trajectory tracking by model predictive control with Laguerre-parameterised control increments.

Requires: the measured position, the velocity commanded last cycle and a sampled reference
(positions and velocities), all in the world frame.
Provides: ``laguerre_basis`` (discrete Laguerre functions, Wang 2009 ch. 3), ``MpcParams`` and
``LaguerreMpc.command`` -> world-frame velocity (ux, uy) for this cycle.
Units SI: m, s, m/s, m/s^2. No ROS: the node rotates the command into the body frame and
controls the heading separately. The computation is compiled (``nubot_control._kernels``, C++ with Eigen, and DAQP's
C library, a dual active-set QP solver, built by catkin_make from ``cpp/mpc.cpp``); this module holds its parameters
and its Python API.

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
solver is not called; else DAQP solves the small dense QP exactly (an ADMM solver to 1e-3 took
250 us and its first move was up to 0.1 m/s off), within ``solver_iterations`` iterations.

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

from dataclasses import asdict, dataclass
from typing import TYPE_CHECKING

from nubot_common.kernels import load_kernels
from nubot_common.params import require_non_negative, require_positive

if TYPE_CHECKING:
    from nubot_control import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("nubot_control")

laguerre_basis = _kernels.laguerre_basis
"""laguerre_basis(pole, terms, steps) -> array (steps, terms): discrete Laguerre functions, row i is L(i)^T.

L(0) = sqrt(1 - a^2) [1, -a, a^2, ..., (-a)^(N-1)] and L(i+1) = A_l L(i) (Wang 2009, ch. 3), A_l having a on the
diagonal and (1 - a^2) (-a)^(r-c-1) below it. The columns are orthonormal over an infinite horizon; with pole 0 they
are unit pulses at steps 0 .. N-1.
"""


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
    solver_iterations: int = 10000  # DAQP's iteration limit (its default); beyond it the fallback rule acts

    def __post_init__(self) -> None:
        require_positive(self, "dt", "position_weight", "max_speed", "max_accel", "solver_iterations")
        require_non_negative(self, "effort_weight", "laguerre_pole")
        for name in ("horizon", "laguerre_terms", "polygon_sides", "constrained_steps", "solver_iterations"):
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


class LaguerreMpc(_kernels.LaguerreMpc):
    """Laguerre-parameterised MPC for a planar integrator: one QP with 2N variables per control cycle.

    ``command(position, previous, ref_positions, ref_velocities, max_speed=None, max_accel=None)`` -> the
    world-frame velocity (2,) for this cycle:
    position: measured position (2,) [m] at the current time k;
    previous: the velocity commanded last cycle (2,) [m/s] (u_{k-1});
    ref_positions: (horizon + 1, 2) reference positions at times k, k+1, ..., k+horizon;
    ref_velocities: (horizon, 2) reference velocities at k .. k+horizon-1;
    max_speed: a lower speed limit for this call (e.g. while dribbling), None = params.max_speed;
    the limit may not exceed params.max_speed (ValueError);
    max_accel: likewise a lower acceleration limit for this call, None = params.max_accel.
    Input of the wrong shape, not finite, or limits out of range: ValueError naming it.

    ``fallbacks``: how many calls used the fallback rule instead of the QP's answer; ``last_status``: how the last
    command was found ('unconstrained', 'solved' by the QP solver, or 'fallback: <reason>'); ``last_qp()``: the QP
    of the last call, (hessian, gradient, rows, lower, upper).
    """

    def __init__(self, params: MpcParams) -> None:
        super().__init__(**asdict(params))
        self.params = params
