"""The coach command line: argument parsing, the interactive prompt's input and the text views it prints.

Requires: command-line arguments, prompt lines, and plain views of a robot's world model
(``WatchView``: positions in the team's own field frame [m], own goal at -x).
Provides: ``parse_args`` -> ``CoachArgs`` (raises ``CoachUsageError``, exit status 2, on
bad usage, an unknown command, or a ``--period`` [s] outside ``COACH_PERIODS`` or a ``--duration`` [s]
outside (0, ``MAX_DURATION``]), ``parse_console_line`` -> ``ConsoleInput``,
``help_text``, ``render_watch`` (a few lines and a small character map of the field)
and ``describe_sent``. No ROS here; ``nodes/coach`` does the talking.
"""

from __future__ import annotations

import argparse
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Literal, NoReturn

from coach4sim import CoachError
from coach4sim.params import COACH_PERIODS, TeamSpec
from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.naming import parse_robot_name

COMMAND_SERVICE = "/referee/command"
STATE_TOPIC = "/referee/state"
USAGE_STATUS = 2
MAX_DURATION = 4 * 3600.0  # --duration at most this long [s]; a longer session is --console's


class CoachUsageError(CoachError):
    """Bad command-line usage; the CLI prints it and exits with status 2."""


def coach_topic(team: str) -> str:
    return f"/{team}/receive_from_coach"


def worldmodel_topic(robot: str) -> str:
    return f"/{robot}/worldmodel/worldmodelinfo"


@dataclass(frozen=True)
class CoachArgs:
    action: Literal["send", "console", "watch"]
    team: str = "nubot"
    mode: MatchMode | None = None  # the command to send (action "send")
    robot: str = ""  # the robot to watch (action "watch")
    duration: float = 2.0  # without a referee, publish the command this long [s], in (0, MAX_DURATION]
    period: float = 0.03  # ... this often [s] (the original coach's 30 ms), within COACH_PERIODS
    count: int = 0  # watch: stop after this many views; 0 never


class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise CoachUsageError(message)


def _parser() -> _Parser:
    parser = _Parser(
        prog="coach",
        description="Send game commands to a team, type them at a prompt, or watch a robot's world model. "
                    f"Commands go through the referee ({COMMAND_SERVICE}) when it runs, otherwise straight to "
                    "/<team>/receive_from_coach.",
        epilog="COMMAND is a MatchMode name or number: " + ", ".join(f"{m.name} {m.value}" for m in MatchMode))
    parser.add_argument("command", nargs="?", help="MatchMode name or number, e.g. OUR_KICKOFF or 1")
    parser.add_argument("--team", default="nubot", help="team prefix the command is for (default nubot)")
    parser.add_argument("--console", action="store_true", help="interactive prompt")
    parser.add_argument("--watch", metavar="ROBOT", default="", help="print ROBOT's world model once a second")
    parser.add_argument("--duration", type=float, default=2.0,
                        help=f"without a referee: publish this long [s] (default 2, at most {MAX_DURATION:g})")
    parser.add_argument("--period", type=float, default=0.03,
                        help=f"without a referee: publish this often [s] (default 0.03, from {COACH_PERIODS[0]:g} "
                             f"to {COACH_PERIODS[1]:g})")
    parser.add_argument("--count", type=int, default=0, help="--watch: stop after this many views (0 never)")
    return parser


def parse_args(argv: Sequence[str]) -> CoachArgs:
    """Read the coach's command line (without the program name)."""
    ns = _parser().parse_args(list(argv))
    chosen = [name for name, on in (("COMMAND", ns.command is not None), ("--console", ns.console),
                                    ("--watch", bool(ns.watch))) if on]
    if len(chosen) != 1:
        raise CoachUsageError("give exactly one of COMMAND, --console or --watch ROBOT"
                              + (f" (got {' and '.join(chosen)})" if chosen else ""))
    try:
        TeamSpec(ns.team)
    except ValueError as exc:
        raise CoachUsageError(f"--team: {exc}") from None
    low, high = COACH_PERIODS
    if not low <= ns.period <= high:
        raise CoachUsageError(f"--period must lie in [{low:g}, {high:g}] s, got {ns.period:g}")
    if not 0.0 < ns.duration <= MAX_DURATION:
        raise CoachUsageError(f"--duration must be positive and at most {MAX_DURATION:g} s, got {ns.duration:g}")
    if ns.count < 0:
        raise CoachUsageError(f"--count must not be negative, got {ns.count}")
    common = {"team": ns.team, "duration": ns.duration, "period": ns.period, "count": ns.count}
    if ns.console:
        return CoachArgs("console", **common)
    if ns.watch:
        try:
            parse_robot_name(ns.watch)  # a name no topic can carry would leave the watch waiting forever
        except NubotCommonError as exc:
            raise CoachUsageError(f"--watch: {exc}") from None
        return CoachArgs("watch", robot=ns.watch, **common)
    try:
        mode = parse_match_mode(ns.command)
    except NubotCommonError as exc:
        raise CoachUsageError(str(exc)) from None
    return CoachArgs("send", mode=mode, **common)


# --- the interactive prompt -------------------------------------------------------------------
_ALIASES = {"": MatchMode.STOPROBOT, "s": MatchMode.STOPROBOT, "stop": MatchMode.STOPROBOT,
            "start": MatchMode.STARTROBOT, "go": MatchMode.STARTROBOT, "drop": MatchMode.DROPBALL,
            "park": MatchMode.PARKINGROBOT}
_QUIT = {"q", "quit", "exit"}
_HELP = {"h", "help", "?"}


