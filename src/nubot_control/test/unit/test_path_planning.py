"""Unit tests of the online path planner: subtargets, cubic B-spline, clearances, bounds and speed profile."""

import json
import math
from pathlib import Path

import numpy as np
import pytest

from nubot_control.path_planning import (
    Bounds,
    Disc,
    PlannerParams,
    _trajectory,
    clearance,
    keeps_clear,
    plan,
    subtargets,
)

P = PlannerParams()
FIELD = Bounds(-11.0, 11.0, -7.0, 7.0)
ROBOT = 0.26  # an obstacle robot's radius [m]
KEEP = P.robot_radius + P.safety_margin  # least distance from the path to an obstacle's hull [m]
TOTAL_ACCEL = P.max_accel  # along and across the path together [m/s^2]


def segment_distance(a, b, o: Disc) -> float:
    """Distance from the obstacle's centre to segment a-b [m]."""
    a, b, c = np.asarray(a, float), np.asarray(b, float), np.array((o.x, o.y))
    d = b - a
    t = 0.0 if d @ d < 1e-12 else float(np.clip((c - a) @ d / (d @ d), 0.0, 1.0))
    return float(np.hypot(*(a + t * d - c)))


def contains(o: Disc, p) -> bool:
    return math.hypot(p[0] - o.x, p[1] - o.y) < clearance(o, P)


def speeds(tr) -> np.ndarray:
    return np.hypot(tr.v[:, 0], tr.v[:, 1])


def turning(tr) -> np.ndarray:
    """Heading change [rad] between consecutive sample-to-sample steps."""
    step = np.diff(tr.xy, axis=0)
    heading = np.unwrap(np.arctan2(step[:, 1], step[:, 0]))
    return np.abs(np.diff(heading))


def random_scene(rng):
    """Start on the left, goal on the right, 1..10 robots between them (not overlapping); now and then one
    right beside the start or the goal, whose clearance then contains it."""
    start, goal = (-5.0, float(rng.uniform(-2.0, 2.0))), (5.0, float(rng.uniform(-2.0, 2.0)))
    obstacles = []
    count = int(rng.integers(1, 11))
    while len(obstacles) < count:
        x, y = rng.uniform(-4.0, 4.0), rng.uniform(-2.5, 2.5)
        if all(math.hypot(x - o.x, y - o.y) >= 2.0 * ROBOT for o in obstacles):
            obstacles.append(Disc(float(x), float(y), ROBOT))
    if rng.random() < 0.25:
        end = start if rng.random() < 0.5 else goal
        angle = rng.uniform(-math.pi, math.pi)
        x, y = end[0] + 0.55 * math.cos(angle), end[1] + 0.55 * math.sin(angle)
        if all(math.hypot(x - o.x, y - o.y) >= 2.0 * ROBOT for o in obstacles):
            obstacles.append(Disc(x, y, ROBOT))
    return start, goal, obstacles


def route_is_clear(route, obstacles) -> bool:
    """Every segment keeps the clearance of every obstacle that contains neither of its ends."""
    return all(segment_distance(a, b, o) >= clearance(o, P) - 1e-9
               for a, b in zip(route, route[1:]) for o in obstacles if not (contains(o, a) or contains(o, b)))


def check_speed_profile(tr, start_speed: float, end_speed: float) -> None:
    v = speeds(tr)
    ds = np.diff(tr.s)
    assert np.all(np.diff(tr.t) > 0.0) and tr.t[0] == 0.0
    assert v.max() <= P.max_speed + 1e-9
    along = (v[1:] ** 2 - v[:-1] ** 2) / (2.0 * ds)  # tangential acceleration between samples
    assert along.max() <= P.max_accel + 1e-6, "speeding up too hard"
    assert along.min() >= -P.max_accel - 1e-6, "braking too hard"
    curvature = turning(tr) / ds[1:]
    lateral = v[1:-1] ** 2 * curvature
    assert lateral.max() <= 1.1 * P.max_lateral_accel, "too fast for the curvature"
    whole = np.hypot(0.5 * (along[:-1] + along[1:]), lateral)
    assert whole.max() <= 1.1 * P.max_accel, "speeding up or braking too hard on a curve"
    assert v[0] == pytest.approx(start_speed, abs=1e-9)
    assert v[-1] == pytest.approx(end_speed, abs=1e-9)


