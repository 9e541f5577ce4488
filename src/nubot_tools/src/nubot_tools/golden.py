"""Golden traces: what one numeric piece of the robot cycle was given and gave back, recorded over seeded lockstep
matches, kept as test data so that a new implementation of the piece can be held to the old one's answers.

Each piece was recorded from its Python implementation before it moved to C++; the recorders of pieces that now run
inside a compiled one (the MPC's commands, the planner's plans, the kept plan's clearance check, reading a plan back,
the acceleration check and the obstacle table, all inside the motion layer's compiled cycle) went with them, their
traces stay in ``nubot_control/test/golden/`` (``mpc``, ``plan``, ``clear``, ``states``, ``accel``, ``table``) and the
unit tests hold the compiled pieces to them; so does the simulator's base model (``limit_drive``, now inside the
compiled physics world's ``drive_robots``; ``sim_visual/test/golden/drive.npz``) and its stuck detection (also
inside ``drive_robots``; ``stuck.npz``: every update over 20 s of seed 0 and 20 s of robots pushed into the goal, a
wall and each other) and its ball handler (``grip_holds``, ``dribble_condition``, ``held_ball_position`` and
``held_ball_velocity``, now under the physics world's ``grip_slips``, ``first_capture`` and ``carry_ball``;
``ball_handler.npz``). What can still be recorded:

``python -m nubot_tools.golden follow --out FILE [--tracker baseline]`` records whole sequences of
``MotionController`` cycles: every ``follow`` (and ``reset``) of ``--trackers`` robots' motion layers in order, with
everything it was given (the robot's pose, the route, the heading, the obstacles, the cycle time, the speed limit,
holding, the areas to keep out of, urgent) and what it gave (the body-frame command, the reference, whether it made a
new plan). A motion layer fed the same sequence from its start must answer the same way, cycle after cycle.

``python -m nubot_tools.golden world --out FILE`` records whole sequences of ``WorldModel`` calls: every input
(``on_vision``, ``on_front_ball``, ``on_ball3d``, ``on_teammate``, ``on_teammate_strategy``, ``on_coach``,
``on_strategy``) and every read (``snapshot``, ``own_view``) of ``--trackers`` robots' world models in order, with its
arguments and what it gave, as JSON lines (xz): each a tagged tree (``encode``). A world model fed the same inputs from
its start must read the same.

``python -m nubot_tools.golden physics --out FILE`` records every change of the simulator's ``PhysicsWorld`` in order
(robots added and removed, states set, robots driven, the ball set and its holder, each step with the robots that
touched the ball) and after every step every body as ODE holds it (``record_physics``). A world fed the same changes
from its start must step the same way.

``python -m nubot_tools.golden sensing --out FILE`` records every omni-vision frame the simulator made
(``record_sensing``): what it was given, the normal numbers it drew and what it gave.

``python -m nubot_tools.golden obstacles --out FILE`` records every call of ``--trackers`` robots' obstacle trackers
(``ObstacleTracker.update`` and ``estimate``), in order.

``python -m nubot_tools.golden cameras --out FILE`` records the front cameras' cylinders and the RGB-D cameras' ray
casts while every robot's cameras render the match a few times a second, then over seeded scenes that show what the
matches do not (tops seen from above; ``record_cameras``). ``sim_visual/test/golden/cameras.npz`` was recorded so
from the Python implementation (numpy), which the compiled ``paint_cylinder`` and ``RgbdRayCaster``
(``sim_visual/cpp/cameras.cpp``) replaced; the recorder now records those through the same methods.

The file is numpy's compressed ``.npz`` (``world``: JSON lines, xz-compressed).
"""

from __future__ import annotations

import argparse
import dataclasses
import enum
import hashlib
import json
import lzma
import math
import sys
from collections.abc import Callable
from pathlib import Path
from typing import Any

import numpy as np

from nubot_common.field import FieldGeometry
from nubot_common.kinect_mount import CameraMount
from nubot_common.world_description import BallBody, RobotBody, WorldDescription
from nubot_control.motion import MotionController
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_tools.workspace import TEAMS
from sim_visual import simulator
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.params import PhysicsParams, SensorParams
from sim_visual.rgbd_camera import BALL, RgbdCameraRenderer
from sim_visual.world import BallState, PhysicsWorld, RobotState
from world_model.obstacles import ObstacleTracker
from world_model.world_model import WorldModel


