"""Unit tests of the Laguerre-parameterised MPC tracker (closed loop on the kinematic model p += dt * u)."""

import json
import math
from pathlib import Path

import numpy as np
import pytest
from scipy.optimize import minimize

from nubot_control.mpc import LaguerreMpc, MpcParams, laguerre_basis

P = MpcParams()
H, DT = P.horizon, P.dt
STEP = P.max_accel * P.dt  # the largest velocity change per cycle [m/s]


def straight(speed, heading=0.0):
    """A reference along ``heading`` at ``speed`` from the origin: t -> (positions, velocities)."""
    direction = np.array([math.cos(heading), math.sin(heading)])
    return lambda t: (np.outer(speed * t, direction), np.tile(speed * direction, (len(t), 1)))


def circle(radius, speed):
    """A counter-clockwise circle about the origin starting at (radius, 0)."""
    def ref(t):
        angle = speed / radius * t
        return (radius * np.column_stack((np.cos(angle), np.sin(angle))),
                speed * np.column_stack((-np.sin(angle), np.cos(angle))))
    return ref


def simulate(ref, start, seconds, previous=(0.0, 0.0), max_speed=None, params=P):
    """Track ``ref`` from ``start``; return the errors |p_k - r_k|, the commands and the controller."""
    mpc = LaguerreMpc(params)
    p, u = np.array(start, float), np.array(previous, float)
    errors, commands = [], []
    for k in range(int(round(seconds / params.dt))):
        ref_positions, ref_velocities = ref((k + np.arange(params.horizon + 1)) * params.dt)
        errors.append(float(np.hypot(*(p - ref_positions[0]))))
        u = mpc.command(p, u, ref_positions, ref_velocities[:-1], max_speed)
        commands.append(u)
        p = p + params.dt * u
    return np.array(errors), np.array(commands), mpc


def random_reference(rng, speed):
    """Reference samples from the origin at about ``speed``, turning at a random rate."""
    heading = rng.uniform(0.0, 2.0 * math.pi) + rng.uniform(-1.5, 1.5) * DT * np.arange(H)
    velocities = speed * np.column_stack((np.cos(heading), np.sin(heading)))
    positions = np.vstack((np.zeros(2), DT * np.cumsum(velocities, axis=0)))
    return positions, velocities


def inside_disc(rng, radius):
    angle, r = rng.uniform(0.0, 2.0 * math.pi), radius * math.sqrt(rng.uniform())
    return np.array([r * math.cos(angle), r * math.sin(angle)])


def test_laguerre_basis_is_orthonormal_and_reduces_to_pulses():
    for pole in (0.2, 0.5, 0.8):
        basis = laguerre_basis(pole, 5, 400)
        assert basis.shape == (400, 5)
        assert basis[0] == pytest.approx(math.sqrt(1 - pole**2) * (-pole) ** np.arange(5))
        np.testing.assert_allclose(basis.T @ basis, np.eye(5), atol=1e-9)
        assert not np.allclose(laguerre_basis(pole, 5, 5).T @ laguerre_basis(pole, 5, 5), np.eye(5), atol=1e-3), \
            "over a short horizon they are not orthonormal yet"
    pulses = laguerre_basis(0.0, 4, 10)
    np.testing.assert_array_equal(pulses, np.vstack((np.eye(4), np.zeros((6, 4)))))


def test_commands_never_exceed_the_speed_and_acceleration_limits():
    rng = np.random.default_rng(20240611)
    mpc = LaguerreMpc(P)
    constrained = 0
    for trial in range(400):
        ref_positions, ref_velocities = random_reference(rng, rng.uniform(0.0, 1.5 * P.max_speed))
        position = inside_disc(rng, 5.0)
        limit = None if trial % 3 else rng.uniform(0.5, P.max_speed)
        speed = P.max_speed if limit is None else limit
        previous = inside_disc(rng, speed)
        u = mpc.command(position, previous, ref_positions, ref_velocities, limit)
        assert u.shape == (2,)
        assert np.hypot(*u) <= speed + 1e-9
        assert np.hypot(*(u - previous)) <= STEP + 1e-9
        constrained += mpc.last_status != "unconstrained"
    assert constrained > 100, "the QP itself must have been exercised"
    assert mpc.fallbacks == 0, "a previous command within the limits always leaves the QP feasible"