def test_clearance_adds_both_radii_and_the_margin():
    assert clearance(Disc(0.0, 0.0, ROBOT), P) == pytest.approx(0.26 + 0.26 + 0.15)
    assert clearance(Disc(0.0, 0.0, 0.06), P) == pytest.approx(0.26 + 0.06 + 0.15)


def test_spline_passes_near_each_waypoint_and_is_smooth():
    waypoints = [(-1.0, 2.0), (3.0, 2.5), (4.0, -1.5), (0.0, -3.0)]
    tr = plan((-5.0, -1.0), waypoints, [Disc(1.0, 2.4, ROBOT)], P, FIELD)
    for w in waypoints:
        assert np.hypot(*(tr.xy - w).T).min() <= 0.05, f"passes near {w}"
    assert tr.xy[0] == pytest.approx((-5.0, -1.0)) and tr.xy[-1] == pytest.approx(waypoints[-1])
    dt = np.diff(tr.t)
    jump = np.hypot(*np.diff(tr.v, axis=0).T)
    assert np.all(np.abs(np.diff(speeds(tr))) <= P.max_accel * dt + 1e-6), "speed continuous"
    assert np.all(jump <= 1.05 * TOTAL_ACCEL * dt + 1e-3), "velocity continuous (along and across the path)"
    assert turning(tr).max() < 0.3, "direction changes gradually"
    assert np.all(np.diff(tr.s) <= P.sample_step + 1e-9)


def test_subtargets_never_route_through_an_obstacle():
    rng = np.random.default_rng(20240611)
    for _ in range(300):
        start, goal, obstacles = random_scene(rng)
        via = subtargets(start, goal, obstacles, P, FIELD)
        assert len(via) <= P.max_subtargets
        assert route_is_clear([start, *via, goal], obstacles), (start, goal, obstacles, via)
        assert not any(contains(o, p) for p in via for o in obstacles), "a subtarget inside a clearance"


def test_subtargets_only_where_needed_and_within_the_budget():
    wall = [Disc(0.0, -3.0, ROBOT), Disc(3.0, 3.0, ROBOT)]  # both well off the straight route
    assert subtargets((-5.0, 0.0), (5.0, 0.0), wall, P, FIELD) == []
    row = [Disc(-2.0, 0.0, ROBOT), Disc(2.0, 0.3, ROBOT)]
    assert len(subtargets((-5.0, 0.0), (5.0, 0.0), row, P, FIELD)) == 2, "one beside each robot"
    assert len(subtargets((-5.0, 0.0), (5.0, 0.0), row, PlannerParams(max_subtargets=1), FIELD)) == 1
    assert subtargets((-5.0, 0.0), (5.0, 0.0), row, PlannerParams(max_subtargets=0), FIELD) == []


def test_adjusted_path_keeps_the_clearances():
    rng = np.random.default_rng(7)
    checked = 0
    for _ in range(200):
        start, goal, obstacles = random_scene(rng)
        if not route_is_clear([start, *subtargets(start, goal, obstacles, P, FIELD), goal], obstacles):
            continue  # no route in this scene
        checked += 1
        kept = [o for o in obstacles if not (contains(o, start) or contains(o, goal))]
        tr = plan(start, [goal], obstacles, P, FIELD)
        assert tr.min_clearance(kept) >= KEEP - 0.02, (start, goal, obstacles)
        assert tr.xy[-1] == pytest.approx(goal)
    assert checked >= 190


def test_spline_pushed_off_an_obstacle_by_the_start_velocity_is_adjusted():
    # moving towards a robot just beside the route: the plain spline through the route would clip its clearance
    robot = Disc(-3.4, 0.7, ROBOT)
    tr = plan((-4.0, 0.0), [(4.0, 0.0)], [robot], P, FIELD, start_velocity=(1.5, 2.0))
    assert tr.v[0] == pytest.approx((1.5, 2.0))
    assert tr.min_clearance([robot]) >= KEEP - 0.02
    free = plan((-4.0, 0.0), [(4.0, 0.0)], [], P, FIELD, start_velocity=(1.5, 2.0))
    assert subtargets((-4.0, 0.0), (4.0, 0.0), [robot], P, FIELD) == [], "the straight route is clear"
    assert len(tr.via) > len(free.via), "a via-point was added to keep the clearance"


