"""Unit tests of match_shots: every shot's outcome and every goal's anatomy on hand-made match records."""

import math

import numpy as np
import pytest

from nubot_common.world_description import WorldDescription
from nubot_match import match_analysis as ma
from nubot_match import match_shots
from nubot_tools.report import match_plots

WORLD = WorldDescription()  # 18 x 12 m: goal lines at x = +-9, posts at y = +-1.2, bar at 1.0 m
NUBOT_KICKOFF, OPP_KICKOFF, OUR_CORNER, OPP_CORNER, DROPBALL, START = 1, 2, 9, 10, 13, 15


def state(t, running, attack=(1, -1)):
    return ma.RefereeState(t, ("nubot", "rival"), (0, 0), attack, 1, t, running, "")


def still(name, x, y, end=60.0):
    t = np.array([0.0, end])
    return ma.Track(name, t, np.array([[x, y], [x, y]]))


TRACKS = {t.name: t for t in (still("nubot1", -8.5, 0.0), still("nubot2", 2.0, 1.0), still("nubot3", 6.0, -1.0),
                              still("rival1", 8.6, 0.3), still("rival2", 7.0, 0.0), still("rival3", 4.0, 3.0),
                              still("rival4", 0.0, -4.0))}


def shot_at_goal(t, robot="nubot3", xy=(6.0, -1.0), aim_y=0.0, speed=8.0, kind=-1):
    """A kick from ``xy`` towards (9, aim_y) at ``speed`` (a lob: 3 m/s upwards too)."""
    dx, dy = 9.0 - xy[0], aim_y - xy[1]
    d = math.hypot(dx, dy)
    return ma.Kick(t, robot, kind, (speed * dx / d, speed * dy / d, 3.0 if kind == 1 else 0.0), xy)


def explain(kicks=(), touches=(), goals=(), referee=None, coach=(), end=60.0, goalies=None):
    log = ma.MatchLog(tracks=dict(TRACKS), kicks=list(kicks), touches=list(touches), goals=list(goals),
                      referee=list(referee if referee is not None else [state(0.0, False), state(1.0, True)]),
                      coach=list(coach), start=0.0, end=end, goalies=goalies or {})
    return match_shots.explain(ma.analyse(log, WORLD), log)


def goal(t, side=1, last="nubot3", height=0.11):
    return ma.Goal(t, side, (9.2 * side, 0.0), last, height)


def test_each_shot_outcome_follows_the_first_thing_that_happens_to_it():
    report = explain(
        kicks=[shot_at_goal(5.0), shot_at_goal(10.0), shot_at_goal(15.0), shot_at_goal(20.0, aim_y=2.0),
               shot_at_goal(25.0), shot_at_goal(30.0)],
        touches=[ma.Touch(5.5, "rival1"), ma.Touch(10.4, "rival2"), ma.Touch(25.5, "nubot2"), ma.Touch(30.3, "rival2")],
        goals=[goal(30.5, last="rival2")])
    assert [(s.t, s.outcome, s.by, s.on_target) for s in report.shots] == [
        (5.0, "saved", "rival1", True),  # the goalie (AgentID 1 without a GOALIE announced) touched it first
        (10.0, "blocked", "rival2", True),
        (15.0, "wide", "", True),  # nothing touched it again before the recording ended
        (20.0, "wide", "", False),  # 0.8 m outside the post: a shot, off target
        (25.0, "wide", "nubot2", True),  # a teammate got it
        (30.0, "goal", "", True)]  # a defender deflected it in: still the shot's goal
    assert report.shot_counts()["nubot"] == {"shots": 6, "on_target": 5, "goal": 1, "saved": 1, "blocked": 1,
                                             "wide": 3, "disallowed": 0}
    anatomy, = report.goals
    assert (anatomy.scorer, anatomy.own_goal, anatomy.shot.t) == ("nubot3", False, 30.0)


def test_a_shot_into_the_goal_the_referee_disallowed_is_no_goal():
    calls = [ma.Call(5.53, "goal_disallowed", "nubot", "nubot3", "goal kick for rival", (9.2, 0.0), "RC-10.1.1")]
    log = ma.MatchLog(tracks=dict(TRACKS), kicks=[shot_at_goal(5.0)], goals=[goal(5.5)], calls=calls,
                      referee=[state(0.0, False), state(1.0, True)], start=0.0, end=60.0)
    summary = ma.analyse(log, WORLD)
    report = match_shots.explain(summary, log)
    assert summary.score == {"nubot": 0, "rival": 0} and len(summary.goals_disallowed) == 1
    assert [s.outcome for s in report.shots] == ["disallowed"] and report.goals == []


def test_kicks_far_wide_or_backwards_are_passes_not_shots():
    report = explain(kicks=[shot_at_goal(5.0, aim_y=2.3), ma.Kick(9.0, "nubot3", -1, (-5.0, 0.0, 0.0), (6.0, -1.0))])
    assert report.shots == []


def test_a_lob_over_the_bar_is_off_target_and_one_under_it_on_target():
    # 0.67 s to the line from x = 5 m: the centre is 0.60 m up at 4 m/s upwards, 1.27 m at 5 m/s (the bar: 1 m)
    low = ma.Kick(5.0, "nubot3", 1, (6.0, 0.0, 4.0), (5.0, 0.0))
    high = ma.Kick(9.0, "nubot3", 1, (6.0, 0.0, 5.0), (5.0, 0.0))
    assert [s.on_target for s in explain(kicks=[low, high]).shots] == [True, False]


def test_the_kickers_own_touch_right_after_its_kick_is_the_kick():
    # rival2 touched the held ball last, so the simulator reports nubot3's kick as a touch one step later
    report = explain(kicks=[shot_at_goal(5.0)], touches=[ma.Touch(4.0, "rival2"), ma.Touch(5.005, "nubot3")],
                     goals=[goal(5.6)])
    assert report.shots[0].outcome == "goal"
    assert report.goals[0].scorer == "nubot3"


