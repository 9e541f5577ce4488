"""A match's ROS 1 bag read back into a ``MatchLog`` (``match_analysis``), without ROS: a bag of a ROS match
(``rosbag record``) or of a lockstep one (``nubot_match.bag``) alike.

Requires: the ``rosbags`` package; the message definitions come from the bag itself, so neither ROS nor the
workspace's .msg files are needed. Reads ``/sim_visual/model_states``, ``goal``, ``kick``, ``ball_touch``,
``/referee/state``, ``/referee/foul``, ``/<team>/receive_from_coach``, ``/clock`` and
``/sim_visual/world_description``; each team's goalie from its robots' first StrategyInfo messages.
Provides: ``read_match`` -> ``MatchLog``, ``build_typestore`` (the bag's own types), ``world_from_msg`` (a
deserialised WorldDescription), ``MatchLogBuilder`` and ``MatchBagError``.
"""

from __future__ import annotations

import dataclasses
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from statistics import median
from typing import Any

import numpy as np
from rosbags.rosbag1 import Reader
from rosbags.typesys import Stores, TypesysError, get_types_from_msg, get_typestore

from nubot_common.field import FieldGeometry
from nubot_common.params import from_mapping
from nubot_common.world_description import BallBody, RobotBody, WorldDescription
from nubot_match import match_analysis as ma

MATCH_TOPICS = {
    "/sim_visual/model_states": "nubot_common/msg/ModelStates",
    "/sim_visual/goal": "nubot_common/msg/GoalEvent",
    "/sim_visual/kick": "nubot_common/msg/KickEvent",
    "/sim_visual/ball_touch": "nubot_common/msg/BallTouch",
    "/referee/state": "nubot_common/msg/GameState",
    "/referee/foul": "nubot_common/msg/RefereeCall",
}
WORLD_TOPIC, WORLD_TYPE = "/sim_visual/world_description", "nubot_common/msg/WorldDescription"
CLOCK_TOPIC, CLOCK_TYPE = "/clock", "rosgraph_msgs/msg/Clock"
COACH_TOPIC = re.compile(r"^/(?P<team>[^/]+)/receive_from_coach$")
COACH_TYPE = "nubot_common/msg/CoachInfo"
STRATEGY_TOPIC = re.compile(r"^/(?P<robot>[^/]+)/nubotcontrol/strategy$")
STRATEGY_TYPE = "nubot_common/msg/StrategyInfo"
GOALIE_ROLE = 0  # StrategyInfo.role GOALIE
GOALIE_SAMPLES = 200  # StrategyInfo messages read per robot to tell each team's goalie
PROGRESS_STEPS = 10  # progress calls per bag


class MatchBagError(Exception):
    """The bag cannot be read as a match: missing, unreadable, or without any match topic."""


# What a damaged bag makes its reader raise: rosbags' ReaderError, but on bytes changed in a header, a chunk or a
# message also UnicodeDecodeError, SerdeError, struct's, zlib's and more (the property-based tests found them one
# after the other): any error while a file from elsewhere is parsed means the file cannot be read.
BAG_FAULTS: tuple[type[BaseException], ...] = (Exception,)


def unreadable(path: Path, exc: BaseException) -> str:
    return f"{path} is not a readable ROS 1 bag: {exc or type(exc).__name__}"


def build_typestore(connections):
    """Return the Noetic typestore with every type defined in these connections' message definitions."""
    typestore = get_typestore(Stores.ROS1_NOETIC)
    types = {}
    try:
        for conn in connections:
            if conn.msgdef.data:
                types.update(get_types_from_msg(conn.msgdef.data, conn.msgtype))
        typestore.register(types)
    except TypesysError as exc:
        raise MatchBagError(f"cannot use the bag's message definitions: {exc}") from exc
    return typestore


def _stamp(msg) -> float:
    return msg.header.stamp.sec + msg.header.stamp.nanosec * 1e-9


def world_from_msg(msg) -> WorldDescription:
    """Convert a deserialised WorldDescription message (fields named as the dataclasses'); fields an older
    definition lacks keep their defaults. Raise ``NubotCommonError`` (a ValueError) naming a bad value."""
    def part(sub, cls) -> dict:
        return {f.name: getattr(sub, f.name) for f in dataclasses.fields(cls) if hasattr(sub, f.name)}

    data = {"field": part(msg.field, FieldGeometry), "ball": part(msg.ball, BallBody),
            "robot": part(msg.robot, RobotBody), "ball_name": msg.ball_name}
    return from_mapping(WorldDescription, data, WORLD_TOPIC)