def test_a_close_pair_is_passed_round_not_between():
    pair = [Disc(0.0, 0.6, ROBOT), Disc(0.0, -0.6, ROBOT)]  # 1.2 m apart: clearances overlap
    via = subtargets((-3.0, 0.1), (3.0, 0.0), pair, P, FIELD)
    assert via and route_is_clear([(-3.0, 0.1), *via, (3.0, 0.0)], pair)
    tr = plan((-3.0, 0.1), [(3.0, 0.0)], pair, P, FIELD)
    crossing = tr.xy[np.argmin(np.abs(tr.xy[:, 0]))]
    assert abs(crossing[1]) >= 0.6 + clearance(pair[0], P) - 0.02
    assert tr.min_clearance(pair) >= KEEP - 0.02


def test_speed_profile_respects_the_limits():
    obstacles = [Disc(0.0, 0.0, ROBOT), Disc(-2.0, -0.5, ROBOT), Disc(2.5, 0.8, ROBOT)]
    # start velocities along the route's first leg; (4.6, 2.1) is faster than max_speed, so capped
    cases = [((0.0, 0.0), 0.0), ((2.0, 0.9), 0.0), ((2.0, 0.9), 1.5), ((4.6, 2.1), 0.0), ((4.6, 2.1), 9.0)]
    for start_velocity, end_speed in cases:
        tr = plan((-5.0, -1.0), [(5.0, 1.0)], obstacles, P, FIELD, start_velocity=start_velocity,
                  end_speed=end_speed)
        check_speed_profile(tr, min(math.hypot(*start_velocity), P.max_speed), min(end_speed, P.max_speed))
    curvy = plan((-5.0, -1.0), [(-3.0, 1.0), (-1.0, -1.0), (1.0, 1.0), (5.0, 0.0)], [], P, FIELD)
    check_speed_profile(curvy, 0.0, 0.0)
    assert speeds(curvy)[np.argmin(np.hypot(*(curvy.xy - (-1.0, -1.0)).T))] < 0.8 * P.max_speed, "slows in turns"


def test_a_start_too_fast_to_stop_in_time_brakes_as_hard_as_allowed():
    tr = plan((0.0, 0.0), [(1.0, 0.0)], [], P, FIELD, start_velocity=(3.0, 0.0))
    v = speeds(tr)
    assert v[0] == pytest.approx(3.0)
    assert np.all((v[1:] ** 2 - v[:-1] ** 2) / (2.0 * np.diff(tr.s)) >= -P.max_accel - 1e-6)
    assert v[-1] == pytest.approx(math.sqrt(3.0**2 - 2.0 * P.max_accel * 1.0), abs=1e-6), "overshoots the goal"


def test_duration_follows_from_the_speeds():
    tr = plan((0.0, 0.0), [(8.0, 0.0)], [], P, FIELD)
    # straight: accelerate to max speed, cruise, brake
    ramp = P.max_speed**2 / P.max_accel
    expected = 2.0 * P.max_speed / P.max_accel + (8.0 - ramp) / P.max_speed
    assert tr.length == pytest.approx(8.0, abs=1e-6)
    assert tr.duration == pytest.approx(expected, rel=0.01)


def test_figure_13_scene():
    p0, p1, p2, p3 = (-6.0, -3.0), (-2.0, 2.0), (2.0, -2.0), (6.0, 2.0)
    robots = [Disc(-4.0, 0.0, ROBOT), Disc(0.0, 0.0, ROBOT)]
    tr = plan(p0, [p1, p2, p3], robots, P, FIELD)
    assert np.hypot(*(tr.xy - p1).T).min() <= 0.05
    assert np.hypot(*(tr.xy - p2).T).min() <= 0.05
    assert tr.xy[-1] == pytest.approx(p3)
    assert tr.min_clearance(robots) >= KEEP - 0.02
    at_top = speeds(tr) >= P.max_speed - 1e-6
    assert at_top.sum() * P.sample_step >= 0.5, "max speed on some stretch"
    assert len(tr.via) > 4, "subtargets round both robots"


