"""Golden traces: what one numeric piece of the robot cycle was given and gave back, recorded over seeded lockstep
matches, kept as test data so that a new implementation of the piece can be held to the old one's answers.

``python -m nubot_tools.golden plan --out FILE`` does the same for the path planner (``path_planning.plan``, as
``MotionController`` calls it): ``--calls`` of its calls drawn with the seeded generator, each with its inputs
(ragged ones flattened, with offsets) and, of the trajectory it gave, the sample count, the route fitted (``via``)
and every ``--every``-th sample's time, arc length, position and velocity (the last sample always).

``python -m nubot_tools.golden clear --out FILE`` records ``path_planning.keeps_clear`` (whether a plan being kept
still keeps the obstacles' clearances) as the motion layer calls it, half of the calls kept clear, half not.

``python -m nubot_tools.golden states --out FILE`` records ``Trajectory.states_at`` (the MPC's reference over its
horizon) and ``Trajectory.state_at`` (where the plan has the robot now) as the motion layer calls them: the
trajectory's samples (t, xy, v), the times asked for and the positions and velocities given.

``python -m nubot_tools.golden accel --out FILE`` records ``MotionController._within_accel`` (whether a new plan can be
followed), half of the calls followable, half not: the plan's first samples (up to three past the part that may be
kept), the limit and the answer.

``python -m nubot_tools.golden table --out FILE`` records ``MotionController._obstacle_table`` (the planner's
obstacles this cycle): the robot, the obstacles it was given ((x, y) or (x, y, keep)), the goals' rows, the
parameters and the table.

``python -m nubot_tools.golden follow --out FILE [--tracker baseline]`` records whole sequences of
``MotionController`` cycles: every ``follow`` (and ``reset``) of ``--trackers`` robots' motion layers in order, with
everything it was given (the robot's pose, the route, the heading, the obstacles, the cycle time, the speed limit,
holding, the areas to keep out of, urgent) and what it gave (the body-frame command, the reference, whether it made a
new plan). A motion layer fed the same sequence from its start must answer the same way, cycle after cycle.

``python -m nubot_tools.golden labels --out FILE`` records ``--calls`` of the world models' ``label_obstacles`` calls
(their inputs and the labelled obstacles they gave).

``python -m nubot_tools.golden mpc --out FILE`` plays ``--seeds`` lockstep matches of the default teams (MPC
tracker) for ``--seconds`` of sim time each and records every ``LaguerreMpc.command`` call: its inputs (position,
previous command, reference, limits), its command and how it was found (``last_status``). Calls are kept per
status, at most ``--per-status`` of each (drawn with the seeded generator), so that the rare ones (the QP solved,
the fallback) are all there beside a sample of the common one. The file is numpy's compressed ``.npz``; its
``params`` entry is the controller's ``MpcParams`` as JSON.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from nubot_tools.workspace import TEAMS


def play(seeds: list[int], seconds: float, tracker: str = "mpc") -> None:
    """Lockstep matches of the default teams with ``tracker`` (the MPC's by default), ``seconds`` of sim time each."""
    from nubot_match.config import match_config
    from nubot_match.engine import LockstepMatch

    for seed in seeds:
        config = match_config(TEAMS / "nubot.yaml", TEAMS / "rival.yaml", "18x12", tracker, half_seconds=600.0,
                              halves=2, seed=seed)
        match = LockstepMatch(config, [])
        match.reset(seed)
        match.run(until=seconds)
        match.close()
        print(f"golden: seed {seed} played ({seconds:.0f} s)", file=sys.stderr)


def record_mpc(seeds: list[int], seconds: float, per_status: int) -> dict[str, np.ndarray]:
    from nubot_control.mpc import LaguerreMpc

    calls: list[tuple[Any, tuple, dict, Any]] = []
    statuses: list[str] = []

    def command(self: Any, *args: Any, **kwargs: Any) -> Any:
        result = original(self, *args, **kwargs)
        calls.append((self, args, kwargs, np.array(result, dtype=float)))
        statuses.append(self.last_status)
        return result

    original = LaguerreMpc.command
    LaguerreMpc.command = command  # type: ignore[assignment]
    try:
        play(seeds, seconds)
    finally:
        LaguerreMpc.command = original  # type: ignore[assignment]
    params = {json.dumps(dataclasses.asdict(mpc.params), sort_keys=True) for mpc, *_ in calls}
    if len(params) != 1:
        raise RuntimeError(f"the robots' controllers differ in their parameters: {sorted(params)}")
    rng = np.random.default_rng(0)
    kept: list[int] = []
    for status in sorted(set(statuses)):
        where = [i for i, s in enumerate(statuses) if s == status]
        chosen = rng.choice(where, size=min(per_status, len(where)), replace=False)
        kept.extend(sorted(int(i) for i in chosen))
        print(f"golden: {status}: {len(where)} calls, {len(chosen)} kept", file=sys.stderr)
    kept.sort()

    def argument(i: int, name: str, position: int, default: Any = None) -> Any:
        _, args, kwargs, _ = calls[i]
        return args[position] if position < len(args) else kwargs.get(name, default)

    names = ("position", "previous", "ref_positions", "ref_velocities")
    trace = {name: np.array([np.asarray(argument(i, name, n), dtype=float) for i in kept])
             for n, name in enumerate(names)}
    def limit(i: int, name: str, position: int) -> float:
        value = argument(i, name, position)
        return math.nan if value is None else float(value)  # NaN: none given (the controller's own)

    limits = {name: np.array([limit(i, name, n) for i in kept]) for n, name in ((4, "max_speed"), (5, "max_accel"))}
    return {**trace, **limits, "command": np.array([calls[i][3] for i in kept]),
            "status": np.array([statuses[i] for i in kept]), "params": np.array(params.pop())}


def _ragged(rows: list[np.ndarray], width: int) -> tuple[np.ndarray, np.ndarray]:
    """Arrays of differing lengths as one (total, width) array and the offsets where each starts (one more: the end)."""
    offsets = np.append(0, np.cumsum([len(r) for r in rows])).astype(np.int64)
    flat = np.concatenate([np.asarray(r, dtype=float).reshape(-1, width) for r in rows]) if rows else \
        np.zeros((0, width))
    return flat, offsets


def record_calls(module: Any, name: str, seeds: list[int], seconds: float,
                 calls: int) -> tuple[list[tuple[tuple, dict, Any]], list[int]]:
    """Every call of the function ``module.name`` (or the method, when ``module`` is a class: ``self`` first) during
    the matches, as (args, kwargs, result), and which ``calls`` of them to keep (drawn with the seeded generator, in
    order)."""
    recorded = record_many(module, [name], seeds, seconds)[name]
    rng = np.random.default_rng(0)
    kept = sorted(int(i) for i in rng.choice(len(recorded), size=min(calls, len(recorded)), replace=False))
    return recorded, kept


def record_many(owner: Any, names: list[str], seeds: list[int],
                seconds: float) -> dict[str, list[tuple[tuple, dict, Any]]]:
    """Every call of each of ``owner``'s functions (or methods) ``names`` during one set of matches."""
    recorded: dict[str, list[tuple[tuple, dict, Any]]] = {name: [] for name in names}
    originals = {name: getattr(owner, name) for name in names}

    def recorder(name: str) -> Callable[..., Any]:
        def recording(*args: Any, **kwargs: Any) -> Any:
            result = originals[name](*args, **kwargs)
            recorded[name].append((args, kwargs, result))
            return result
        return recording

    for name in names:
        setattr(owner, name, recorder(name))
    try:
        play(seeds, seconds)
    finally:
        for name, original in originals.items():
            setattr(owner, name, original)
    return recorded


def record_plan(seeds: list[int], seconds: float, calls: int, every: int) -> dict[str, np.ndarray]:
    from nubot_control import motion

    recorded, kept = record_calls(motion, "plan", seeds, seconds, calls)  # the name MotionController calls
    print(f"golden: {len(recorded)} plans, {len(kept)} kept", file=sys.stderr)
    out: dict[str, list] = {name: [] for name in ("start", "start_velocity", "end_speed", "bounds", "params")}
    waypoints, obstacles, via, samples, picked = [], [], [], [], []
    for i in kept:
        args, kwargs, trajectory = recorded[i]
        start, goals, discs, params, bounds = args
        out["start"].append(start)
        out["start_velocity"].append(kwargs.get("start_velocity", (0.0, 0.0)))
        out["end_speed"].append(kwargs.get("end_speed", 0.0))
        out["bounds"].append((bounds.x_min, bounds.x_max, bounds.y_min, bounds.y_max))
        out["params"].append(json.dumps(dataclasses.asdict(params), sort_keys=True))
        waypoints.append(np.array(goals, dtype=float).reshape(-1, 2))
        obstacles.append(np.array([(d.x, d.y, d.radius) for d in discs], dtype=float).reshape(-1, 3))
        via.append(np.array(trajectory.via, dtype=float).reshape(-1, 2))
        n = len(trajectory.t)
        index: np.ndarray = np.unique(np.append(np.arange(0, n, every), n - 1))
        picked.append(index)
        samples.append(np.column_stack((trajectory.t[index], trajectory.s[index], trajectory.xy[index],
                                        trajectory.v[index])))
    trace = {name: np.array(values) for name, values in out.items()}
    for name, rows, width in (("waypoints", waypoints, 2), ("obstacles", obstacles, 3), ("via", via, 2),
                              ("samples", samples, 6), ("sample_index", picked, 1)):
        trace[name], trace[f"{name}_offsets"] = _ragged(rows, width)
    trace["sample_count"] = np.array([len(recorded[i][2].t) for i in kept])
    return trace


def record_clear(seeds: list[int], seconds: float, calls: int) -> dict[str, np.ndarray]:
    """``path_planning.keeps_clear`` as ``MotionController`` calls it to decide whether a plan still holds: up to
    ``--calls`` / 2 calls of each answer (drawn with the seeded generator), each with the path, the ends, the
    obstacles, the margin and tolerance, and the answer."""
    from nubot_control import motion

    recorded, _ = record_calls(motion, "keeps_clear", seeds, seconds, 0)
    kept = _halves(recorded, bool, calls)
    print(f"golden: {len(recorded)} checks ({sum(r for _, _, r in recorded)} clear), {len(kept)} kept",
          file=sys.stderr)
    paths, ends, obstacles, scalars = [], [], [], []
    for i in kept:
        (path, points, table, margin, tolerance), _, result = recorded[i]
        paths.append(np.asarray(path, dtype=float).reshape(-1, 2))
        ends.append(np.array(points, dtype=float).reshape(-1, 2))
        obstacles.append(np.array(table, dtype=float).reshape(-1, 3))
        scalars.append((margin, tolerance, float(result)))
    trace = {"scalars": np.array(scalars).reshape(-1, 3)}
    for name, rows, width in (("path", paths, 2), ("ends", ends, 2), ("obstacles", obstacles, 3)):
        trace[name], trace[f"{name}_offsets"] = _ragged(rows, width)
    return trace


def _halves(recorded: list[tuple[tuple, dict, Any]], answer: Callable[[Any], bool], calls: int) -> list[int]:
    """Up to ``calls`` / 2 of the calls whose result gives each answer, drawn with the seeded generator, in order."""
    rng = np.random.default_rng(0)
    kept: list[int] = []
    for wanted in (True, False):
        which = [i for i, (_, _, result) in enumerate(recorded) if answer(result) is wanted]
        kept += [int(i) for i in rng.choice(which, size=min(calls // 2, len(which)), replace=False)]
    return sorted(kept)


def record_states(seeds: list[int], seconds: float, calls: int) -> dict[str, np.ndarray]:
    """``Trajectory.states_at`` and ``Trajectory.state_at`` as the motion layer calls them: ``--calls`` / 2 of each
    (drawn with the seeded generator), each with the trajectory's samples, the times and the states given."""
    from nubot_control.path_planning import Trajectory

    rows: dict[str, list[np.ndarray]] = {"t": [], "xy": [], "v": [], "times": [], "out_xy": [], "out_v": []}
    single: list[float] = []
    rng = np.random.default_rng(0)
    for name, recorded in record_many(Trajectory, ["states_at", "state_at"], seeds, seconds).items():
        kept = sorted(int(i) for i in rng.choice(len(recorded), size=min(calls // 2, len(recorded)), replace=False))
        print(f"golden: {len(recorded)} {name} calls, {len(kept)} kept", file=sys.stderr)
        for i in kept:
            (trajectory, times), _, (xy, v) = recorded[i]
            for key, value in (("t", trajectory.t), ("xy", trajectory.xy), ("v", trajectory.v),
                               ("times", np.atleast_1d(np.asarray(times, dtype=float))),
                               ("out_xy", np.asarray(xy).reshape(-1, 2)), ("out_v", np.asarray(v).reshape(-1, 2))):
                rows[key].append(np.asarray(value, dtype=float))
            single.append(float(name == "state_at"))
    trace = {"single": np.array(single)}
    for key, width in (("t", 1), ("xy", 2), ("v", 2), ("times", 1), ("out_xy", 2), ("out_v", 2)):
        trace[key], trace[f"{key}_offsets"] = _ragged(rows[key], width)
    return trace


def record_accel(seeds: list[int], seconds: float, calls: int) -> dict[str, np.ndarray]:
    """``MotionController._within_accel`` on new plans: up to ``--calls`` / 2 of each answer, each with the plan's
    samples up to three past the first after ``keep_plan_time`` (all the check reads), the limit and the answer."""
    from nubot_control.motion import MotionController

    recorded, _ = record_calls(MotionController, "_within_accel", seeds, seconds, 0)
    kept = _halves(recorded, bool, calls)
    print(f"golden: {len(recorded)} acceleration checks ({sum(bool(r) for *_, r in recorded)} followable), "
          f"{len(kept)} kept", file=sys.stderr)
    samples, scalars = [], []
    for i in kept:
        (motion, trajectory, accel), _, result = recorded[i]
        until = motion.params.keep_plan_time
        end = int(np.searchsorted(trajectory.t, until, side="right")) + 4
        samples.append(np.column_stack((trajectory.t[:end], trajectory.v[:end])))
        scalars.append((until, accel, float(result)))
    trace = {"scalars": np.array(scalars).reshape(-1, 3)}
    trace["samples"], trace["samples_offsets"] = _ragged(samples, 3)
    return trace


def record_table(seeds: list[int], seconds: float, calls: int) -> dict[str, np.ndarray]:
    """``MotionController._obstacle_table``: ``--calls`` of its calls (drawn with the seeded generator), each with the
    robot's position, its obstacles as (x, y, keep, kept) rows (kept 0: a robot's (x, y)), the goals' rows, the
    robot radius, clearance and planning range, and the table given."""
    from nubot_control.motion import MotionController

    recorded, kept = record_calls(MotionController, "_obstacle_table", seeds, seconds, calls)
    print(f"golden: {len(recorded)} obstacle tables, {len(kept)} kept", file=sys.stderr)
    given, goals, tables, scalars = [], [], [], []
    for i in kept:
        (motion, me, obstacles), _, table = recorded[i]
        given.append(np.array([(o[0], o[1], o[2], 1.0) if len(o) > 2 else (o[0], o[1], 0.0, 0.0)
                               for o in obstacles], dtype=float).reshape(-1, 4))
        goals.append(np.array(motion.goal_table, dtype=float).reshape(-1, 3))
        tables.append(np.array(table, dtype=float).reshape(-1, 3))
        scalars.append((me.x, me.y, motion.robot_radius, motion.params.clearance, motion.params.planning_range))
    trace = {"scalars": np.array(scalars).reshape(-1, 5)}
    for name, rows, width in (("obstacles", given, 4), ("goals", goals, 3), ("table", tables, 3)):
        trace[name], trace[f"{name}_offsets"] = _ragged(rows, width)
    return trace


def record_obstacles(seeds: list[int], seconds: float, trackers: int) -> dict[str, np.ndarray]:
    """Every call of ``--trackers`` robots' ``ObstacleTracker`` (drawn with the seeded generator), in order: an
    update's frame time and percepts (kind 0), an estimate's time and its tracks, positions and velocities (kind 1)."""
    from world_model.obstacles import ObstacleTracker

    calls: dict[int, list[tuple[int, float, np.ndarray]]] = {}
    made: list[Any] = []
    update, estimate = ObstacleTracker.update, ObstacleTracker.estimate

    def recorded_update(self: Any, stamp: float, percepts: Any) -> None:
        if id(self) not in calls:
            calls[id(self)] = []
            made.append(self)  # kept alive: ids stay unique
        calls[id(self)].append((0, float(stamp), np.array(percepts, dtype=float).reshape(-1, 2)))
        update(self, stamp, percepts)

    def recorded_estimate(self: Any, t: float) -> Any:
        result = estimate(self, t)
        positions, velocities = result
        calls.setdefault(id(self), []).append(
            (1, float(t), np.column_stack((np.array(positions, dtype=float).reshape(-1, 2),
                                           np.array(velocities, dtype=float).reshape(-1, 2)))))
        return result

    ObstacleTracker.update, ObstacleTracker.estimate = recorded_update, recorded_estimate  # type: ignore[assignment]
    try:
        play(seeds, seconds)
    finally:
        ObstacleTracker.update, ObstacleTracker.estimate = update, estimate  # type: ignore[assignment]
    rng = np.random.default_rng(0)
    chosen = sorted(int(i) for i in rng.choice(len(made), size=min(trackers, len(made)), replace=False))
    kinds, times, which = [], [], []
    percepts: list[np.ndarray] = []  # the updates' percepts, in order
    tracks: list[np.ndarray] = []  # the estimates' tracks (x, y, vx, vy), in order
    for n, i in enumerate(chosen):
        estimates = 0
        for kind, t, data in calls[id(made[i])]:
            if kind:  # an estimate changes nothing: every fourth is enough to hold a new tracker to
                estimates += 1
                if estimates % 4:
                    continue
            kinds.append(kind)
            times.append(t)
            which.append(n)
            (tracks if kind else percepts).append(data)
    print(f"golden: {len(made)} trackers, {len(chosen)} kept, {len(kinds)} calls", file=sys.stderr)
    trace = {"tracker": np.array(which), "kind": np.array(kinds), "time": np.array(times)}
    trace["percepts"], trace["percepts_offsets"] = _ragged(percepts, 2)
    trace["tracks"], trace["tracks_offsets"] = _ragged(tracks, 4)
    return trace


def record_follow(seeds: list[int], seconds: float, trackers: int, tracker: str = "mpc") -> dict[str, np.ndarray]:
    """Every ``follow`` and ``reset`` of ``trackers`` robots' ``MotionController`` in order (kind 0 a cycle with its
    inputs and answers, kind 1 a reset): a robot that stepped urgently, one reset and one that held the ball if the
    matches have them, the rest drawn with the seeded generator."""
    from nubot_common.world_description import WorldDescription
    from nubot_control.motion import MotionController

    calls: dict[int, list[tuple]] = {}
    made: list[Any] = []
    follow, reset = MotionController.follow, MotionController.reset

    def note(self: Any, entry: tuple) -> None:
        if id(self) not in calls:
            calls[id(self)] = []
            made.append(self)  # kept alive: ids stay unique
        calls[id(self)].append(entry)

    def recorded_follow(self: Any, me: Any, waypoints: Any, heading: float, obstacles: Any, dt: float,
                        speed_limit: float | None = None, holding: bool = False, no_go: Any = (),
                        urgent: bool = False) -> Any:
        before = self.trajectory
        command = follow(self, me, waypoints, heading, obstacles, dt, speed_limit, holding, no_go, urgent)
        reference = self.reference
        note(self, (0, (me.x, me.y, me.theta), np.array(waypoints, dtype=float).reshape(-1, 2), float(heading),
                    np.array([(o[0], o[1], o[2], 1.0) if len(o) > 2 else (o[0], o[1], 0.0, 0.0) for o in obstacles],
                             dtype=float).reshape(-1, 4),
                    float(dt), math.nan if speed_limit is None else float(speed_limit), float(holding),
                    np.array(no_go, dtype=float).reshape(-1, 4), float(urgent), tuple(float(c) for c in command),
                    (*reference[0], *reference[1]) if reference is not None else (math.nan,) * 4,
                    float(self.trajectory is not None and self.trajectory is not before)))
        return command

    def recorded_reset(self: Any) -> None:
        note(self, (1,))
        reset(self)

    MotionController.follow, MotionController.reset = recorded_follow, recorded_reset  # type: ignore[assignment]
    try:
        play(seeds, seconds, tracker)
    finally:
        MotionController.follow, MotionController.reset = follow, reset  # type: ignore[assignment]
    world = WorldDescription()
    rng = np.random.default_rng(0)
    order = [int(i) for i in rng.permutation(len(made))]
    # the rare ways through a cycle first: the first robot (in the drawn order) that stepped urgently, one reset, one
    # that held the ball; then the others in the drawn order
    wanted = [lambda e: e[0] == 0 and e[9] > 0.0, lambda e: e[0] == 1, lambda e: e[0] == 0 and e[7] > 0.0]
    chosen_set: list[int] = []
    for rare in wanted:
        for i in order:
            if i not in chosen_set and any(rare(e) for e in calls[id(made[i])]):
                chosen_set.append(i)
                break
    chosen_set += [i for i in order if i not in chosen_set]
    chosen = sorted(chosen_set[:trackers])
    params, dts = [], []
    which: list[int] = []
    kinds: list[int] = []
    scalars: list[tuple[float, ...]] = []
    answers: list[tuple[float, ...]] = []
    rows: dict[str, list[np.ndarray]] = {"waypoints": [], "obstacles": [], "no_go": []}
    for n, i in enumerate(chosen):
        motion = made[i]
        if motion.field != world.field or motion.robot_radius != world.robot.radius:
            raise RuntimeError("the matches' world is not the default one the trace is replayed in")
        params.append(json.dumps(dataclasses.asdict(motion.params), sort_keys=True))
        dts.append(motion.mpc.params.dt if motion.mpc is not None else math.nan)
        for entry in calls[id(motion)]:
            which.append(n)
            kinds.append(entry[0])
            if entry[0]:
                scalars.append((math.nan,) * 9)
                answers.append((math.nan,) * 8)
                for name, width in (("waypoints", 2), ("obstacles", 4), ("no_go", 4)):
                    rows[name].append(np.zeros((0, width)))
                continue
            _, me, waypoints, heading, obstacles, dt, limit, holding, no_go, urgent, command, reference, new = entry
            scalars.append((*me, heading, dt, limit, holding, urgent, 0.0))
            answers.append((*command, *reference, new))
            rows["waypoints"].append(waypoints)
            rows["obstacles"].append(obstacles)
            rows["no_go"].append(no_go)
    print(f"golden: {len(made)} motion layers, {len(chosen)} kept, {len(kinds)} calls", file=sys.stderr)
    trace = {"params": np.array(params), "dt": np.array(dts), "tracker": np.array(which), "kind": np.array(kinds),
             "scalars": np.array(scalars).reshape(-1, 9), "answers": np.array(answers).reshape(-1, 8)}
    for name, width in (("waypoints", 2), ("obstacles", 4), ("no_go", 4)):
        trace[name], trace[f"{name}_offsets"] = _ragged(rows[name], width)
    return trace


def record_labels(seeds: list[int], seconds: float, calls: int) -> dict[str, np.ndarray]:
    """``--calls`` of the world models' ``label_obstacles`` calls (drawn with the seeded generator): this robot's pose
    and AgentID, its own obstacles and their velocities, the teammates' reported obstacles (observer, x, y) and
    positions (AgentID, x, y), the two radii, and the labelled obstacles it gave (x, y, teammate or not, the teammate,
    observer, angle, radius, vx, vy)."""
    from nubot_common.world_state import ObstacleLabel
    from world_model import world_model

    # the name WorldModel.snapshot calls
    recorded, kept = record_calls(world_model, "label_obstacles", seeds, seconds, calls)
    print(f"golden: {len(recorded)} labellings, {len(kept)} kept", file=sys.stderr)
    me, agent, radii = [], [], []
    own, velocities, reported, mates, labelled = [], [], [], [], []
    for i in kept:
        (pose, agent_id, own_points, by_observer, mate_points, teammate_radius, merge_radius, speeds), _, result = \
            recorded[i]
        me.append((pose.x, pose.y, pose.theta))
        agent.append(agent_id)
        radii.append((teammate_radius, merge_radius))
        own.append(np.array(own_points, dtype=float).reshape(-1, 2))
        velocities.append(np.array(speeds, dtype=float).reshape(-1, 2))
        reported.append(np.array([(o, *p) for o in by_observer for p in by_observer[o]], dtype=float).reshape(-1, 3))
        mates.append(np.array([(a, *p) for a, p in mate_points.items()], dtype=float).reshape(-1, 3))
        labelled.append(np.array([(o.x, o.y, o.label is ObstacleLabel.TEAMMATE, o.teammate_id, o.observer_id, o.angle,
                                   o.radius, o.vx, o.vy) for o in result], dtype=float).reshape(-1, 9))
    trace = {"me": np.array(me), "agent_id": np.array(agent), "radii": np.array(radii)}
    for name, rows, width in (("own", own, 2), ("velocities", velocities, 2), ("reported", reported, 3),
                              ("mates", mates, 3), ("labelled", labelled, 9)):
        trace[name], trace[f"{name}_offsets"] = _ragged(rows, width)
    return trace


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("piece", choices=("mpc", "plan", "obstacles", "labels", "clear", "states", "accel", "table",
                                           "follow"))
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--seeds", type=int, default=3, help="matches, seeds 0 .. N-1")
    ap.add_argument("--seconds", type=float, default=60.0, help="sim time per match [s]")
    ap.add_argument("--per-status", type=int, default=500, help="mpc: calls kept of each way a command was found")
    ap.add_argument("--calls", type=int, default=600, help="plan, labels, clear, states, accel, table: calls kept")
    ap.add_argument("--every", type=int, default=8, help="plan: every n-th sample of a trajectory kept")
    ap.add_argument("--tracker", choices=("mpc", "baseline"), default="mpc",
                    help="follow: the robots' tracker in the matches played")
    ap.add_argument("--trackers", type=int, default=3,
                    help="obstacles, follow: robots whose obstacle tracker or motion layer is kept")
    args = ap.parse_args(argv)
    if args.seeds < 1 or not args.seconds > 0 or args.per_status < 1 or args.calls < 1 or args.every < 1:
        ap.error("--seeds, --seconds, --per-status, --calls and --every must be positive")
    seeds = list(range(args.seeds))
    if args.piece == "mpc":
        trace = record_mpc(seeds, args.seconds, args.per_status)
    elif args.piece == "plan":
        trace = record_plan(seeds, args.seconds, args.calls, args.every)
    elif args.piece == "labels":
        trace = record_labels(seeds, args.seconds, args.calls)
    elif args.piece == "clear":
        trace = record_clear(seeds, args.seconds, args.calls)
    elif args.piece == "states":
        trace = record_states(seeds, args.seconds, args.calls)
    elif args.piece == "accel":
        trace = record_accel(seeds, args.seconds, args.calls)
    elif args.piece == "table":
        trace = record_table(seeds, args.seconds, args.calls)
    elif args.piece == "follow":
        trace = record_follow(seeds, args.seconds, args.trackers, args.tracker)
    else:
        trace = record_obstacles(seeds, args.seconds, args.trackers)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **trace)
    print(f"golden: {args.piece} trace written to {args.out} ({args.out.stat().st_size // 1024} KiB)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