@dataclass
class MatchLogBuilder:
    """Collects converted messages in bag order; ``finish`` returns the ``MatchLog``."""

    clock_recorded: bool
    clock: float | None = None  # latest /clock [s]
    sample_stamps: list[float] = field(default_factory=list)  # model-state header stamps [s], NaN: none or 0
    sample_clocks: list[float] = field(default_factory=list)  # latest /clock before each sample, NaN: none yet
    sample_bag_times: list[float] = field(default_factory=list)
    positions: dict[str, tuple[list[int], list[float], list[float]]] = field(default_factory=dict)
    stamp_lags: list[float] = field(default_factory=list)  # bag time - header stamp [s]
    ignored: list[str] = field(default_factory=list)  # messages left out, and why
    log: ma.MatchLog = field(default_factory=ma.MatchLog)

    @property
    def sim_time(self) -> float | None:
        """The latest sim time [s] seen so far (for progress lines)."""
        stamp = self.sample_stamps[-1] if self.sample_stamps else np.nan
        return self.clock if np.isnan(stamp) else max(stamp, self.clock or 0.0)

    def add(self, topic: str, msgtype: str, msg, bag_time: float) -> None:
        if msgtype == CLOCK_TYPE:
            self.clock = msg.clock.sec + msg.clock.nanosec * 1e-9
            return
        if msgtype == MATCH_TOPICS["/sim_visual/model_states"]:
            self._add_model_states(msg, bag_time)
            return
        if msgtype == WORLD_TYPE:
            try:
                if self.log.world is None:  # latched: the first one is the world of the match
                    self.log.world = world_from_msg(msg)
            except ValueError as exc:
                self.ignored.append(str(exc))  # names the topic and the bad value
            return
        t = _stamp(msg)
        self.stamp_lags.append(bag_time - t)
        log = self.log
        if msgtype == MATCH_TOPICS["/sim_visual/goal"]:
            log.goals.append(ma.Goal(t, int(msg.side), (msg.ball_pos.x, msg.ball_pos.y), msg.last_touch,
                                     msg.ball_pos.z))
        elif msgtype == MATCH_TOPICS["/sim_visual/kick"]:
            v = msg.velocity
            log.kicks.append(ma.Kick(t, msg.robot, int(msg.kind), (v.x, v.y, v.z), (msg.ball_pos.x, msg.ball_pos.y)))
        elif msgtype == MATCH_TOPICS["/sim_visual/ball_touch"]:
            log.touches.append(ma.Touch(t, msg.robot))
        elif msgtype == MATCH_TOPICS["/referee/state"]:
            log.referee.append(ma.RefereeState(
                t, tuple(msg.teams), tuple(int(s) for s in msg.score), tuple(int(a) for a in msg.attack),
                int(msg.half), float(msg.game_time), bool(msg.running), msg.last_event))
        elif msgtype == MATCH_TOPICS["/referee/foul"]:
            log.calls.append(ma.Call(t, msg.kind, msg.team, msg.robot, msg.restart, (msg.position.x, msg.position.y),
                                     msg.rule, msg.text))
        elif msgtype == COACH_TYPE:
            team = COACH_TOPIC.match(topic)
            assert team is not None  # only coach topics have this type (read_match checks)
            log.coach.append(ma.CoachCommand(t, team["team"], int(msg.MatchMode)))

    def _add_model_states(self, msg, bag_time: float) -> None:
        index = len(self.sample_stamps)
        stamp = _stamp(msg) if hasattr(msg, "header") else 0.0  # older bags: ModelStates without a header
        self.sample_stamps.append(stamp if stamp > 0.0 else np.nan)
        self.sample_clocks.append(np.nan if self.clock is None else self.clock)
        self.sample_bag_times.append(bag_time)
        for name, pose in zip(msg.name, msg.pose):
            indices, xs, ys = self.positions.setdefault(name, ([], [], []))
            indices.append(index)
            xs.append(pose.position.x)
            ys.append(pose.position.y)

    def _sample_times(self) -> np.ndarray:
        """Return the model-state sample times [s]: header stamps, else the /clock (or lag) fallback, spread."""
        stamps = np.asarray(self.sample_stamps, dtype=float)
        if self.clock_recorded:
            fallback = np.asarray(self.sample_clocks, dtype=float)
            known = fallback[~np.isnan(fallback)]
            fallback[np.isnan(fallback)] = known[0] if len(known) else (self.clock or 0.0)
        else:
            # without /clock, bring receive times to sim time with the typical lag of the stamped messages
            lag = median(self.stamp_lags) if self.stamp_lags else 0.0
            fallback = np.asarray(self.sample_bag_times, dtype=float) - lag
        return ma.spread_repeated_times(np.where(np.isnan(stamps), fallback, stamps))

    def finish(self) -> ma.MatchLog:
        times = self._sample_times()
        log = self.log
        for name, (indices, xs, ys) in self.positions.items():
            log.tracks[name] = ma.Track(name, times[np.asarray(indices, dtype=int)], np.column_stack([xs, ys]))
        log.goals.sort(key=lambda r: r.t)
        log.kicks.sort(key=lambda r: r.t)
        log.touches.sort(key=lambda r: r.t)
        log.referee.sort(key=lambda r: r.t)
        log.coach.sort(key=lambda r: r.t)
        log.calls.sort(key=lambda r: r.t)
        records: list[Any] = [*log.goals, *log.kicks, *log.touches, *log.referee, *log.coach, *log.calls]
        seen = [*times, *(r.t for r in records)]
        if self.clock is not None:
            seen.append(self.clock)
        log.start, log.end = (float(min(seen)), float(max(seen))) if seen else (0.0, 0.0)
        return log