def test_goal_outside_the_field_is_clamped_and_the_path_stays_inside():
    tr = plan((8.0, 5.0), [(14.0, 9.0)], [], P, FIELD)
    assert tr.xy[-1] == pytest.approx((11.0, 7.0)) and tr.via[-1] == (11.0, 7.0)
    assert tr.length == pytest.approx(math.hypot(3.0, 2.0), abs=0.01), "straight to the clamped goal"
    assert all(FIELD.contains(p) for p in tr.xy)
    # through the corner flag and back along the touchline: the spline would bulge a few cm outside
    tr = plan((8.0, 0.0), [(11.0, 7.0), (5.0, 7.0)], [], P, FIELD)
    assert all(FIELD.contains(p) for p in tr.xy)
    assert np.hypot(*(tr.xy - (11.0, 7.0)).T).min() <= 0.05
    # along the touchline round a robot standing next to it: the detour must not leave the field
    tr = plan((-6.0, -6.8), [(6.0, -6.8)], [Disc(0.0, -6.6, ROBOT)], P, FIELD)
    assert all(FIELD.contains(p) for p in tr.xy)
    assert tr.min_clearance([Disc(0.0, -6.6, ROBOT)]) >= KEEP - 0.02


def test_bounds_clamp_and_contain():
    assert FIELD.clamp((20.0, -9.0)) == (11.0, -7.0)
    assert FIELD.clamp((1.0, 2.0)) == (1.0, 2.0)
    assert FIELD.contains((11.0, 0.0)) and not FIELD.contains((11.01, 0.0))
    with pytest.raises(ValueError, match="x_min < x_max"):
        Bounds(1.0, -1.0, 0.0, 1.0)


def test_goal_at_the_start_stands_still():
    tr = plan((1.0, 2.0), [(1.0, 2.005)], [Disc(3.0, 2.0, ROBOT)], P, FIELD, start_velocity=(1.0, 0.0))
    assert len(tr.t) == 1 and tr.duration == 0.0 and tr.length == 0.0
    xy, v = tr.state_at(3.0)
    assert tuple(xy) == (1.0, 2.0) and tuple(v) == (0.0, 0.0)


@pytest.mark.parametrize("kwargs, message", [
    ({"start": (math.nan, 0.0)}, "start must be finite"),
    ({"waypoints": [(1.0, math.inf)]}, r"waypoints\[0\] must be finite"),
    ({"waypoints": []}, "waypoints must not be empty"),
    ({"start_velocity": (0.0, math.nan)}, "start_velocity must be finite"),
    ({"end_speed": -1.0}, "end_speed"),
])
def test_bad_input_raises_a_clear_error(kwargs, message):
    args = {"start": (0.0, 0.0), "waypoints": [(3.0, 0.0)], "obstacles": [], "params": P, "bounds": FIELD} | kwargs
    with pytest.raises(ValueError, match=message):
        plan(**args)


def test_bad_obstacles_and_params_are_refused():
    with pytest.raises(ValueError, match="obstacle x must be finite"):
        Disc(math.nan, 0.0, ROBOT)
    with pytest.raises(ValueError, match="radius must not be negative"):
        Disc(0.0, 0.0, -0.1)
    with pytest.raises(ValueError, match="max_speed must be positive"):
        PlannerParams(max_speed=0.0)
    with pytest.raises(ValueError, match="safety_margin must be finite"):
        PlannerParams(safety_margin=math.inf)
    with pytest.raises(ValueError, match="detour_factor"):
        PlannerParams(detour_factor=0.9)


