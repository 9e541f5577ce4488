#!/usr/bin/env python3
"""Report on one match from its rosbag alone: score, possession, passes, shots, collisions, referee events, plots.

    python scripts/match_report.py matches/<match>/match.bag [--out DIR]

Requires (any of these topics in the bag; the message definitions come from the bag itself, so
neither ROS nor the workspace's .msg files are needed, only the ``rosbags`` package):
``/sim_visual/model_states`` (nubot_common/ModelStates), ``/sim_visual/goal`` (GoalEvent),
``/sim_visual/kick`` (KickEvent), ``/sim_visual/ball_touch`` (BallTouch), ``/referee/state``
(GameState), ``/<team>/receive_from_coach`` (CoachInfo) and ``/clock`` (rosgraph_msgs/Clock).
Provides: ``report.json``, ``heatmap.png`` (ball during running time) and ``trajectories.png``
in ``--out`` (default: the bag's folder), and a short summary on stdout; progress on stderr.
Parameters: ``--field-length`` / ``--field-width`` / ``--goal-width`` [m] (18 / 12 / 2.4),
``--attack TEAM=+x|-x`` (the side TEAM attacks when no GameState was recorded; the others
attack the opposite side; default nubot=+x).
Times are sim time [s]: header stamps, and for model states the latest ``/clock`` before them.
The statistics are defined in ``match_analysis`` (and in report.json under "definitions").
Exit status: 0 on success, 2 for a missing or unreadable bag or one without any expected topic.
"""

from __future__ import annotations

import argparse
import json
import re
import sys
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from statistics import median

import numpy as np
from rosbags.rosbag1 import Reader, ReaderError
from rosbags.typesys import Stores, TypesysError, get_types_from_msg, get_typestore

import match_analysis as ma

MATCH_TOPICS = {
    "/sim_visual/model_states": "nubot_common/msg/ModelStates",
    "/sim_visual/goal": "nubot_common/msg/GoalEvent",
    "/sim_visual/kick": "nubot_common/msg/KickEvent",
    "/sim_visual/ball_touch": "nubot_common/msg/BallTouch",
    "/referee/state": "nubot_common/msg/GameState",
}
CLOCK_TOPIC, CLOCK_TYPE = "/clock", "rosgraph_msgs/msg/Clock"
COACH_TOPIC = re.compile(r"^/(?P<team>[^/]+)/receive_from_coach$")
COACH_TYPE = "nubot_common/msg/CoachInfo"
PROGRESS_STEPS = 10  # progress lines per bag
PROGRESS_MIN_MESSAGES = 10_000  # smaller bags read in a blink: no progress lines


class MatchReportError(Exception):
    """The bag cannot give a match report (missing, unreadable, or without match topics)."""


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