def test_the_goalie_is_the_one_the_log_names():
    report = explain(kicks=[shot_at_goal(5.0)], touches=[ma.Touch(5.5, "rival2")], goalies={"rival": "rival2"})
    assert (report.shots[0].outcome, report.goalies) == ("saved", {"nubot": "nubot1", "rival": "rival2"})


def test_an_own_goal_without_a_shot_names_the_defender():
    report = explain(touches=[ma.Touch(5.0, "nubot3"), ma.Touch(6.0, "rival2")], goals=[goal(7.0, last="rival2")])
    anatomy, = report.goals
    assert (anatomy.own_goal, anatomy.scorer, anatomy.cause, anatomy.shot) == (True, "rival2", "own goal", None)


def test_a_goal_from_the_teams_own_restart_is_a_set_piece_and_the_pass_an_assist():
    coach = [ma.CoachCommand(0.5, "nubot", OUR_CORNER), ma.CoachCommand(0.5, "rival", OPP_CORNER),
             ma.CoachCommand(1.0, "nubot", START), ma.CoachCommand(1.0, "rival", START)]
    kicks = [ma.Kick(2.0, "nubot2", -1, (4.0, -2.0, 0.0), (2.0, 1.0)), shot_at_goal(5.0)]
    report = explain(kicks=kicks, touches=[ma.Touch(1.5, "nubot2"), ma.Touch(3.0, "nubot3")], goals=[goal(5.5)],
                     coach=coach)
    anatomy, = report.goals
    assert (anatomy.cause, anatomy.scorer, anatomy.assist) == ("set piece", "nubot3", "nubot2")
    # the same play after the opponents' restart, which they lost at once: a turnover
    coach = [ma.CoachCommand(0.5, "nubot", OPP_CORNER), ma.CoachCommand(0.5, "rival", OUR_CORNER),
             ma.CoachCommand(1.0, "nubot", START), ma.CoachCommand(1.0, "rival", START)]
    report = explain(kicks=kicks, touches=[ma.Touch(1.2, "rival3"), ma.Touch(1.5, "nubot2"), ma.Touch(3.0, "nubot3")],
                     goals=[goal(5.5)], coach=coach)
    assert report.goals[0].cause == "turnover"


def test_a_second_shot_soon_after_a_save_is_a_rebound():
    report = explain(kicks=[shot_at_goal(5.0), shot_at_goal(7.0, robot="nubot2", xy=(7.0, 1.0))],
                     touches=[ma.Touch(2.0, "nubot3"), ma.Touch(5.4, "rival1"), ma.Touch(6.5, "nubot2")],
                     goals=[goal(7.4, last="nubot2")])
    anatomy, = report.goals
    assert (anatomy.cause, anatomy.scorer, anatomy.shot.t) == ("rebound", "nubot2", 7.0)


def test_three_changes_of_toucher_by_both_teams_just_before_the_goal_are_a_scramble():
    touches = [ma.Touch(2.0, "nubot3"), ma.Touch(8.0, "rival2"), ma.Touch(8.5, "nubot2"), ma.Touch(9.0, "rival3"),
               ma.Touch(9.5, "nubot3")]
    assert explain(touches=touches, goals=[goal(10.0)]).goals[0].cause == "scramble"
    # two changes only: the ball was won back from rival3 at 9.5 s, a turnover
    assert explain(touches=[touches[0], touches[3], touches[4]], goals=[goal(10.0)]).goals[0].cause == "turnover"
    # won 12 s before the goal and kept since: a build-up
    assert explain(touches=[ma.Touch(2.0, "rival2"), ma.Touch(3.0, "nubot3"), ma.Touch(9.0, "nubot2"),
                            ma.Touch(14.0, "nubot3")], goals=[goal(15.0)]).goals[0].cause == "build-up"


def test_goalie_and_nearest_defenders_are_measured_from_the_shots_line():
    anatomy, = explain(kicks=[shot_at_goal(5.0)], goals=[goal(5.5)]).goals
    # the line from (6, -1) to (9, 0): rival1 at (8.6, 0.3) 0.41 m off, rival2 at (7, 0) 0.63 m, rival3 far
    assert anatomy.goalie.robot == "rival1"
    assert anatomy.goalie.line_distance == pytest.approx(0.411, abs=1e-3)
    assert [d.robot for d in anatomy.defenders] == ["rival2", "rival3"]
    assert anatomy.defenders[0].line_distance == pytest.approx(0.632, abs=1e-3)
    assert anatomy.height == 0.11
    line, = match_shots.goal_lines(explain(kicks=[shot_at_goal(5.0)], goals=[goal(5.5)]))
    assert "nubot3; flat 8.0 m/s from (+6.0, -1.0) attacking +x, 3.2 m out, 0.11 m high at the line" in line


def test_goalies_by_role_takes_each_teams_most_announced():
    assert ma.goalies_by_role({"nubot1": 5, "nubot2": 90, "rival3": 12, "rival1": 0}) == {"nubot": "nubot2",
                                                                                          "rival": "rival3"}


def test_the_shot_map_is_drawn_per_team(tmp_path):
    report = explain(kicks=[shot_at_goal(5.0), shot_at_goal(9.0, kind=1)], goals=[goal(5.5)])
    match_plots.plot_shot_map(report.shots, report.teams, WORLD.field, tmp_path / "shots.png")
    data = (tmp_path / "shots.png").read_bytes()
    assert data.startswith(b"\x89PNG") and len(data) > 10_000
    assert report.to_json()["counts"]["nubot"]["shots"] == 2