def test_replanning_from_a_moving_state_continues_smoothly():
    obstacles = [Disc(0.0, 0.0, ROBOT), Disc(-2.0, -0.5, ROBOT), Disc(2.5, 0.8, ROBOT)]
    first = plan((-5.0, -1.0), [(5.0, 1.0)], obstacles, P, FIELD)
    for time in (0.3, 1.0, 2.0, 3.0):
        xy, v = first.state_at(time)
        again = plan(tuple(xy), [(5.0, 1.0)], obstacles, P, FIELD, start_velocity=tuple(v))
        assert np.hypot(*(again.v[0] - v)) <= 0.05 * np.hypot(*v), f"velocity kept at t={time}"
        assert again.xy[0] == pytest.approx(xy)
        ahead = np.array([0.1, 0.3])
        drift = np.hypot(*(again.states_at(ahead)[0] - first.states_at(time + ahead)[0]).T)
        assert drift.max() < 0.1, "the new plan continues the old one"
        assert again.duration == pytest.approx(first.duration - time, abs=0.15)


def test_states_at_interpolates_and_holds_the_ends():
    tr = plan((0.0, 0.0), [(4.0, 0.0)], [], P, FIELD)
    xy, v = tr.states_at(np.array([-1.0, tr.duration / 2.0, tr.duration + 1.0]))
    assert xy[0] == pytest.approx((0.0, 0.0)) and v[0] == pytest.approx((0.0, 0.0))
    assert xy[1] == pytest.approx((2.0, 0.0), abs=0.01) and v[1][0] > 1.0
    assert xy[2] == pytest.approx((4.0, 0.0)) and v[2] == pytest.approx((0.0, 0.0))
    # from rest the first steps are long in time: positions follow the constant acceleration, not a chord
    xy, v = tr.state_at(0.1)
    assert xy == pytest.approx((0.5 * P.max_accel * 0.1**2, 0.0), abs=1e-6)
    assert v == pytest.approx((P.max_accel * 0.1, 0.0), abs=1e-6)
    assert tr.min_clearance([]) == math.inf
    assert tr.min_clearance([Disc(2.0, 1.0, 0.2)]) == pytest.approx(0.8, abs=1e-6)


def test_state_at_is_states_at_for_one_time():
    tr = plan((0.0, 0.0), [(3.0, 2.0), (5.0, -1.0)], [Disc(1.5, 1.0, 0.26)], P, FIELD, start_velocity=(1.0, 0.5))
    times = np.concatenate(([-1.0, 0.0], np.linspace(0.0, tr.duration, 97), [tr.duration + 2.0]))
    xy, v = tr.states_at(times)
    for i, time in enumerate(times.tolist()):
        one_xy, one_v = tr.state_at(time)
        assert one_xy.tolist() == pytest.approx(xy[i].tolist(), abs=1e-12)
        assert one_v.tolist() == pytest.approx(v[i].tolist(), abs=1e-12)
    still = plan((1.0, 1.0), [(1.0, 1.0)], [], P, FIELD)
    assert still.state_at(0.5)[0].tolist() == [1.0, 1.0]


GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "plan.npz"


def test_the_compiled_planner_gives_the_python_planner_s_trajectories_on_its_golden_trace():
    """600 calls drawn from the 25,268 the Python implementation made over 3 seeded lockstep matches of 60 s
    (by ``nubot_tools.golden`` before it moved), each trajectory kept at every 8th sample and its last: the same number
    of samples and route, positions to 1e-9 m, velocities to 1e-6 m/s, times to 1e-5 s. The two differ in the order
    of floating-point sums and in the spline's linear solver (LAPACK's banded LU against Eigen's dense one, both
    with partial pivoting); measured: positions and routes 2e-13 m, velocities 3e-8 m/s, times 3e-6 s (the latter
    two where a plan starts from rest: its first speeds are square roots of differences of nearly equal numbers)."""
    with np.load(GOLDEN) as archive:
        trace = dict(archive)  # an archive reads an entry anew at each look

    def rows(name, i):
        offsets = trace[f"{name}_offsets"]
        return trace[name][offsets[i]:offsets[i + 1]]

    extended = 0
    for i in range(len(trace["start"])):
        params = PlannerParams(**json.loads(str(trace["params"][i])))
        obstacles = [Disc(*row) for row in rows("obstacles", i)]
        waypoints = [tuple(w) for w in rows("waypoints", i)]
        tr = plan(tuple(trace["start"][i]), waypoints, obstacles, params, Bounds(*trace["bounds"][i]),
                  start_velocity=tuple(trace["start_velocity"][i]), end_speed=float(trace["end_speed"][i]))
        assert len(tr.t) == trace["sample_count"][i], f"call {i}"
        np.testing.assert_allclose(np.array(tr.via), rows("via", i), rtol=0.0, atol=1e-9, err_msg=f"call {i}")
        index, expected = rows("sample_index", i).ravel().astype(int), rows("samples", i)
        np.testing.assert_allclose(tr.t[index], expected[:, 0], rtol=0.0, atol=1e-5, err_msg=f"call {i}")
        np.testing.assert_allclose(tr.s[index], expected[:, 1], rtol=0.0, atol=1e-9, err_msg=f"call {i}")
        np.testing.assert_allclose(tr.xy[index], expected[:, 2:4], rtol=0.0, atol=1e-9, err_msg=f"call {i}")
        np.testing.assert_allclose(tr.v[index], expected[:, 4:6], rtol=0.0, atol=1e-6, err_msg=f"call {i}")
        extended += len(tr.via) > len(waypoints) + 1
    assert extended > 50, "the trace must hold routes the planner extended (subtargets, corrections)"