def test_a_lowered_acceleration_limit_holds_for_that_call():
    rng = np.random.default_rng(11)
    mpc = LaguerreMpc(P)
    for _ in range(200):
        ref_positions, ref_velocities = random_reference(rng, rng.uniform(0.0, P.max_speed))
        previous = inside_disc(rng, 1.5)
        u = mpc.command(inside_disc(rng, 3.0), previous, ref_positions, ref_velocities, max_speed=1.5,
                        max_accel=1.5)
        assert np.hypot(*(u - previous)) <= 1.5 * DT + 1e-9 and np.hypot(*u) <= 1.5 + 1e-9
    with pytest.raises(ValueError, match="max_accel must lie in"):
        mpc.command(np.zeros(2), np.zeros(2), np.zeros((H + 1, 2)), np.zeros((H, 2)), max_accel=P.max_accel + 1)


def test_a_lowered_limit_below_the_previous_speed_brakes_at_max_accel():
    mpc = LaguerreMpc(P)
    ref_positions, ref_velocities = straight(3.0)((np.arange(H + 1)) * DT)
    previous, position, braking = np.array([3.0, 0.0]), np.zeros(2), 0
    for _ in range(40):
        u = mpc.command(position, previous, ref_positions + position, ref_velocities[:-1], max_speed=1.5)
        assert np.hypot(*(u - previous)) <= STEP + 1e-9
        if np.hypot(*previous) > 1.5 + STEP:
            braking += 1
            assert np.hypot(*u) == pytest.approx(np.hypot(*previous) - STEP, abs=1e-12), "as hard as allowed"
            assert mpc.last_status.startswith("fallback")
        else:
            assert np.hypot(*u) <= 1.5 + 1e-9
        previous, position = u, position + DT * u
    assert braking == 16 and mpc.fallbacks == braking
    # From any direction and situation the speed drops, by a full step towards the feasible velocity.
    rng = np.random.default_rng(7)
    for trial in range(100):
        ref_positions, ref_velocities = random_reference(rng, rng.uniform(0.0, P.max_speed))
        previous = inside_disc(rng, 1.0)
        previous *= rng.uniform(1.0 + STEP + 1e-6, P.max_speed) / np.hypot(*previous)
        u = mpc.command(inside_disc(rng, 3.0), previous, ref_positions, ref_velocities, max_speed=1.0)
        assert np.hypot(*(u - previous)) == pytest.approx(STEP, abs=1e-12)
        assert np.hypot(*u) < np.hypot(*previous)
        assert mpc.fallbacks == braking + trial + 1


def test_a_tracker_answers_each_qp_as_a_new_tracker_does():
    """The solver's workspace is set up once and kept from one QP to the next; it carries nothing over: the same
    commands to the last bit and the same way found, for solvable and infeasible QPs alike."""
    rng = np.random.default_rng(5)
    for params in (P, MpcParams(polygon_sides=7, constrained_steps=3)):
        kept = LaguerreMpc(params)
        statuses = set()
        for trial in range(300):
            ref_positions, ref_velocities = random_reference(rng, rng.uniform(0.0, 1.5 * params.max_speed))
            speed = None if trial % 3 else rng.uniform(0.5, params.max_speed)
            accel = None if trial % 4 else rng.uniform(0.5, params.max_accel)
            call = (inside_disc(rng, 2.0), inside_disc(rng, params.max_speed), ref_positions, ref_velocities, speed,
                    accel)
            new = LaguerreMpc(params)
            np.testing.assert_array_equal(kept.command(*call), new.command(*call), err_msg=f"call {trial}")
            assert kept.last_status == new.last_status, f"call {trial}"
            statuses.add(kept.last_status)
        assert {"solved", "fallback: infeasible"} <= statuses


def test_a_failing_solver_falls_back_within_both_limits():
    mpc = LaguerreMpc(MpcParams(solver_iterations=1))  # DAQP runs out of iterations on every constrained QP
    rng = np.random.default_rng(11)
    fallbacks = 0
    for _ in range(200):
        ref_positions, ref_velocities = random_reference(rng, rng.uniform(0.0, 1.5 * P.max_speed))
        limit = rng.uniform(0.5, P.max_speed)
        previous = inside_disc(rng, 1.0)
        previous *= rng.uniform(0.0, limit + STEP) / np.hypot(*previous)  # within one step of the limit
        u = mpc.command(inside_disc(rng, 5.0), previous, ref_positions, ref_velocities, limit)
        assert np.hypot(*u) <= limit + 1e-9
        assert np.hypot(*(u - previous)) <= STEP + 1e-9
        assert mpc.last_status in ("unconstrained", "fallback: iteration limit")
        fallbacks += mpc.last_status != "unconstrained"
    assert mpc.fallbacks == fallbacks > 100