def play(seeds: list[int], seconds: float, tracker: str = "mpc") -> None:
    """Lockstep matches of the default teams with ``tracker`` (the MPC's by default), ``seconds`` of sim time each."""
    for seed in seeds:
        config = match_config(TEAMS / "nubot.yaml", TEAMS / "rival.yaml", "18x12", tracker, half_seconds=600.0,
                              halves=2, seed=seed)
        match = LockstepMatch(config, [])
        match.reset(seed)
        match.run(until=seconds)
        match.close()
        print(f"golden: seed {seed} played ({seconds:.0f} s)", file=sys.stderr)


def _ragged(rows: list[np.ndarray], width: int) -> tuple[np.ndarray, np.ndarray]:
    """Arrays of differing lengths as one (total, width) array and the offsets where each starts (one more: the end)."""
    offsets = np.append(0, np.cumsum([len(r) for r in rows])).astype(np.int64)
    flat = np.concatenate([np.asarray(r, dtype=float).reshape(-1, width) for r in rows]) if rows else \
        np.zeros((0, width))
    return flat, offsets


def play_wrapped(owner: Any, wrappers: dict[str, Callable[..., Any]], seeds: list[int], seconds: float) -> None:
    """Play the matches with ``owner``'s attributes replaced by ``wrappers``, then put the originals back."""
    originals = {name: getattr(owner, name) for name in wrappers}
    for name, wrapper in wrappers.items():
        setattr(owner, name, wrapper)
    try:
        play(seeds, seconds)
    finally:
        for name, original in originals.items():
            setattr(owner, name, original)


def record_obstacles(seeds: list[int], seconds: float, trackers: int) -> dict[str, np.ndarray]:
    """Every call of ``--trackers`` robots' ``ObstacleTracker`` (drawn with the seeded generator), in order: an
    update's frame time and percepts (kind 0), an estimate's time and its tracks, positions and velocities (kind 1)."""
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


WORLD_CALLS = ("on_vision", "on_front_ball", "on_ball3d", "on_teammate", "on_teammate_strategy", "on_coach",
               "on_strategy", "snapshot", "own_view")


# Rows of a physics trace: (world, op, robot) with 13 numbers; op codes and what the numbers hold.
PHYSICS_OPS = {"add": 0, "remove": 1, "set_robot": 2, "drive": 3, "set_ball": 4, "holder": 5, "step": 6, "robot": 7,
               "ball": 8}