CLEAR_GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "clear.npz"


def test_the_clearance_check_gives_its_golden_answers():
    """400 of the 40,057 checks the motion layer made of a kept plan's path (3 seeded lockstep matches of 60 s,
    by ``nubot_tools.golden``), half clear and half not, recorded from the numpy implementation the
    compiled one replaced: the same answer for every one (both compare the same squared distances)."""
    with np.load(CLEAR_GOLDEN) as archive:
        trace = dict(archive)

    def rows(name, i):
        offsets = trace[f"{name}_offsets"]
        return trace[name][offsets[i]:offsets[i + 1]]

    answers = []
    for i, (margin, tolerance, expected) in enumerate(trace["scalars"]):
        ends, obstacles = [tuple(e) for e in rows("ends", i)], [tuple(o) for o in rows("obstacles", i)]
        got = keeps_clear(rows("path", i), ends, obstacles, margin, tolerance)
        assert got == bool(expected), f"check {i}"
        answers.append(got)
    assert 0 < sum(answers) < len(answers), "the trace must hold both answers"


def test_the_clearance_check_ignores_an_obstacle_that_holds_the_robot_or_a_waypoint():
    path = np.array([(x, 0.0) for x in np.linspace(0.0, 4.0, 41)])
    in_the_way = (2.0, 0.3, 0.26)
    assert not keeps_clear(path, [(0.0, 0.0), (4.0, 0.0)], [in_the_way], 0.3, 0.01)
    assert keeps_clear(path, [(0.0, 0.0), (2.0, 0.5)], [in_the_way], 0.3, 0.01), "a waypoint inside: not avoided"
    assert keeps_clear(path, [(0.0, 0.0), (4.0, 0.0)], [(2.0, 1.0, 0.26)], 0.3, 0.01)
    assert keeps_clear(path, [(0.0, 0.0)], [], 0.3, 0.01)
    with pytest.raises(ValueError, match="path must be an"):
        keeps_clear(np.zeros(3), [(0.0, 0.0)], [in_the_way], 0.3, 0.01)


@pytest.mark.parametrize("row", [(math.nan, 0.0, 0.26), (1.0, math.inf, 0.26), (1.0, 0.0, -0.1)])
def test_the_compiled_planner_refuses_an_obstacle_its_python_checks_would_have_refused(row):
    """Disc checks its fields in Python; the compiled planner checks the table it is given as well."""
    from nubot_common.kernels import load_kernels

    kernels = load_kernels("nubot_control")
    with pytest.raises(ValueError, match="obstacle 1 must be finite with a radius not negative"):
        kernels.plan((0.0, 0.0), [(3.0, 0.0)], np.array([(1.0, 1.0, 0.26), row]), P, FIELD, (0.0, 0.0), 0.0)


STATES_GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "states.npz"


def _golden_rows(trace, name, i):
    offsets = trace[f"{name}_offsets"]
    return trace[name][offsets[i]:offsets[i + 1]]