def _wanted(conn) -> bool:
    if conn.topic in MATCH_TOPICS or conn.topic == WORLD_TOPIC or COACH_TOPIC.match(conn.topic):
        return True
    return conn.topic == CLOCK_TOPIC and conn.msgtype == CLOCK_TYPE


def read_match(path: Path, progress: Callable[[int, int, float | None], None] | None = None,
               warn: Callable[[str], None] = lambda line: print(f"warning: {line}", file=sys.stderr)) -> ma.MatchLog:
    """Read a match bag into a ``MatchLog`` (``world``: the bag's world description, None without one);
    ``progress(done, total, sim_time)`` is called every 10 %, ``warn`` with each message left out and why. Raises
    ``MatchBagError`` for a missing or unreadable bag, or one without any match topic."""
    if not path.is_file():
        raise MatchBagError(f"no such bag file: {path}")
    try:
        with Reader(path) as reader:
            conns = [c for c in reader.connections if _wanted(c)]
            expected = {**MATCH_TOPICS, WORLD_TOPIC: WORLD_TYPE,
                        **{c.topic: COACH_TYPE for c in conns if COACH_TOPIC.match(c.topic)}}
            wrong = sorted({f"{c.topic} ({c.msgtype})" for c in conns
                            if c.topic in expected and c.msgtype != expected[c.topic]})
            conns = [c for c in conns if c.topic not in expected or c.msgtype == expected[c.topic]]
            if not any(c.topic in MATCH_TOPICS for c in conns):
                found = ", ".join(sorted({c.topic for c in reader.connections})) or "no topics at all"
                raise MatchBagError(
                    f"{path} has none of the expected topics ({', '.join(MATCH_TOPICS)}); it has: {found}"
                    + (f"; wrong types: {', '.join(wrong)}" if wrong else ""))
            typestore = build_typestore(conns)
            builder = MatchLogBuilder(clock_recorded=any(c.topic == CLOCK_TOPIC for c in conns))
            total = sum(reader.topics[c.topic].msgcount for c in {c.topic: c for c in conns}.values())
            next_report = 1
            for done, (conn, timestamp, raw) in enumerate(reader.messages(connections=conns), start=1):
                builder.add(conn.topic, conn.msgtype, typestore.deserialize_ros1(raw, conn.msgtype), timestamp * 1e-9)
                if progress is not None and done * PROGRESS_STEPS >= next_report * total:
                    progress(done, total, builder.sim_time)
                    next_report = done * PROGRESS_STEPS // total + 1
            log = builder.finish()
            log.goalies = _goalies(reader)
    except MatchBagError:
        raise
    except BAG_FAULTS as exc:
        raise MatchBagError(unreadable(path, exc)) from exc
    for w in [*(f"{w}: not the expected type" for w in wrong), *builder.ignored]:
        warn(f"ignored {w}")
    return log


def _goalies(reader: Reader) -> dict[str, str]:
    """Each team's goalie from the first ``GOALIE_SAMPLES`` StrategyInfo of every robot (the role it announced most
    often); none without strategy topics (a bag of the simulator alone)."""
    conns = [c for c in reader.connections if STRATEGY_TOPIC.match(c.topic) and c.msgtype == STRATEGY_TYPE]
    if not conns:
        return {}
    typestore = build_typestore(conns[:1])
    seen: dict[str, int] = {}
    goalie: dict[str, int] = {}
    for conn, _stamp_ns, raw in reader.messages(connections=conns):
        match = STRATEGY_TOPIC.match(conn.topic)
        assert match is not None
        robot = match["robot"]
        if seen.get(robot, 0) >= GOALIE_SAMPLES:
            if all(n >= GOALIE_SAMPLES for n in seen.values()) and len(seen) == len({c.topic for c in conns}):
                break
            continue
        seen[robot] = seen.get(robot, 0) + 1
        if typestore.deserialize_ros1(raw, conn.msgtype).role == GOALIE_ROLE:
            goalie[robot] = goalie.get(robot, 0) + 1
    return ma.goalies_by_role(goalie)
