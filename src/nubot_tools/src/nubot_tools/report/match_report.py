"""Report on one match from its rosbag alone: score, possession, passes, shots, collisions, referee events, plots.

    python -m nubot_tools.report.match_report matches/<match>/match.bag [--out DIR] [--field 18x12|22x14|PATH]

Requires (any of these topics in the bag; the message definitions come from the bag itself, so
neither ROS nor the workspace's .msg files are needed, only the ``rosbags`` package):
``/sim_visual/model_states`` (nubot_common/ModelStates), ``/sim_visual/goal`` (GoalEvent),
``/sim_visual/kick`` (KickEvent), ``/sim_visual/ball_touch`` (BallTouch), ``/referee/state``
(GameState), ``/referee/foul`` (RefereeCall: the fouls and other calls, counted per team and kind),
``/<team>/receive_from_coach`` (CoachInfo), ``/clock`` (rosgraph_msgs/Clock) and
``/sim_visual/world_description`` (WorldDescription, latched: the field, the ball's model name, the robots'
radius).
Provides: ``report.json`` (with "field": the field used [m] and its source: bag, --field, flags or
default; "shot_report": every shot and every goal explained, ``match_shots``), ``heatmap.png`` (running
time [s] of the ball per cell), ``trajectories.png`` and ``shots.png`` (the shot map) in ``--out``
(default: the bag's folder), and a short summary on stdout (each goal in a line); progress on stderr.
Each team's goalie is the robot that announced the role GOALIE most in its first StrategyInfo messages
(``/<robot>/nubotcontrol/strategy``), else AgentID 1.
Parameters: ``--field 18x12|22x14|PATH`` (a world description instead of the bag's; without either,
the 18 x 12 m default and a warning), ``--field-length`` / ``--field-width`` / ``--goal-width`` [m]
(override those dimensions of the field used), ``--attack TEAM=+x|-x`` (the side TEAM attacks when
no GameState was recorded; the others attack the opposite side; default nubot=+x).
Times are sim time [s]: header stamps; for model states their header stamp when the bag's
definition has one and it is > 0, else the latest ``/clock`` before them (else the receive time
minus the typical lag of the stamped messages); samples sharing one time are spread out up to the
next (``match_analysis.spread_repeated_times``).
The statistics are defined in ``match_analysis`` (and in report.json under "definitions").
Exit status: 0 on success, 2 for a missing or unreadable bag or one without any expected topic, a
bad field, or an ``--out`` that cannot hold the report (then no file of the report is written).
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import os
import re
import shutil
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from statistics import median
from typing import Any

import numpy as np
from rosbags.rosbag1 import Reader, ReaderError
from rosbags.typesys import Stores, TypesysError, get_types_from_msg, get_typestore

from nubot_common.field import FieldGeometry
from nubot_common.naming import team_of
from nubot_common.params import from_mapping
from nubot_common.world_description import BallBody, RobotBody, WorldDescription, load_world
from nubot_match import match_analysis as ma
from nubot_match import match_shots
from nubot_tools.report import match_plots

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
DEFAULT_FIELD = "18x12"
PROGRESS_STEPS = 10  # progress lines per bag
PROGRESS_MIN_MESSAGES = 10_000  # smaller bags read in a blink: no progress lines
REPORT_FILES = ("report.json", "heatmap.png", "trajectories.png", "shots.png")  # what a report writes into --out


class MatchReportError(Exception):
    """The bag cannot give a match report (missing, unreadable, or without match topics), or the field is bad."""


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
        raise MatchReportError(f"cannot use the bag's message definitions: {exc}") from exc
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


def read_match(path: Path, progress: Callable[[int, int, float | None], None] | None = None) -> ma.MatchLog:
    """Read a match bag into a ``MatchLog`` (``world``: the bag's world description, None without one);
    ``progress(done, total, sim_time)`` is called every 10 %."""
    if not path.is_file():
        raise MatchReportError(f"no such bag file: {path}")
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
                raise MatchReportError(
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
    except ReaderError as exc:
        raise MatchReportError(f"{path} is not a readable ROS 1 bag: {exc}") from exc
    for w in [*(f"{w}: not the expected type" for w in wrong), *builder.ignored]:
        print(f"match_report: warning: ignored {w}", file=sys.stderr)
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


@dataclass(frozen=True)
class FieldChoice:
    """The world a report uses, and where its field came from."""

    world: WorldDescription
    source: str  # bag | --field | flags | default
    refines: str = ""  # for flags: the source whose field they change

    def describe(self) -> str:
        """Say where the field came from, in a few words."""
        if self.source == "flags":
            return f"--field-length/--field-width/--goal-width over the {_SOURCE_WORDS[self.refines]}"
        return _SOURCE_WORDS[self.source]

    def to_json(self) -> dict:
        return {"source": self.source, **({"refines": self.refines} if self.refines else {})}


_SOURCE_WORDS = {"bag": "bag's world description", "--field": "--field world description",
                 "default": "default field: the bag has no world description"}


def choose_world(bag_world: WorldDescription | None, field_name: str | None = None, length: float | None = None,
                 width: float | None = None, goal_width: float | None = None) -> FieldChoice:
    """Return the world to report in: ``--field`` (a shipped field or a YAML path), else the bag's, else the
    18 x 12 m default; then the given dimensions [m] replace the field's. Raise ``MatchReportError`` if bad."""
    try:
        if field_name is not None:
            choice = FieldChoice(load_world(field_name), "--field")
        elif bag_world is not None:
            choice = FieldChoice(bag_world, "bag")
        else:
            choice = FieldChoice(load_world(DEFAULT_FIELD), "default")
        sizes = {k: v for k, v in (("length", length), ("width", width), ("goal_width", goal_width)) if v is not None}
        if sizes:
            world = choice.world
            choice = FieldChoice(dataclasses.replace(world, field=dataclasses.replace(world.field, **sizes)),
                                 "flags", choice.source)
    except ValueError as exc:
        raise MatchReportError(f"bad field: {exc}") from exc
    return choice


def _print_progress(done: int, total: int, sim_time: float | None) -> None:
    if total < PROGRESS_MIN_MESSAGES:
        return
    clock = "" if sim_time is None else f", sim time {sim_time:.1f} s"
    print(f"  read {100 * done // total:3d} % ({done}/{total} messages{clock})", file=sys.stderr, flush=True)


def format_summary(summary: ma.MatchSummary, bag: Path, out: Path, field_source: str = "",
                   shots: match_shots.ShotReport | None = None) -> str:
    """Return the few lines a person reads first; ``field_source`` says where the field came from."""
    teams = summary.teams
    f = summary.world.field
    lines = [f"match report for {bag}",
             f"  field {f.length:g} x {f.width:g} m, goals {f.goal_width:g} m wide"
             + (f" ({field_source})" if field_source else ""),
             f"  sim time {summary.start:.1f} to {summary.end:.1f} s ({summary.end - summary.start:.1f} s), "
             f"running {summary.running_time:.1f} s (ball samples cover {summary.ball_in_play.total:.1f} s of it); "
             f"teams: {', '.join(teams) or 'none seen'}"]
    score = " - ".join(f"{t} {summary.score.get(t, 0)}" for t in teams)
    if summary.referee_score is not None:
        ref = " - ".join(f"{t} {n}" for t, n in summary.referee_score.items())
        score += "  (referee agrees)" if summary.score_agrees else f"  (REFEREE DIFFERS: {ref})"
    lines.append(f"  score: {score}")
    if shots is not None:
        lines += [f"    goal at {g.goal.goal.t:.1f} s: {line}"
                  for g, line in zip(shots.goals, match_shots.goal_lines(shots))]
    else:
        for g in summary.goals:
            clock = f", half {g.half} at {g.game_time:.1f} s game time" if g.game_time is not None else ""
            who = f"own goal by {g.goal.last_touch}" if g.own_goal else (g.goal.last_touch or "no touch")
            lines.append(f"    goal at {g.goal.t:.1f} s for {g.team or '?'} ({who}{clock})")
    for g in summary.goals_disallowed:
        lines.append(f"    no goal: ball in the goal at {'+x' if g.goal.side > 0 else '-x'} at {g.goal.t:.1f} s, "
                     f"disallowed by the referee (last touch {g.goal.last_touch or 'nobody'})")
    for g in summary.goals_outside_play:
        lines.append(f"    not counted: ball in the goal at {'+x' if g.goal.side > 0 else '-x'} at {g.goal.t:.1f} s "
                     f"while play was stopped (last touch {g.goal.last_touch or 'nobody'})")
    share = summary.possession_share()
    lines.append("  possession: " + ", ".join(f"{k} {100 * v:.1f} %" for k, v in share.items()))
    passes = summary.pass_counts()
    lines.append("  passes completed/tried: " + ", ".join(f"{t} {c['completed']}/{c['tried']}"
                                                           for t, c in passes.items()))
    if shots is not None:
        lines.append("  shots (on target; goal/saved/blocked/wide): " + ", ".join(
            f"{t} {c['shots']} ({c['on_target']}; {c['goal']}/{c['saved']}/{c['blocked']}/{c['wide']}"
            + (f", {c['disallowed']} disallowed" if c["disallowed"] else "") + ")"
            for t, c in shots.shot_counts().items()))
        lines.append("  goals from: " + ", ".join(f"{k} {n}" for k, n in shots.cause_counts().items() if n)
                     if shots.goals else "  goals from: no goal")
    else:
        lines.append("  shots: " + ", ".join(f"{t} {n}" for t, n in summary.shot_counts().items()))
    clashes = summary.collision_counts()
    lines.append(f"  collisions: {clashes['total']} ({clashes['per_minute']:.2f} per running minute): opponents "
                 f"{clashes['opponents']}" + "".join(f", {t}-{t} {n}" for t, n in clashes["same_team"].items()))
    reach = summary.ball_reach_stats()
    line = f"  free balls reached: {reach['episodes']}"
    if reach["episodes"]:
        line += (f" (median {reach['median_s']:.2f} s, mean {reach['mean_s']:.2f} s to reach); "
                 + ", ".join(f"{t} {s['episodes']}" + (f" (median {s['median_s']:.2f} s)" if s["episodes"] else "")
                             for t, s in reach["per_team"].items()))
    if summary.ball_reaches_dropped:
        line += f"; {summary.ball_reaches_dropped} left out (running time ended first)"
    lines.append(line)
    fouls = summary.foul_counts()
    lines.append("  fouls: " + "; ".join(
        f"{t} " + (", ".join(f"{k.replace('_', ' ')} {n}" for k, n in c.items() if n) or "none")
        for t, c in fouls.items()))
    events = summary.referee_events
    lines.append(f"  referee events: {len(events)}")
    shown = events if len(events) <= 12 else [*events[:6], *events[-5:]]
    for i, (t, text) in enumerate(shown):
        if len(events) > 12 and i == 6:
            lines.append(f"    ... {len(events) - 11} more")
        lines.append(f"    {t:7.1f} s  {text}")
    lines.append("  distance run [m]:")
    for team in sorted({team_of(r) for r in summary.distance_run}, key=lambda t: (t not in teams, t)):
        lines.append(f"    {team}: " + ", ".join(f"{r} {d:.1f}" for r, d in summary.distance_run.items()
                                                 if team_of(r) == team))
    lines += [f"  warning: {w}" for w in summary.warnings]
    lines.append(f"  wrote {', '.join(REPORT_FILES)} in {out}")
    return "\n".join(lines)


def _attack(text: str) -> tuple[str, int]:
    team, _, side = text.partition("=")
    sides = {"+x": 1, "x": 1, "1": 1, "+1": 1, "-x": -1, "-1": -1}
    if not team or side not in sides:
        raise argparse.ArgumentTypeError(f"expected TEAM=+x or TEAM=-x, got {text!r}")
    return team, sides[side]


def parse_args(argv: list[str] | None) -> argparse.Namespace:
    parser = argparse.ArgumentParser(prog="match_report", description=__doc__.splitlines()[0])
    parser.add_argument("bag", type=Path, help="the match's rosbag (ROS 1)")
    parser.add_argument("--out", type=Path, help="folder for report.json and the PNGs (default: the bag's folder)")
    parser.add_argument("--field", metavar="18x12|22x14|PATH",
                        help="world description to use instead of the bag's (default: the bag's, else 18x12)")
    parser.add_argument("--field-length", type=float, help="override the field's length [m]")
    parser.add_argument("--field-width", type=float, help="override the field's width [m]")
    parser.add_argument("--goal-width", type=float, help="override the goal width between the posts [m]")
    parser.add_argument("--attack", type=_attack, default=("nubot", 1), metavar="TEAM=+x|-x",
                        help="side TEAM attacks when no GameState was recorded (default nubot=+x)")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        log = read_match(args.bag, _print_progress)
        choice = choose_world(log.world, args.field, args.field_length, args.field_width, args.goal_width)
    except MatchReportError as exc:
        print(f"match_report: error: {exc}", file=sys.stderr)
        return 2
    world = choice.world
    summary = ma.analyse(log, world, default_attack=args.attack)
    if choice.source == "default":
        summary.warnings.insert(0, f"no world description in the bag ({WORLD_TOPIC}) and no --field: using the "
                                   f"default {world.name} field")
    out = args.out if args.out is not None else args.bag.parent
    shots = match_shots.explain(summary, log)
    summary_json = summary.to_json()
    summary_json["field"].update(choice.to_json())
    report = {"bag": str(args.bag), **summary_json, "shot_report": shots.to_json(),
              "files": {"heatmap": "heatmap.png", "trajectories": "trajectories.png", "shots": "shots.png"}}
    run = read_run(args.bag)
    if run is not None:
        report["run"] = run
    ball = summary.ball_in_play

    def draw(folder: Path) -> None:
        match_plots.plot_ball_heatmap(ball.xy, ball.seconds, world.field, folder / "heatmap.png",
                                      title=f"Ball heat map ({args.bag.name})")
        match_plots.plot_trajectories(log.tracks, summary.teams, world.field, folder / "trajectories.png",
                                      teleport_step=summary.teleport_step,
                                      title=f"Robot trajectories ({args.bag.name})")
        match_plots.plot_shot_map(shots.shots, summary.teams, world.field, folder / "shots.png",
                                  title=f"Shot map ({args.bag.name})")

    try:
        write_report(out, report, draw)
    except MatchReportError as exc:
        print(f"match_report: error: {exc}", file=sys.stderr)
        return 2
    print(format_summary(summary, args.bag, out, choice.describe(), shots))
    if run is not None and run.get("ended") == "cut short":
        print(f"  CUT SHORT at sim {run.get('sim_time', 0.0):.1f} s: {run.get('reason')}")
    for event in (run or {}).get("events", []):
        if not event.get("cut_short"):
            print(f"  at sim {event.get('sim_time', 0.0):.1f} s: {event.get('event')}")
    return 0


def write_report(out: Path, report: dict[str, Any], draw: Callable[[Path], None]) -> None:
    """Write ``report`` as report.json and the PNGs ``draw(folder)`` makes into ``out`` (created if need be), all
    or none: they are made in a hidden folder inside ``out`` and moved into place once all exist, so a failure
    (not a folder, no room) leaves an earlier report whole. Raise ``MatchReportError`` naming ``out``."""
    staging: Path | None = None
    try:
        out.mkdir(parents=True, exist_ok=True)
        staging = Path(tempfile.mkdtemp(prefix=".match_report-", dir=out))
        (staging / "report.json").write_text(json.dumps(report, indent=2) + "\n")
        draw(staging)
        for name in REPORT_FILES:
            os.replace(staging / name, out / name)
    except OSError as exc:
        raise MatchReportError(f"cannot write the report to {out}: {exc.strerror or exc} "
                               "(choose another folder with --out)") from None
    finally:
        if staging is not None:
            shutil.rmtree(staging, ignore_errors=True)


def read_run(bag: Path) -> dict | None:
    """How the match runner says the match ended (``run.json`` beside the bag), if it left one."""
    path = bag.parent / "run.json"
    try:
        run = json.loads(path.read_text())
    except FileNotFoundError:
        return None
    except (OSError, ValueError) as exc:
        return {"ended": "unknown", "reason": f"{path} unreadable: {exc}"}
    return run if isinstance(run, dict) else {"ended": "unknown", "reason": f"{path} is not a JSON object"}


if __name__ == "__main__":
    sys.exit(main())