@dataclass
class MatchLogBuilder:
    """Collects converted messages in bag order; ``finish`` returns the ``MatchLog``."""

    clock_recorded: bool
    clock: float | None = None
    sample_times: list[float] = field(default_factory=list)  # NaN until a /clock value is known
    sample_bag_times: list[float] = field(default_factory=list)
    positions: dict[str, tuple[list[int], list[float], list[float]]] = field(default_factory=dict)
    stamp_lags: list[float] = field(default_factory=list)  # bag time - header stamp [s]
    log: ma.MatchLog = field(default_factory=ma.MatchLog)

    def add(self, topic: str, msgtype: str, msg, bag_time: float) -> None:
        if msgtype == CLOCK_TYPE:
            self.clock = msg.clock.sec + msg.clock.nanosec * 1e-9
            return
        if msgtype == MATCH_TOPICS["/sim_visual/model_states"]:
            self._add_model_states(msg, bag_time)
            return
        t = _stamp(msg)
        self.stamp_lags.append(bag_time - t)
        log = self.log
        if msgtype == MATCH_TOPICS["/sim_visual/goal"]:
            log.goals.append(ma.Goal(t, int(msg.side), (msg.ball_pos.x, msg.ball_pos.y), msg.last_touch))
        elif msgtype == MATCH_TOPICS["/sim_visual/kick"]:
            v = msg.velocity
            log.kicks.append(ma.Kick(t, msg.robot, int(msg.kind), (v.x, v.y, v.z), (msg.ball_pos.x, msg.ball_pos.y)))
        elif msgtype == MATCH_TOPICS["/sim_visual/ball_touch"]:
            log.touches.append(ma.Touch(t, msg.robot))
        elif msgtype == MATCH_TOPICS["/referee/state"]:
            log.referee.append(ma.RefereeState(
                t, tuple(msg.teams), tuple(int(s) for s in msg.score), tuple(int(a) for a in msg.attack),
                int(msg.half), float(msg.game_time), bool(msg.running), msg.last_event))
        elif msgtype == COACH_TYPE:
            log.coach.append(ma.CoachCommand(t, COACH_TOPIC.match(topic)["team"], int(msg.MatchMode)))

    def _add_model_states(self, msg, bag_time: float) -> None:
        index = len(self.sample_times)
        self.sample_times.append(np.nan if self.clock is None else self.clock)
        self.sample_bag_times.append(bag_time)
        for name, pose in zip(msg.name, msg.pose):
            indices, xs, ys = self.positions.setdefault(name, ([], [], []))
            indices.append(index)
            xs.append(pose.position.x)
            ys.append(pose.position.y)

    def finish(self) -> ma.MatchLog:
        times = np.asarray(self.sample_times, dtype=float)
        if not self.clock_recorded:
            # without /clock, bring receive times to sim time with the typical lag of the stamped messages
            lag = median(self.stamp_lags) if self.stamp_lags else 0.0
            times = np.asarray(self.sample_bag_times, dtype=float) - lag
        elif len(times) and np.isnan(times).any():
            known = times[~np.isnan(times)]
            times[np.isnan(times)] = known[0] if len(known) else (self.clock or 0.0)
        log = self.log
        for name, (indices, xs, ys) in self.positions.items():
            log.tracks[name] = ma.Track(name, times[np.asarray(indices, dtype=int)], np.column_stack([xs, ys]))
        for records in (log.goals, log.kicks, log.touches, log.referee, log.coach):
            records.sort(key=lambda r: r.t)
        seen = [*times, *(r.t for rs in (log.goals, log.kicks, log.touches, log.referee, log.coach) for r in rs)]
        if self.clock is not None:
            seen.append(self.clock)
        log.start, log.end = (float(min(seen)), float(max(seen))) if seen else (0.0, 0.0)
        return log


def _wanted(conn) -> bool:
    if conn.topic in MATCH_TOPICS or COACH_TOPIC.match(conn.topic):
        return True
    return conn.topic == CLOCK_TOPIC and conn.msgtype == CLOCK_TYPE


def read_match(path: Path, progress: Callable[[int, int, float | None], None] | None = None) -> ma.MatchLog:
    """Read a match bag into a ``MatchLog``; ``progress(done, total, sim_time)`` is called every 10 %."""
    if not path.is_file():
        raise MatchReportError(f"no such bag file: {path}")
    try:
        with Reader(path) as reader:
            conns = [c for c in reader.connections if _wanted(c)]
            expected = {**MATCH_TOPICS, **{c.topic: COACH_TYPE for c in conns if COACH_TOPIC.match(c.topic)}}
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
                    progress(done, total, builder.clock)
                    next_report = done * PROGRESS_STEPS // total + 1
            log = builder.finish()
    except ReaderError as exc:
        raise MatchReportError(f"{path} is not a readable ROS 1 bag: {exc}") from exc
    for w in wrong:
        print(f"match_report: warning: ignored {w}: not the expected type", file=sys.stderr)
    return log


def _print_progress(done: int, total: int, sim_time: float | None) -> None:
    if total < PROGRESS_MIN_MESSAGES:
        return
    clock = "" if sim_time is None else f", sim time {sim_time:.1f} s"
    print(f"  read {100 * done // total:3d} % ({done}/{total} messages{clock})", file=sys.stderr, flush=True)