def test_the_compiled_trajectory_reads_back_its_golden_states():
    """Calls of ``states_at`` (the MPC's reference over its horizon) and ``state_at`` (where the plan has the robot
    now) recorded from the numpy implementation the compiled one replaced (3 seeded lockstep matches of 30 s,
    by ``nubot_tools.golden``): the same positions and velocities to 1e-12 m and m/s (the same
    arithmetic in the same order; 1e-12 leaves room for a compiler's other rounding)."""
    with np.load(STATES_GOLDEN) as archive:
        trace = dict(archive)
    singles = 0
    for i, single in enumerate(trace["single"]):
        t = _golden_rows(trace, "t", i).reshape(-1)
        tr = _trajectory(t, np.zeros_like(t), _golden_rows(trace, "xy", i), _golden_rows(trace, "v", i), ())
        times = _golden_rows(trace, "times", i).reshape(-1)
        if single:
            xy, v = tr.state_at(float(times[0]))
            xy, v = xy.reshape(1, 2), v.reshape(1, 2)
            singles += 1
        else:
            xy, v = tr.states_at(times)
        np.testing.assert_allclose(xy, _golden_rows(trace, "out_xy", i), rtol=0.0, atol=1e-12, err_msg=f"call {i}")
        np.testing.assert_allclose(v, _golden_rows(trace, "out_v", i), rtol=0.0, atol=1e-12, err_msg=f"call {i}")
    assert 0 < singles < len(trace["single"]), "the trace must hold both kinds of call"


def test_a_trajectory_s_states_keep_the_shape_of_the_times_asked_for_and_refuse_bad_samples():
    tr = plan((0.0, 0.0), [(3.0, 0.0)], [], P, FIELD)
    xy, v = tr.states_at(np.linspace(0.0, 1.0, 6).reshape(2, 3))
    assert xy.shape == v.shape == (2, 3, 2)
    assert tr.states_at(0.2)[0].shape == (2,)
    from nubot_common.kernels import load_kernels

    kernels = load_kernels("nubot_control")
    with pytest.raises(ValueError, match=r"xy must be \(n, 2\) rows for the n = 3 sample times"):
        kernels.trajectory_states(np.zeros(3), np.zeros((2, 2)), np.zeros((3, 2)), np.zeros(1))
    with pytest.raises(ValueError, match="t must be a vector of at least one sample time"):
        kernels.trajectory_states(np.zeros(0), np.zeros((0, 2)), np.zeros((0, 2)), np.zeros(1))


ACCEL_GOLDEN = Path(__file__).resolve().parents[1] / "golden" / "accel.npz"


def test_the_compiled_acceleration_check_gives_its_golden_answers():
    """Whether a new plan can be followed (its velocity changing no faster than the limit over the part that may be
    kept), as the motion layer asked it of plans in 3 seeded lockstep matches of 30 s (by ``nubot_tools.golden``
    before it moved), half followable and half not, recorded from the numpy implementation: the same answer for each."""
    with np.load(ACCEL_GOLDEN) as archive:
        trace = dict(archive)
    answers = []
    for i, (until, accel, expected) in enumerate(trace["scalars"]):
        samples = _golden_rows(trace, "samples", i)
        t = np.ascontiguousarray(samples[:, 0])
        tr = _trajectory(t, np.zeros_like(t), np.zeros((len(t), 2)), np.ascontiguousarray(samples[:, 1:3]), ())
        got = tr.followable(until, accel)
        assert got == bool(expected), f"check {i}"
        answers.append(got)
    assert 0 < sum(answers) < len(answers), "the trace must hold both answers"


def test_a_plan_that_turns_harder_than_the_limit_at_its_start_is_not_followable():
    t = np.array([0.0, 0.1, 0.2, 0.3, 0.9])
    straight = np.array([(1.0, 0.0), (1.2, 0.0), (1.4, 0.0), (1.6, 0.0), (0.0, 5.0)])
    tr = _trajectory(t, np.zeros_like(t), np.zeros((5, 2)), straight, ())
    assert tr.followable(0.25, 2.0 + 1e-12)  # 2 m/s^2 up to the first sample after 0.25 s; the jump later is not read
    assert not tr.followable(0.25, 1.9)
    assert not tr.followable(0.3, 2.0), "the first sample after 0.3 s is the jump's end"
    assert _trajectory(t[:1], t[:1], np.zeros((1, 2)), straight[:1], ()).followable(0.5, 0.1)