def record_physics(seeds: list[int], seconds: float) -> dict[str, np.ndarray]:
    """Every change of the simulator's ``PhysicsWorld`` in the matches, in order, and after every step every body's
    position, orientation (w, x, y, z) and velocities: a row (world, op, robot) with 13 numbers each. ``add``: x, y,
    theta; ``set_robot``: the six state numbers; ``drive``: vx, vy, w, world frame (1 or 0); ``set_ball``: the nine;
    ``holder``: the robot whose ball contacts are ignored (-1 none); ``step``: dt, and in the robot column the touched
    robots as a bit mask; ``robot`` / ``ball``: the body after the step. Robots are numbered in the order a world
    added them. The worlds were built with the default field, physics, robot and ball (checked)."""
    rows: list[tuple[int, int, int, list[float]]] = []
    ids: dict[int, int] = {}
    names: dict[int, list[str]] = {}
    original = {n: getattr(PhysicsWorld, n) for n in ("__init__", "add_robot", "remove_robot", "set_robot_state",
                                                     "drive_robot", "drive_robots", "advance", "set_ball_state",
                                                     "set_ball_collides_with", "step")}

    def world_of(self: Any) -> int:
        return ids[id(self)]

    def robot_of(self: Any, name: str | None) -> int:
        return -1 if name is None else names[world_of(self)].index(name)

    def add(op: str, self: Any, robot: int, values: list[float]) -> None:
        rows.append((world_of(self), PHYSICS_OPS[op], robot, [float(v) for v in values] + [0.0] * (13 - len(values))))

    def init(self: Any, field: Any, physics: Any, robot: Any, ball: Any) -> None:
        if (field, physics, robot, ball) != (FieldGeometry(), PhysicsParams(), RobotBody(), BallBody()):
            raise RuntimeError("golden physics: the matches must use the default field, physics, robot and ball")
        ids[id(self)] = len(ids)
        names[ids[id(self)]] = []
        original["__init__"](self, field, physics, robot, ball)

    def add_robot(self: Any, name: str, x: float, y: float, theta: float) -> None:
        names[world_of(self)].append(name)
        add("add", self, robot_of(self, name), [x, y, theta])
        original["add_robot"](self, name, x, y, theta)

    def remove_robot(self: Any, name: str) -> None:
        add("remove", self, robot_of(self, name), [])
        original["remove_robot"](self, name)

    def set_robot_state(self: Any, name: str, state: Any) -> None:
        add("set_robot", self, robot_of(self, name), list(dataclasses.astuple(state)))
        original["set_robot_state"](self, name, state)

    def drive_robot(self: Any, name: str, vx: float, vy: float, w: float, world_frame: bool = False) -> None:
        add("drive", self, robot_of(self, name), [vx, vy, w, float(world_frame)])
        original["drive_robot"](self, name, vx, vy, w, world_frame)

    def drive_robots(self: Any, dt: float, *args: Any) -> None:
        original["drive_robots"](self, dt, *args)
        for name in self.robot_names:  # as driving each robot in the world frame
            add("drive", self, robot_of(self, name), [*self.base_drive(name), 1.0])

    def set_ball_state(self: Any, state: Any) -> None:
        add("set_ball", self, -1, list(dataclasses.astuple(state)))
        original["set_ball_state"](self, state)

    def set_ball_collides_with(self: Any, name: str | None) -> None:
        add("holder", self, robot_of(self, name), [])
        original["set_ball_collides_with"](self, name)

    def step(self: Any, dt: float) -> set[str]:
        touched = original["step"](self, dt)
        mask = sum(1 << robot_of(self, n) for n in touched)
        add("step", self, mask, [dt])
        bodies = self.bodies()
        for name in self.robot_names:
            add("robot", self, robot_of(self, name), list(bodies[name]))
        add("ball", self, -1, list(bodies[None]))
        return touched

    def advance(self: Any, dt: float, time: float, steps: int,
                holder: str | None) -> tuple[set[str], bool, str | None] | None:
        # The compiled advance is these calls in this order (test_physics_golden): made one by one, recorded.
        drive_robots(self, dt, time, steps, *self.drive_params)
        slipped = holder is not None and self.grip_slips(holder, dt, time)
        if slipped:
            holder = None
        set_ball_collides_with(self, holder)
        touched = step(self, dt)
        captured = self.first_capture((steps + 1) * dt) if holder is None else None
        holder = captured if holder is None else holder
        if holder is not None:
            self.carry_ball(holder)
            add("set_ball", self, -1, list(self._core.ball_state()))
        if not touched and not slipped and captured is None and abs(self.ball_x()) < self.field.half_length:
            return None
        return touched, slipped, captured

    wrappers: dict[str, Callable[..., Any]] = {
        "advance": advance,
        "__init__": init, "add_robot": add_robot, "remove_robot": remove_robot, "set_robot_state": set_robot_state,
        "drive_robot": drive_robot, "drive_robots": drive_robots, "set_ball_state": set_ball_state,
        "set_ball_collides_with": set_ball_collides_with, "step": step}
    play_wrapped(PhysicsWorld, wrappers, seeds, seconds)
    return {"index": np.array([r[:3] for r in rows], dtype=np.int64),
            "values": np.array([r[3] for r in rows], dtype=float)}


def encode(value: Any) -> Any:
    """A tagged JSON tree of ``value``: a record (dataclass, named tuple) as {"_": its class, "f": its fields in
    order}, an enum member as {"_e": its class, "v": its value}, a tuple as {"_t": its items}."""
    if isinstance(value, enum.Enum):
        return {"_e": type(value).__name__, "v": value.value}
    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        return {"_": type(value).__name__, "f": [encode(getattr(value, f.name)) for f in dataclasses.fields(value)]}
    if isinstance(value, tuple) and hasattr(value, "_fields"):
        return {"_": type(value).__name__, "f": [encode(v) for v in value]}
    if isinstance(value, tuple):
        return {"_t": [encode(v) for v in value]}
    if isinstance(value, list):
        return [encode(v) for v in value]
    if isinstance(value, dict):
        return {"_d": [[encode(k), encode(v)] for k, v in value.items()]}
    if isinstance(value, (bool, int, float, str)) or value is None:
        return value
    if isinstance(value, bytes):
        return {"_b": value.decode("latin-1")}
    raise TypeError(f"golden: cannot record a {type(value).__name__}")