def format_summary(summary: ma.MatchSummary, bag: Path, out: Path) -> str:
    """Return the few lines a person reads first."""
    teams = summary.teams
    lines = [f"match report for {bag}",
             f"  sim time {summary.start:.1f} to {summary.end:.1f} s ({summary.end - summary.start:.1f} s), "
             f"running {summary.running_time:.1f} s; teams: {', '.join(teams) or 'none seen'}"]
    score = " - ".join(f"{t} {summary.score.get(t, 0)}" for t in teams)
    if summary.referee_score is not None:
        ref = " - ".join(f"{t} {n}" for t, n in summary.referee_score.items())
        score += "  (referee agrees)" if summary.score_agrees else f"  (REFEREE DIFFERS: {ref})"
    lines.append(f"  score: {score}")
    for g in summary.goals:
        clock = f", half {g.half} at {g.game_time:.1f} s game time" if g.game_time is not None else ""
        who = f"own goal by {g.goal.last_touch}" if g.own_goal else (g.goal.last_touch or "no touch")
        lines.append(f"    goal at {g.goal.t:.1f} s for {g.team or '?'} ({who}{clock})")
    for g in summary.goals_outside_play:
        lines.append(f"    not counted: ball in the goal at {'+x' if g.goal.side > 0 else '-x'} at {g.goal.t:.1f} s "
                     f"while play was stopped (last touch {g.goal.last_touch or 'nobody'})")
    share = summary.possession_share()
    lines.append("  possession: " + ", ".join(f"{k} {100 * v:.1f} %" for k, v in share.items()))
    passes = summary.pass_counts()
    lines.append("  passes completed/tried: " + ", ".join(f"{t} {c['completed']}/{c['tried']}"
                                                           for t, c in passes.items()))
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
    events = summary.referee_events
    lines.append(f"  referee events: {len(events)}")
    shown = events if len(events) <= 12 else [*events[:6], *events[-5:]]
    for i, (t, text) in enumerate(shown):
        if len(events) > 12 and i == 6:
            lines.append(f"    ... {len(events) - 11} more")
        lines.append(f"    {t:7.1f} s  {text}")
    lines.append("  distance run [m]:")
    for team in sorted({ma.team_of(r) for r in summary.distance_run}, key=lambda t: (t not in teams, t)):
        lines.append(f"    {team}: " + ", ".join(f"{r} {d:.1f}" for r, d in summary.distance_run.items()
                                                 if ma.team_of(r) == team))
    lines += [f"  warning: {w}" for w in summary.warnings]
    lines.append(f"  wrote report.json, heatmap.png, trajectories.png in {out}")
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
    parser.add_argument("--field-length", type=float, default=18.0, help="[m] (default 18)")
    parser.add_argument("--field-width", type=float, default=12.0, help="[m] (default 12)")
    parser.add_argument("--goal-width", type=float, default=2.4, help="between the posts [m] (default 2.4)")
    parser.add_argument("--attack", type=_attack, default=("nubot", 1), metavar="TEAM=+x|-x",
                        help="side TEAM attacks when no GameState was recorded (default nubot=+x)")
    return parser.parse_args(argv)


def main(argv: list[str] | None = None) -> int:
    args = parse_args(argv)
    try:
        field_size = ma.FieldSize(length=args.field_length, width=args.field_width, goal_width=args.goal_width)
        log = read_match(args.bag, _print_progress)
    except (MatchReportError, ValueError) as exc:
        print(f"match_report: error: {exc}", file=sys.stderr)
        return 2
    summary = ma.analyse(log, field_size, default_attack=args.attack)
    out = args.out if args.out is not None else args.bag.parent
    out.mkdir(parents=True, exist_ok=True)
    report = {"bag": str(args.bag), **summary.to_json(),
              "files": {"heatmap": "heatmap.png", "trajectories": "trajectories.png"}}
    (out / "report.json").write_text(json.dumps(report, indent=2) + "\n")
    ball = ma.ball_samples_in_play(log, ma.running_intervals(log.referee, log.start, log.end))
    ball_track = log.tracks.get(ma.BALL)
    period = float(np.median(np.diff(ball_track.t))) if ball_track is not None and len(ball_track.t) > 1 else 0.0
    ma.plot_ball_heatmap(ball, field_size, out / "heatmap.png", sample_period=period,
                         title=f"Ball heat map, running time ({args.bag.name})")
    ma.plot_trajectories(log.tracks, summary.teams, field_size, out / "trajectories.png",
                         title=f"Robot trajectories ({args.bag.name})")
    print(format_summary(summary, args.bag, out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