@dataclass(frozen=True)
class ConsoleInput:
    kind: Literal["send", "quit", "help", "error"]
    mode: MatchMode | None = None
    message: str = ""


def parse_console_line(line: str) -> ConsoleInput:
    """One prompt line: a MatchMode name or number; empty or ``s`` = STOPROBOT; ``q`` quits; ``h`` helps."""
    text = line.strip().lower()
    if text in _QUIT:
        return ConsoleInput("quit")
    if text in _HELP:
        return ConsoleInput("help")
    if text in _ALIASES:
        return ConsoleInput("send", _ALIASES[text])
    try:
        return ConsoleInput("send", parse_match_mode(text))
    except NubotCommonError as exc:
        return ConsoleInput("error", message=f"{exc} (h for help)")


def help_text() -> str:
    modes = [f"{m.value:>2} {m.name:<15}" for m in MatchMode]
    rows = ["  " + "".join(modes[i:i + 3]).rstrip() for i in range(0, len(modes), 3)]
    return "\n".join(["Type a command name or number and press Enter:", *rows,
                      "  Enter or s = STOPROBOT, start = STARTROBOT, drop = DROPBALL, park = PARKINGROBOT,",
                      "  h = this help, q = quit"])


def mode_name(value: int) -> str:
    try:
        return MatchMode(value).name
    except ValueError:
        return f"unknown({value})"


def describe_sent(what: str, topic: str, period: float, duration: float | None) -> str:
    """What the coach does without a referee, e.g. ``what`` = ``OUR_KICKOFF (1)`` or ``each command``."""
    how_long = f" for {duration:g} s" if duration is not None else ""
    return f"no referee at {COMMAND_SERVICE}: publishing {what} to {topic} every {period * 1000:.0f} ms{how_long}"


# --- the watch view ------------------------------------------------------------------------------
@dataclass(frozen=True)
class ScoreView:
    teams: tuple[str, ...]
    score: tuple[int, ...]
    half: int
    game_time: float  # [s]
    running: bool
    last_event: str


@dataclass(frozen=True)
class WatchView:
    """One robot's world model, in its team's field frame (own goal at -x) [m, rad]."""

    robot: str
    stamp: float  # [s]
    pose: tuple[float, float, float] | None = None  # own x, y, heading
    ball: tuple[float, float] | None = None
    ball_source: str = ""  # "own" (own sensors) or "team" (a teammate's)
    teammates: tuple[tuple[int, float, float], ...] = ()  # (AgentID, x, y) of the valid teammates
    opponents: tuple[tuple[float, float], ...] = ()
    mode: int = int(MatchMode.STOPROBOT)
    previous: int = int(MatchMode.STOPROBOT)
    score: ScoreView | None = None


def _xy(point: tuple[float, ...]) -> str:
    return f"({point[0]:+.2f}, {point[1]:+.2f})"


def render_score(score: ScoreView | None) -> str:
    if score is None:
        return "score: no referee state"
    goals = " : ".join(str(s) for s in score.score)
    clock = f"{int(score.game_time) // 60}:{int(score.game_time) % 60:02d}"
    state = "play on" if score.running else "stopped"
    return f"{' - '.join(score.teams)} {goals}  half {score.half} {clock} {state}"


def render_field(view: WatchView, field: FieldGeometry, columns: int = 37, rows: int = 13) -> list[str]:
    """A character map of the field: ``@`` this robot, digits teammates, ``x`` opponents, ``o`` the ball."""
    grid = [[" "] * columns for _ in range(rows)]
    for r in range(rows):
        grid[r][columns // 2] = ":"

    def put(x: float, y: float, mark: str) -> None:
        col = round((x + field.half_length) / field.length * (columns - 1))
        row = round((field.half_width - y) / field.width * (rows - 1))
        grid[min(max(row, 0), rows - 1)][min(max(col, 0), columns - 1)] = mark

    for x, y in view.opponents:
        put(x, y, "x")
    for agent, x, y in view.teammates:
        put(x, y, str(agent % 10))
    if view.pose is not None:
        put(view.pose[0], view.pose[1], "@")
    if view.ball is not None:
        put(view.ball[0], view.ball[1], "o")
    border = "+" + "-" * columns + "+"
    goal_rows = {r for r in range(rows) if abs(field.half_width - r * field.width / (rows - 1)) <= field.goal_width / 2}
    lines = [border]
    for r, cells in enumerate(grid):
        edge = "]" if r in goal_rows else "|"
        lines.append(("[" if r in goal_rows else "|") + "".join(cells) + edge)
    lines.append(border)
    return lines


def render_watch(view: WatchView, field: FieldGeometry | None = None, with_map: bool = True) -> str:
    """The compact text view the coach prints once a second."""
    field = field or FieldGeometry()
    mode = f"mode {mode_name(view.mode)} (before: {mode_name(view.previous)})"
    me = "me: unknown" if view.pose is None else \
        f"me {_xy(view.pose)} {math.degrees(view.pose[2]):+.0f} deg"
    ball = "ball: unknown" if view.ball is None else f"ball {_xy(view.ball)} ({view.ball_source})"
    mates = " ".join(f"{a}{_xy((x, y))}" for a, x, y in view.teammates) or "-"
    lines = [f"{view.robot} t={view.stamp:.1f} s  {mode}  {render_score(view.score)}",
             f"{me} | {ball} | teammates {len(view.teammates)}: {mates} | opponents {len(view.opponents)}"]
    if with_map:
        lines += render_field(view, field)
    if view.score is not None and view.score.last_event:
        lines.append(f"last event: {view.score.last_event}")
    return "\n".join(lines)