def _rounded(tree: Any) -> Any:
    """``tree`` with its floats to 12 significant digits."""
    if isinstance(tree, float):
        return float(f"{tree:.12g}")
    if isinstance(tree, list):
        return [_rounded(v) for v in tree]
    if isinstance(tree, dict):
        return {k: _rounded(v) for k, v in tree.items()}
    return tree


def record_world(seeds: list[int], seconds: float, trackers: int) -> list[dict]:
    """Every call of ``trackers`` robots' ``WorldModel`` (a goalie, whose RGB-D cameras see the ball in 3-D, first if
    there is one, then its teammates; the rest drawn with the seeded generator), in order: first the records given as
    arguments, each once ({"object": key, "value"}), then the calls ({"robot", "call", "args", "result"}, an argument
    {"@": key} one of those records); of the reads (``snapshot``, ``own_view``) every other result is kept (None: not
    kept), to 12 significant digits."""
    calls: dict[int, list[dict]] = {}
    made: list[Any] = []
    originals = {name: getattr(WorldModel, name) for name in WORLD_CALLS}

    shared: dict[int, tuple[Any, Any]] = {}  # the records given to several world models (a relayed packet): by id

    def argument(value: Any) -> Any:
        if isinstance(value, (bool, int, float, str, bytes)) or value is None:
            return encode(value)
        if id(value) not in shared:
            shared[id(value)] = (value, encode(value))  # kept alive: ids stay unique
        return {"@": id(value)}

    def recorder(name: str) -> Callable[..., Any]:
        def recording(self: Any, *args: Any) -> Any:
            result = originals[name](self, *args)
            if id(self) not in calls:
                calls[id(self)] = []
                made.append(self)  # kept alive: ids stay unique
            calls[id(self)].append({"call": name, "args": [argument(a) for a in args], "result": encode(result)})
            return result
        return recording

    play_wrapped(WorldModel, {name: recorder(name) for name in WORLD_CALLS}, seeds, seconds)
    rng = np.random.default_rng(0)
    order = [int(i) for i in rng.permutation(len(made))]
    goalies = [i for i in order if any(c["call"] == "on_ball3d" for c in calls[id(made[i])])]
    first = goalies[:1] or order[:1]
    # the first one's teammates next: they are given the same packets, kept once
    heard = _packets(calls[id(made[first[0]])])
    team = [i for i in order if i not in first and _packets(calls[id(made[i])]) & heard]
    chosen = (first + team + [i for i in order if i not in first and i not in team])[:trackers]
    records: list[dict] = []
    used: set[int] = set()
    for n, i in enumerate(sorted(chosen)):
        model = made[i]
        records.append({"robot": n, "call": "__init__", "args": encode([model.params, model.agent_id, model.world]),
                        "result": None})
        reads = {"snapshot": 0, "own_view": 0}
        for c in calls[id(model)]:
            if c["call"] in reads:  # what a world model reads out: every other one is kept, its numbers to 12
                reads[c["call"]] += 1  # digits (a test compares them to 1e-9); every input is kept exactly
                c = {**c, "result": _rounded(c["result"]) if reads[c["call"]] % 2 else None}
            used.update(a["@"] for a in c["args"] if isinstance(a, dict) and "@" in a)
            records.append({"robot": n, **c})
    objects = [{"object": key, "value": shared[key][1]} for key in sorted(used)]
    print(f"golden: {len(made)} world models, {len(chosen)} kept, {len(records)} calls, {len(objects)} records "
          "given", file=sys.stderr)
    return objects + records


def _packets(calls: list[dict]) -> set[int]:
    """The keys of the teammates' packets a world model was given."""
    return {c["args"][1]["@"] for c in calls if c["call"] == "on_teammate"}