def test_converges_on_a_straight_line_from_a_lateral_offset():
    errors, commands, mpc = simulate(straight(2.0), start=(0.0, 0.5), seconds=6.0)
    settled = errors[int(3.0 / DT):]
    assert settled.max() < 0.02, f"error after 3 s up to {settled.max():.4f} m"
    assert errors[0] == pytest.approx(0.5)
    assert np.hypot(*commands[-1]) == pytest.approx(2.0, abs=1e-3)
    assert mpc.fallbacks == 0


def test_converges_on_a_circle_from_an_offset_start():
    errors, _, mpc = simulate(circle(2.5, 2.0), start=(3.0, 0.0), seconds=8.0)
    settled = errors[int(4.0 / DT):]
    assert settled.max() < 0.03, f"error after 4 s up to {settled.max():.4f} m"
    assert mpc.fallbacks == 0


def test_a_reference_faster_than_max_speed_saturates_the_command():
    for heading in (0.0, math.radians(10.0), math.radians(-120.0)):
        errors, commands, _ = simulate(straight(4.0, heading), start=(0.0, 0.0), seconds=4.0)
        speeds = np.hypot(*commands.T)
        assert speeds.max() <= P.max_speed + 1e-9
        # Full speed, up to the inscribed polygon's corner cut (1.9 % with 16 sides) between its vertices,
        # with a reference running away.
        assert speeds[-30:].min() >= 0.95 * P.max_speed
        assert commands[-1] @ [math.cos(heading), math.sin(heading)] == pytest.approx(speeds[-1], rel=0.02)
        assert np.all(np.diff(errors[-30:]) > 0), "the reference runs away; the robot does its best"
    _, commands, _ = simulate(straight(4.0), start=(0.0, 0.0), seconds=4.0)
    assert 0.95 * P.max_speed <= np.hypot(*commands[-1]) <= P.max_speed, "along an axis, at a polygon vertex"


def test_zero_error_and_a_still_reference_give_a_zero_command():
    mpc = LaguerreMpc(P)
    here = np.array([1.2, -3.4])
    u = mpc.command(here, [0.0, 0.0], np.tile(here, (H + 1, 1)), np.zeros((H, 2)))
    np.testing.assert_allclose(u, [0.0, 0.0], atol=1e-12)
    assert mpc.last_status == "unconstrained" and mpc.fallbacks == 0


def solve_exactly(hessian, q, rows, lower, upper):
    """argmin 0.5 x'Hx + q'x with lower <= rows x <= upper, by SLSQP to 1e-12."""
    result = minimize(lambda x: 0.5 * x @ hessian @ x + q @ x, np.zeros(len(q)), jac=lambda x: hessian @ x + q,
                      method="SLSQP", tol=1e-12, options={"maxiter": 500},
                      constraints=[{"type": "ineq", "fun": lambda x: rows @ x - lower, "jac": lambda x: rows},
                                   {"type": "ineq", "fun": lambda x: upper - rows @ x, "jac": lambda x: -rows}])
    assert result.success, result.message
    return result.x


def test_a_constrained_command_is_the_first_move_of_the_qp_s_exact_optimum():
    """Where the limits bind, the command is the optimum's first move, as an independent solver (SLSQP to
    1e-12) finds it on the same QP: not an approximation of it."""
    mpc, n = LaguerreMpc(P), P.laguerre_terms
    rng = np.random.default_rng(5)
    first = laguerre_basis(P.laguerre_pole, n, H)[0]
    checked = 0
    while checked < 20:
        ref_positions, ref_velocities = random_reference(rng, 5.0)
        position, previous = inside_disc(rng, 3.0), inside_disc(rng, 2.5)
        u = mpc.command(position, previous, ref_positions, ref_velocities)
        if mpc.last_status != "solved":
            continue
        hessian, q, rows, lower, upper = mpc.last_qp()  # the QP of this call
        eta = solve_exactly(hessian, q, rows, lower, upper)
        exact = previous + np.array([first @ eta[:n], first @ eta[n:]])
        np.testing.assert_allclose(u, exact, atol=1e-5)
        checked += 1


