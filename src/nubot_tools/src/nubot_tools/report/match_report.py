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
import shutil
import sys
import tempfile
from collections.abc import Callable
from dataclasses import dataclass
from pathlib import Path
from typing import Any

from nubot_common.json_text import strict_json
from nubot_common.naming import team_of
from nubot_common.world_description import WorldDescription, load_world
from nubot_match import match_analysis as ma
from nubot_match import match_shots
from nubot_match.bag_reader import WORLD_TOPIC, MatchBagError, read_match
from nubot_tools.report import match_plots

DEFAULT_FIELD = "18x12"
PROGRESS_MIN_MESSAGES = 10_000  # smaller bags read in a blink: no progress lines
REPORT_FILES = ("report.json", "heatmap.png", "trajectories.png", "shots.png")  # what a report writes into --out


class MatchReportError(Exception):
    """The bag cannot give a match report (missing, unreadable, or without match topics), or the field is bad."""


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
        log = read_match(args.bag, _print_progress, lambda line: print(f"match_report: warning: {line}",
                                                                       file=sys.stderr))
        choice = choose_world(log.world, args.field, args.field_length, args.field_width, args.goal_width)
    except (MatchBagError, MatchReportError) as exc:
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
        (staging / "report.json").write_text(strict_json(report))
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