def record_sensing(seeds: list[int], seconds: float) -> dict[str, np.ndarray]:
    """Every omni-vision frame the simulator made in the matches (``sensing.observe``), in order: what it was given
    (``frame``: stamp, the robot's six state numbers, its team's attack, AgentID, the four flags, the ball's x, y, vx,
    vy, the five noise parameters; ``others``: each other robot's six numbers) and the normal numbers it drew
    (``normals``), and what it gave (``robot``: pose x, y, theta, vx, vy, w; ``ball``: seen, x, y, vx, vy;
    ``obstacles``: x, y each). Ragged parts come with their ``_offsets``."""
    frames: list[list[float]] = []
    others: list[np.ndarray] = []
    normals: list[np.ndarray] = []
    robots: list[list[float]] = []
    balls: list[list[float]] = []
    obstacles: list[np.ndarray] = []
    original = simulator.observe

    def observe(stamp: float, me: Any, frame: Any, agent_id: int, flags: Any, ball: Any, rest: list, noise: Any,
                rng: np.random.Generator) -> Any:
        state = rng.bit_generator.state
        view = original(stamp, me, frame, agent_id, flags, ball, rest, noise, rng)
        replay = np.random.Generator(type(rng.bit_generator)())
        replay.bit_generator.state = state
        drawn = 6 + 4 * ((view.ball is not None) + len(view.obstacles))
        normals.append(replay.normal(0.0, 1.0, size=drawn))
        if replay.bit_generator.state != rng.bit_generator.state:
            raise RuntimeError("golden sensing: the frame drew other numbers than 6 + 4 per object seen")
        frames.append([stamp, *dataclasses.astuple(me), frame.attack, agent_id, *map(float, dataclasses.astuple(flags)),
                       ball.x, ball.y, ball.vx, ball.vy, *dataclasses.astuple(noise)])
        others.append(np.array([dataclasses.astuple(r) for r in rest], dtype=float).reshape(-1, 6))
        r = view.robot
        robots.append([r.pose.x, r.pose.y, r.pose.theta, r.vx, r.vy, r.w])
        b = view.ball
        balls.append([1.0, b.x, b.y, b.vx, b.vy] if b is not None else [0.0] * 5)
        obstacles.append(np.array(view.obstacles, dtype=float).reshape(-1, 2))
        return view

    play_wrapped(simulator, {"observe": observe}, seeds, seconds)
    trace = {"frame": np.array(frames), "robot": np.array(robots), "ball": np.array(balls)}
    trace["others"], trace["others_offsets"] = _ragged(others, 6)
    trace["normals"], trace["normals_offsets"] = _ragged([n.reshape(-1, 1) for n in normals], 1)
    trace["obstacles"], trace["obstacles_offsets"] = _ragged(obstacles, 2)
    print(f"golden: {len(frames)} frames", file=sys.stderr)
    return trace


