"""Unit tests of the coach CLI's parsing and text views (coach4sim.console)."""

import math

import pytest

from coach4sim.console import (
    CoachUsageError,
    ScoreView,
    WatchView,
    describe_sent,
    help_text,
    parse_args,
    parse_console_line,
    render_field,
    render_watch,
)
from nubot_common.field import FieldGeometry
from nubot_common.match_mode import MatchMode


@pytest.mark.parametrize(("argv", "mode", "team"), [
    (["OUR_KICKOFF"], MatchMode.OUR_KICKOFF, "nubot"),
    (["our_throwin", "--team", "rival"], MatchMode.OUR_THROWIN, "rival"),
    (["--team", "rival", "15"], MatchMode.STARTROBOT, "rival"),
    (["0"], MatchMode.STOPROBOT, "nubot"),
])
def test_a_command_by_name_or_number(argv, mode, team):
    args = parse_args(argv)
    assert (args.action, args.mode, args.team) == ("send", mode, team)
    assert (args.duration, args.period) == (2.0, 0.03)


def test_console_and_watch_modes():
    assert parse_args(["--console", "--team", "rival"]).action == "console"
    watch = parse_args(["--watch", "nubot2", "--count", "3"])
    assert (watch.action, watch.robot, watch.count) == ("watch", "nubot2", 3)


@pytest.mark.parametrize(("argv", "message"), [
    (["OUR_KICKOF"], "unknown MatchMode name 'OUR_KICKOF'"),
    (["14"], "unknown MatchMode 14"),
    ([], "give exactly one of COMMAND, --console or --watch ROBOT$"),
    (["1", "--console"], r"\(got COMMAND and --console\)"),
    (["1", "--team", "nubot1"], "--team: a team prefix is letters and underscores"),
    (["1", "--duration", "0"], r"--duration must be positive and at most 14400 s, got 0$"),
    (["1", "--duration", "5e4"], r"--duration must be positive and at most 14400 s, got 50000$"),
    (["1", "--duration", "nan"], r"--duration must be positive and at most 14400 s, got nan$"),
    (["1", "--period", "1e300"], r"--period must lie in \[0.005, 10\] s, got 1e\+300$"),
    (["1", "--period", "30"], r"--period must lie in \[0.005, 10\] s, got 30$"),
    (["1", "--period", "0.001"], r"--period must lie in \[0.005, 10\] s, got 0.001$"),
    (["1", "--period", "inf"], r"--period must lie in \[0.005, 10\] s, got inf$"),
    (["1", "--bogus"], "unrecognized arguments: --bogus"),
    (["--watch", "no such/robot"], r"--watch: a robot name is a team prefix and an AgentID from 1"),  # once: FATAL,
    (["--watch", "nubot0"], r"--watch: a robot name is a team prefix and an AgentID from 1"),  # then a hang
])
def test_bad_usage_is_refused_with_a_clear_message(argv, message):
    with pytest.raises(CoachUsageError, match=message):
        parse_args(argv)


@pytest.mark.parametrize(("period", "duration"), [(0.005, 14400.0), (10.0, 0.5)])
def test_period_and_duration_at_the_ends_of_their_ranges_are_accepted(period, duration):
    args = parse_args(["1", "--period", str(period), "--duration", str(duration)])
    assert (args.period, args.duration) == (period, duration)


@pytest.mark.parametrize(("line", "kind", "mode"), [
    ("", "send", MatchMode.STOPROBOT),
    ("  s ", "send", MatchMode.STOPROBOT),
    ("3", "send", MatchMode.OUR_THROWIN),
    ("opp_cornerkick", "send", MatchMode.OPP_CORNERKICK),
    ("start", "send", MatchMode.STARTROBOT),
    ("q", "quit", None),
    ("h", "help", None),
])
def test_console_lines(line, kind, mode):
    entry = parse_console_line(line)
    assert (entry.kind, entry.mode) == (kind, mode)


def test_console_line_that_is_no_command_says_why():
    entry = parse_console_line("14")
    assert entry.kind == "error" and "unknown MatchMode 14" in entry.message and "h for help" in entry.message


def test_help_lists_every_command_with_its_number():
    text = help_text()
    for mode in MatchMode:
        assert f"{mode.value:>2} {mode.name}" in text


def test_describe_sent_names_topic_and_period():
    text = describe_sent("OUR_KICKOFF (1)", "/nubot/receive_from_coach", 0.03, 2.0)
    assert text == ("no referee at /referee/command: publishing OUR_KICKOFF (1) to /nubot/receive_from_coach "
                    "every 30 ms for 2 s")


def _view(**kwargs) -> WatchView:
    base = dict(robot="nubot1", stamp=12.34, pose=(-2.0, 0.0, math.pi / 2), ball=(1.0, 2.0), ball_source="own",
                teammates=((2, -4.0, 3.0),), opponents=((9.0, -6.0), (0.5, 0.5)),
                mode=int(MatchMode.STARTROBOT), previous=int(MatchMode.OUR_KICKOFF),
                score=ScoreView(("nubot", "rival"), (2, 1), 1, 75.0, True, "goal for nubot"))
    base.update(kwargs)
    return WatchView(**base)


def test_watch_view_text():
    lines = render_watch(_view()).splitlines()
    assert lines[0] == ("nubot1 t=12.3 s  mode STARTROBOT (before: OUR_KICKOFF)  nubot - rival 2 : 1  half 1 1:15 "
                        "play on")
    assert lines[1] == ("me (-2.00, +0.00) +90 deg | ball (+1.00, +2.00) (own) | teammates 1: 2(-4.00, +3.00) | "
                        "opponents 2")
    assert lines[-1] == "last event: goal for nubot"


def test_watch_view_without_referee_or_pose_and_with_an_unknown_mode():
    text = render_watch(_view(pose=None, ball=None, score=None, mode=14), with_map=False)
    assert "mode unknown(14)" in text and "score: no referee state" in text
    assert "me: unknown" in text and "ball: unknown" in text
    assert len(text.splitlines()) == 2


def test_field_map_places_each_object_in_its_cell():
    field = FieldGeometry()
    lines = render_field(_view(), field, columns=37, rows=13)
    assert len(lines) == 15 and all(len(line) == 39 for line in lines)
    cell = lambda x, y: lines[1 + round((6.0 - y) / 12.0 * 12)][1 + round((x + 9.0) / 18.0 * 36)]  # noqa: E731
    assert cell(1.0, 2.0) == "o"
    assert cell(-2.0, 0.0) == "@"
    assert cell(-4.0, 3.0) == "2"
    assert cell(9.0, -6.0) == "x"
    assert lines[7][0] == "[" and lines[1][0] == "|", "the goals are drawn on the end lines"