@pytest.mark.parametrize("kwargs, message", [
    ({"position": [math.nan, 0.0]}, "position must be finite"),
    ({"position": [0.0, 0.0, 0.0]}, "position must have shape"),
    ({"previous": [0.0, math.inf]}, "previous must be finite"),
    ({"previous": "fast"}, "previous must be numbers"),
    ({"ref_positions": np.zeros((H, 2))}, "ref_positions must have shape"),
    ({"ref_velocities": np.zeros((H + 1, 2))}, "ref_velocities must have shape"),
    ({"ref_velocities": np.full((H, 2), math.nan)}, "ref_velocities must be finite"),
    ({"max_speed": P.max_speed + 0.01}, "max_speed must lie in"),
    ({"max_speed": 0.0}, "max_speed must lie in"),
    ({"max_speed": math.nan}, "max_speed must lie in"),
])
def test_bad_input_is_refused(kwargs, message):
    args = {"position": np.zeros(2), "previous": np.zeros(2), "ref_positions": np.zeros((H + 1, 2)),
            "ref_velocities": np.zeros((H, 2)), **kwargs}
    mpc = LaguerreMpc(P)
    with pytest.raises(ValueError, match=message):
        mpc.command(**args)
    assert mpc.last_status == "not run"


@pytest.mark.parametrize("kwargs, message", [
    ({"dt": 0.0}, "dt must be positive"),
    ({"max_speed": -1.0}, "max_speed must be positive"),
    ({"effort_weight": -0.1}, "effort_weight must not be negative"),
    ({"laguerre_pole": 1.0}, "laguerre_pole must be below 1"),
    ({"laguerre_pole": -0.1}, "laguerre_pole must not be negative"),
    ({"laguerre_terms": 21}, "laguerre_terms must lie in"),
    ({"horizon": 20.0}, "horizon must be an integer"),
    ({"polygon_sides": 2}, "polygon_sides must be >= 3"),
    ({"constrained_steps": 0}, "constrained_steps must lie in"),
    ({"constrained_steps": 21}, "constrained_steps must lie in"),
])
def test_bad_parameters_are_refused(kwargs, message):
    with pytest.raises(ValueError, match=message):
        MpcParams(**kwargs)


def test_odd_polygons_and_a_short_constrained_horizon_also_keep_the_limits():
    params = MpcParams(polygon_sides=7, constrained_steps=1)
    errors, commands, mpc = simulate(circle(2.5, 2.0), start=(3.0, 0.0), seconds=6.0, params=params)
    previous = np.vstack((np.zeros(2), commands[:-1]))
    assert np.hypot(*commands.T).max() <= params.max_speed + 1e-9
    assert np.hypot(*(commands - previous).T).max() <= params.max_accel * params.dt + 1e-9
    assert errors[-30:].max() < 0.03 and mpc.fallbacks == 0


GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "mpc.npz"


def test_the_compiled_tracker_gives_the_python_tracker_s_commands_on_its_golden_trace():
    """1254 calls recorded from the Python implementation over 3 seeded lockstep matches of 60 s (every call whose
    QP was infeasible, 500 solved, 500 unconstrained; by ``nubot_tools.golden`` before it moved): the same way found,
    the same command to 1e-12 m/s. The two differ only in the order of floating-point sums (measured: 6e-15)."""
    with np.load(GOLDEN) as archive:
        trace = dict(archive)  # an archive reads an entry anew at each look
    mpc = LaguerreMpc(MpcParams(**json.loads(str(trace["params"]))))
    statuses = set()
    for i, status in enumerate(trace["status"]):
        limits = [None if math.isnan(v) else float(v) for v in (trace["max_speed"][i], trace["max_accel"][i])]
        u = mpc.command(trace["position"][i], trace["previous"][i], trace["ref_positions"][i],
                        trace["ref_velocities"][i], *limits)
        assert mpc.last_status == status, f"call {i}"
        np.testing.assert_allclose(u, trace["command"][i], rtol=0.0, atol=1e-12, err_msg=f"call {i} ({status})")
        statuses.add(status)
    assert statuses == {"unconstrained", "solved", "fallback: infeasible"}