def record_cameras(seeds: list[int], seconds: float, period: float = 0.3, cylinders: int = 600,
                   views: int = 100) -> dict[str, np.ndarray]:
    """Ray casting of the front and RGB-D cameras in the matches: every ``period`` [s] of sim time each robot's
    cameras render the scene (a goalie its two RGB-D cameras, any other robot its front camera). Both cameras sit
    below the robots' and the posts' tops, so ``cylinders`` seeded cylinders (lower and higher than the front camera's
    lens, in front of it) and ``views`` seeded RGB-D views (cameras 0.3-2 m high looking down on robots, the ball and
    the goals) follow, drawn from ``default_rng(0)``. Recorded:

    - ``paint``: every upright cylinder the front cameras painted (``FrontCameraRenderer._paint_cylinder``): its box
      (u0, v0, u1, v1), geometry (x, y, height, radius in the body frame), side and top colours; ``side_bits`` and
      ``top_bits``: which pixels of the box it painted in the side's and in the top's colour (row by row, as
      ``np.packbits``: each cylinder's bits from a new byte, its first byte at ``bits_offsets``);
    - ``cast``: every RGB-D ray cast (``RgbdCameraRenderer.cast``): the viewpoint and rotation (twelve numbers);
      ``shapes`` (six numbers each, ragged); what each ray met (``kind``, ragged), the ranges of the rays that met
      the ball (``ranges``, ragged) and the SHA-256 of all the ranges' bytes (``ranges_sha``)."""
    paints: list[list[float]] = []
    side_bits: list[np.ndarray] = []
    top_bits: list[np.ndarray] = []
    casts: list[np.ndarray] = []
    shapes: list[np.ndarray] = []
    kinds: list[np.ndarray] = []
    ranges: list[np.ndarray] = []
    digests: list[np.ndarray] = []
    paint, cast, pose = FrontCameraRenderer._paint_cylinder, RgbdCameraRenderer.cast, RgbdCameraRenderer.pose
    posed: list[tuple[np.ndarray, np.ndarray]] = []

    def recorded_paint(self: Any, image: np.ndarray, box: tuple[int, int, int, int], geometry: Any,
                       side_rgb: np.ndarray, top_rgb: np.ndarray) -> None:
        # The box picks the camera's rays: painted on whole images (once dark, once light: any colour shows) and
        # read back within the box
        u0, v0, u1, v1 = box
        dark, light = (np.full(image.shape, fill, np.uint8) for fill in (0, 255))
        for canvas in (dark, light):
            paint(self, canvas, box, geometry, side_rgb, top_rgb)
        if np.array_equal(side_rgb, top_rgb):
            raise RuntimeError("golden cameras: a cylinder's side and top have one colour")
        outside = np.ones(image.shape[:2], bool)
        outside[v0:v1, u0:u1] = False
        if (dark[outside] != 0).any() or (light[outside] != 255).any():
            raise RuntimeError("golden cameras: a cylinder painted outside its box")
        dark, light = dark[v0:v1, u0:u1], light[v0:v1, u0:u1]
        touched = (dark != 0).any(axis=2) | (light != 255).any(axis=2)
        top = touched & (dark == top_rgb).all(axis=2)
        paints.append([*box, *geometry, *side_rgb, *top_rgb])
        side_bits.append(np.packbits(touched & ~top))
        top_bits.append(np.packbits(top))
        paint(self, image, box, geometry, side_rgb, top_rgb)

    def recorded_pose(self: Any, mount: Any, me: Any) -> tuple[np.ndarray, np.ndarray]:
        posed.append(pose(self, mount, me))
        return posed[-1]

    def recorded_cast(self: Any, o: np.ndarray, rotation: np.ndarray,
                      bodies: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        rng_t, kind = cast(self, o, rotation, bodies)
        origin, turn = posed.pop()
        if not (np.array_equal(origin, o) and np.array_equal(turn, rotation)):
            raise RuntimeError("golden cameras: a cast is not from the camera's pose")
        casts.append(np.concatenate([o, rotation.reshape(-1)]))
        shapes.append(np.array(bodies, dtype=float).reshape(-1, 6))
        kinds.append(kind.reshape(-1, 1))
        ranges.append(rng_t[kind == BALL].reshape(-1, 1))
        digests.append(np.frombuffer(hashlib.sha256(rng_t.tobytes()).digest(), np.uint8))
        return rng_t, kind

    FrontCameraRenderer._paint_cylinder = recorded_paint  # type: ignore[assignment]
    RgbdCameraRenderer.cast, RgbdCameraRenderer.pose = recorded_cast, recorded_pose  # type: ignore[assignment]
    try:
        for seed in seeds:
            config = match_config(TEAMS / "nubot.yaml", TEAMS / "rival.yaml", "18x12", "mpc", half_seconds=600.0,
                                  halves=2, seed=seed)
            with LockstepMatch(config, []) as match:
                match.reset(seed)
                sim = match.sim
                assert sim is not None
                t = period
                while t <= seconds + 1e-9:
                    match.run(until=t)
                    for name in sorted(sim.plugins):
                        if name in match.goalies:
                            sim.rgbd_frames(name)
                        else:
                            sim.front_camera_frame(name)
                    t += period
            print(f"golden: seed {seed} played ({seconds:.0f} s)", file=sys.stderr)
        rng = np.random.default_rng(0)
        world, params = WorldDescription(), SensorParams()
        front = FrontCameraRenderer(world, params.front_camera, params.camera)
        image = np.zeros((front.camera.height, front.camera.width, 3), np.uint8)
        for _ in range(cylinders):
            x, y, height, radius = (float(v) for v in rng.uniform((0.1, -3.0, 0.05, 0.05), (5.0, 3.0, 1.2, 0.5)))
            r, g, b = (float(c) for c in rng.uniform(10.0, 240.0, 3))
            front._draw_cylinder(image, (x, y, height, radius), (r, g, b))
        rgbd = RgbdCameraRenderer(world, params.rgbd)
        f = world.field
        for _ in range(views):
            side = float(rng.choice((-1.0, 1.0)))
            x, y = side * rng.uniform(2.0, f.half_length), rng.uniform(-f.half_width, f.half_width)
            heading = math.atan2(-y, side * f.half_length - x) + rng.uniform(-1.0, 1.0)  # towards the goal, roughly
            me = RobotState(float(x), float(y), float(heading), 0.0, 0.0, 0.0)
            mount = CameraMount(z=float(rng.uniform(0.3, 2.0)), yaw_deg=float(rng.uniform(-45.0, 45.0)),
                                pitch_deg=float(rng.uniform(-60.0, 20.0)))
            around = [(float(d), heading + float(a))
                      for d, a in zip(rng.uniform(0.6, 4.0, 5), rng.uniform(-0.8, 0.8, 5), strict=True)]
            others = [RobotState(x + d * math.cos(a), y + d * math.sin(a), 0.0, 0.0, 0.0, 0.0) for d, a in around[:4]]
            d, a = around[4]
            ball = BallState(x + d * math.cos(a), y + d * math.sin(a), float(rng.uniform(world.ball.radius, 1.5)), 0.0,
                             0.0, 0.0)
            rgbd.render_camera("left", mount, me, ball, others, 0.0, rng)
    finally:
        FrontCameraRenderer._paint_cylinder = paint  # type: ignore[assignment]
        RgbdCameraRenderer.cast, RgbdCameraRenderer.pose = cast, pose  # type: ignore[assignment]
    trace: dict[str, np.ndarray] = {"paint": np.array(paints).reshape(-1, 14), "cast": np.array(casts),
                                    "ranges_sha": np.array(digests)}
    trace["side_bits"], trace["top_bits"] = np.concatenate(side_bits), np.concatenate(top_bits)
    trace["bits_offsets"] = np.append(0, np.cumsum([len(b) for b in side_bits])).astype(np.int64)
    trace["kind"] = np.concatenate(kinds)  # bytes, not floats
    trace["kind_offsets"] = np.append(0, np.cumsum([len(k) for k in kinds])).astype(np.int64)
    trace["shapes"], trace["shapes_offsets"] = _ragged(shapes, 6)
    trace["ranges"], trace["ranges_offsets"] = _ragged(ranges, 1)
    print(f"golden: {len(paints)} cylinders painted, {len(casts)} RGB-D casts", file=sys.stderr)
    return trace


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("piece", choices=("follow", "world", "obstacles", "physics", "sensing", "cameras"))
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--seeds", type=int, default=3, help="matches, seeds 0 .. N-1")
    ap.add_argument("--seconds", type=float, default=60.0, help="sim time per match [s]")
    ap.add_argument("--tracker", choices=("mpc", "baseline"), default="mpc",
                    help="follow: the robots' tracker in the matches played")
    ap.add_argument("--trackers", type=int, default=3,
                    help="obstacles, follow, world: robots whose obstacle tracker, motion layer or world model is kept")
    args = ap.parse_args(argv)
    if args.seeds < 1 or not args.seconds > 0 or args.trackers < 1:
        ap.error("--seeds, --seconds and --trackers must be positive")
    seeds = list(range(args.seeds))
    if args.piece == "world":
        records = record_world(seeds, args.seconds, args.trackers)
        args.out.parent.mkdir(parents=True, exist_ok=True)
        with lzma.open(args.out, "wt", encoding="utf-8", preset=9) as out:
            for record in records:
                out.write(json.dumps(record) + "\n")
        print(f"golden: world trace written to {args.out} ({args.out.stat().st_size // 1024} KiB)", file=sys.stderr)
        return 0
    if args.piece == "follow":
        trace = record_follow(seeds, args.seconds, args.trackers, args.tracker)
    elif args.piece == "physics":
        trace = record_physics(seeds, args.seconds)
    elif args.piece == "sensing":
        trace = record_sensing(seeds, args.seconds)
    elif args.piece == "cameras":
        trace = record_cameras(seeds, args.seconds)
    else:
        trace = record_obstacles(seeds, args.seconds, args.trackers)
    if args.out.suffix != ".npz":  # numpy would add it
        args.out = args.out.with_name(args.out.name + ".npz")
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **trace)
    print(f"golden: {args.piece} trace written to {args.out} ({args.out.stat().st_size // 1024} KiB)", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
