"""Unit tests of the automatic referee (coach4sim.referee) on hand-made situations, 18 x 12 m field."""

import pytest

from coach4sim.referee import GoalSeen, Phase, RefereeInputs
from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode


def restart_for(team: str, name: str) -> dict:
    """Both teams' commands when ``team`` gets the set piece ``name`` (e.g. THROWIN)."""
    other = "rival" if team == "nubot" else "nubot"
    return {team: f"OUR_{name}", other: f"OPP_{name}"}


def test_the_match_starts_with_a_kickoff_for_the_first_team_and_startrobot_after_setup_time(match):
    decision = match.step()
    assert match.modes() == restart_for("nubot", "KICKOFF")
    assert decision.ball == (0.0, 0.0)
    assert "kickoff for nubot" in decision.event and match.game.half == 1
    assert match.run(3.75) == [], "nothing before setup_time"
    assert not match.game.running
    start = match.step(0.25)
    assert start.commands == (("nubot", MatchMode.STARTROBOT), ("rival", MatchMode.STARTROBOT))
    assert start.ball is None and match.game.running
    assert match.game.status("nubot").previous.name == "OUR_KICKOFF"


def test_a_ball_pushed_off_its_spot_during_the_setup_goes_back_at_startrobot(match):
    match.step()
    match.run(2.0)
    match.ball = (1.2, -0.4, 0.11)  # a robot walked into it
    match.run(1.75)
    start = match.step(0.25)
    assert start.commands[0][1] is MatchMode.STARTROBOT
    assert start.ball == (0.0, 0.0) and "goes back to its spot" in start.event
    match.ball = (0.0, 0.0, 0.11)
    match.run(2.0)
    assert match.referee.restart_pending, "the replaced ball has not been played yet"


def test_the_ball_is_judged_only_once_the_simulator_shows_it_back_on_its_spot(match):
    match.step()
    match.run(2.0)
    match.ball = (3.0, 6.3, 0.11)  # pushed over the side line during the kickoff setup
    match.run(1.75)
    assert match.step(0.25).ball == (0.0, 0.0)
    match.ball = (3.0, 6.3, 0.11)  # the simulator has not applied the placement yet
    assert match.step(0.05) is None, "no throw-in for where the ball was before it was put back"
    match.ball = (0.0, 0.0, 0.11)
    assert match.run(2.0) == [] and match.game.running
    match.ball = (3.0, 6.3, 0.11)
    assert "throw-in" in match.step(0.25, last_touch="nubot2").event, "later the lines count again"


def test_a_ball_still_on_its_spot_is_left_alone_at_startrobot(match):
    match.step()
    match.ball = (0.1, 0.05, 0.11)
    match.run(3.75)
    assert match.step(0.25).ball is None


@pytest.mark.parametrize(("ball", "toucher", "team", "spot"), [
    ((3.0, 6.2), "nubot1", "rival", (3.0, 5.9)),  # over y = +6, nubot touched last
    ((3.0, 6.2), "rival4", "nubot", (3.0, 5.9)),
    ((-8.7, -6.3), "rival2", "nubot", (-8.0, -5.9)),  # over y = -6, x clamped 1 m inside the goal line
    ((-8.7, -6.3), "nubot5", "rival", (-8.0, -5.9)),
])
def test_throw_in_goes_to_the_team_that_did_not_touch_last(match, ball, toucher, team, spot):
    match.kickoff_and_play()
    match.ball = (*ball, 0.11)
    decision = match.step(0.25, last_touch=toucher)
    assert match.modes() == restart_for(team, "THROWIN")
    assert decision.ball == pytest.approx(spot)
    assert f"throw-in for {team}" in decision.event and toucher in decision.event
    assert match.game.last_event == decision.event


def test_a_ball_on_the_side_line_is_still_in(match):
    match.kickoff_and_play()
    match.ball = (0.0, 6.0 + 0.11 - 0.01, 0.11)  # centre beyond the line, but not the whole ball
    assert match.step(0.25, last_touch="nubot1") is None
    assert match.game.running


@pytest.mark.parametrize(("ball", "toucher", "mode", "team", "spot"), [
    ((9.2, 3.0, 0.11), "nubot1", "GOALKICK", "rival", (7.25, 1.75)),  # attacker of +x played it out
    ((9.2, 3.0, 0.11), "rival1", "CORNERKICK", "nubot", (8.75, 5.75)),  # defender of +x played it out
    ((-9.3, -2.0, 0.11), "rival1", "GOALKICK", "nubot", (-7.25, -1.75)),
    ((-9.3, -2.0, 0.11), "nubot2", "CORNERKICK", "rival", (-8.75, -5.75)),
    ((9.3, 0.0, 1.5), "nubot3", "GOALKICK", "rival", (7.25, 1.75)),  # over the bar
])
def test_goal_line_gives_a_goal_kick_or_a_corner_by_last_touch(match, ball, toucher, mode, team, spot):
    match.kickoff_and_play()
    match.ball = ball
    decision = match.step(0.25, last_touch=toucher)
    assert match.modes() == restart_for(team, mode)
    assert decision.ball == pytest.approx(spot)
    assert match.game.state().score == (0, 0)


def test_goal_scores_and_the_conceding_team_kicks_off_from_the_centre(match):
    match.kickoff_and_play()
    match.ball = (9.3, 0.2, 0.11)
    decision = match.step(0.25, goals=(GoalSeen(1, "nubot1"),))
    assert match.game.state().score == (1, 0)
    assert match.modes() == restart_for("rival", "KICKOFF")
    assert decision.ball == (0.0, 0.0)
    assert "goal for nubot" in decision.event and "kickoff for rival" in decision.event
    match.step(0.25, goals=(GoalSeen(1, "nubot1"),))  # a late duplicate while the teams set up
    assert match.game.state().score == (1, 0)


def test_own_goal_counts_for_the_other_team(match):
    match.kickoff_and_play()
    match.ball = (-9.3, 0.0, 0.11)
    match.step(0.25, goals=(GoalSeen(-1, "nubot2"),))
    assert match.game.state().score == (0, 1)
    assert match.modes() == restart_for("nubot", "KICKOFF")


def test_goal_is_seen_by_geometry_before_the_simulator_reports_it(match):
    match.kickoff_and_play()
    match.ball = (-9.2, 0.5, 0.3)
    decision = match.step(0.25, last_touch="rival1")
    assert match.game.state().score == (0, 1)
    assert "kickoff for nubot" in decision.event


@pytest.mark.parametrize(("shot", "goals"), [
    ((-8.0, 0.95, 0.44, -5.08, 0.68, 2.13), 1),  # a lob that grazes a post on its way in
    ((-8.0, 1.02, 0.26, -7.1, 0.49, 2.01), 1),
    ((-8.0, 0.0, 0.11, -6.0, 0.0, 0.0), 1),
    ((-8.0, 2.0, 0.11, -6.0, 0.0, 0.0), 0),  # wide of the post
    ((-8.0, 0.0, 1.3, -6.0, 0.0, 1.0), 0),  # over the bar
])
def test_on_the_simulator_s_states_alone_the_referee_scores_what_the_simulator_scores(match, shot, goals):
    """Its goal events may come late over ROS: judged on the 100 Hz states alone the referee must agree with the
    simulator's goals, or the two would tell different scores."""
    from sim_visual.params import SimConfig
    from sim_visual.simulator import GoalScored, Simulator
    from sim_visual.world import BallState

    match.kickoff_and_play()
    sim = Simulator(SimConfig(robots=(), ball_start=(0.0, 0.0)))
    sim.world.set_ball_state(BallState(*shot))
    simulated, decision = [], None
    while decision is None and sim.time < 1.5:
        simulated += [e for e in sim.step() + sim.step() if isinstance(e, GoalScored)]  # two 5 ms steps
        b = sim.world.ball_state()
        match.ball = (b.x, b.y, b.z)
        decision = match.step(0.01, last_touch="nubot1")
    assert [g.side for g in simulated] == [-1] * goals
    assert match.game.state().score == (0, goals)
    if goals:
        assert "goal for rival" in decision.event
    else:
        assert "ball out over the goal line" in decision.event


def test_a_ball_far_beyond_the_goal_line_in_line_with_the_goal_is_out_not_a_goal(match):
    match.kickoff_and_play()
    match.ball = (50.0, 0.0, 0.11)
    decision = match.step(0.25, last_touch="nubot2")
    assert match.game.state().score == (0, 0)
    assert "goal kick for rival" in decision.event


def test_out_with_no_known_toucher_is_a_dropped_ball_inside_the_field(match):
    match.kickoff_and_play()
    match.ball = (8.9, -6.4, 0.11)
    decision = match.step(0.25, last_touch="")
    assert match.modes() == {"nubot": "DROPBALL", "rival": "DROPBALL"}
    assert decision.ball == pytest.approx((8.0, -5.0))


def test_contested_ball_that_does_not_move_is_dropped(match):
    match.kickoff_and_play()
    match.ball = (8.7, 1.0, 0.11)
    match.robots = {"nubot1": (8.0, 0.6), "rival1": (8.9, 1.6)}  # the attacker just out of the goal area
    start, drops = match.time, []
    for i in range(30):  # 7.5 s with the ball jiggling by 0.1 m
        match.ball = (8.7 + 0.1 * (i % 2), 1.0, 0.11)
        decision = match.step(0.25)
        if decision is not None:
            drops.append((match.time - start, decision))
    assert len(drops) == 1
    after, drop = drops[0]
    assert after == pytest.approx(5.25), "stuck_time 5 s after the first look at the contested ball"
    assert match.modes() == {"nubot": "DROPBALL", "rival": "DROPBALL"}
    assert drop.ball == pytest.approx((8.0, 1.0)), "clamped 1 m inside the goal line"
    assert "stuck" in drop.event


def test_ball_near_one_team_only_is_not_stuck(match):
    match.kickoff_and_play()
    match.ball = (1.0, 1.0, 0.11)
    match.robots = {"nubot1": (1.5, 1.0), "nubot2": (0.5, 1.0), "rival1": (4.0, 1.0)}
    assert match.run(8.0) == []
    match.robots["rival1"] = (1.0, 1.8)
    assert match.run(5.0) == [], "stuck_time counts from the first look at the contested ball"
    assert match.step(0.25).event.startswith("ball stuck")


def test_moving_contested_ball_is_not_stuck(match):
    match.kickoff_and_play()
    match.robots = {"nubot1": (0.0, 0.0), "rival1": (0.0, 0.0)}
    for i in range(40):
        match.ball = (0.2 * i, 0.0, 0.11)
        match.robots = {"nubot1": (0.2 * i - 0.5, 0.0), "rival1": (0.2 * i + 0.5, 0.0)}
        assert match.step(0.25) is None


def test_a_set_piece_not_taken_in_7_s_lets_the_opponents_play_and_one_nobody_plays_is_dropped(match):
    match.kickoff_and_play()
    match.ball = (2.0, 6.5, 0.11)
    match.step(0.25, last_touch="nubot1")  # throw-in for rival
    match.ball = (2.0, 5.9, 0.11)
    assert [d.commands[0][1].name for d in match.run(4.0)] == ["STARTROBOT"]
    assert match.referee.restart_pending
    assert match.step(0.25, touches=("nubot2",)) is None, "the other team's touch does not take it"
    assert match.run(6.5) == []
    slow = match.step(0.25)  # 7 s after STARTROBOT: a call, and play goes on (RC-13)
    assert slow.ball is None and match.modes() == {"nubot": "STARTROBOT", "rival": "STARTROBOT"}
    call, = slow.calls
    assert (call.kind, call.team, call.restart) == ("slow_restart", "rival", "")
    assert "rival did not take the throw-in within 7 s" in slow.event
    assert match.run(12.75) == []
    late = match.step(0.25)  # 20 s and still nobody played it: the game is stuck
    assert match.modes() == {"nubot": "DROPBALL", "rival": "DROPBALL"}
    assert "nobody played the throw-in within 20 s" in late.event
    assert late.ball == pytest.approx((2.0, 5.0))


def test_after_7_s_the_opponents_touch_puts_the_ball_in_play(match):
    match.kickoff_and_play()
    match.ball = (2.0, 6.5, 0.11)
    match.step(0.25, last_touch="nubot1")
    match.ball = (2.0, 5.9, 0.11)
    match.run(4.0)
    match.run(7.0)
    assert match.referee.restart_pending
    match.step(0.25, touches=("nubot2",))
    assert not match.referee.restart_pending


@pytest.mark.parametrize("taken", [{"touches": ("rival3",)}, {"kicks": ("rival3",)}, {"ball": (2.0, 5.2, 0.11)}])
def test_set_piece_taken_by_the_restart_team_is_play_on(match, taken):
    match.kickoff_and_play()
    match.ball = (2.0, 6.5, 0.11)
    match.step(0.25, last_touch="nubot1")
    match.ball = (2.0, 5.9, 0.11)
    match.run(4.0)
    match.ball = taken.pop("ball", match.ball)
    assert match.step(0.25, **taken) is None
    assert not match.referee.restart_pending
    assert match.run(16.0) == [] and match.game.running


def test_game_clock_stops_while_the_teams_set_up(match):
    match.kickoff_and_play()
    match.run(2.0)
    clock = match.game.game_time
    match.ball = (0.0, -6.5, 0.11)
    match.step(0.25, last_touch="rival1")
    match.run(3.75)
    assert match.game.game_time == pytest.approx(clock + 0.25)


@pytest.mark.parametrize("switch", [True, False])
def test_end_of_each_half_stops_the_robots_and_the_second_half_starts_with_the_other_kickoff(make_match, switch):
    match = make_match(half_duration=20.0, half_time_break=5.0, switch_ends=switch)
    match.kickoff_and_play()  # the clock runs since STARTROBOT at t = 4 s; now t = 4.5 s
    decisions = match.run(19.25)
    assert decisions == [] and match.game.running
    stop = match.step(0.25)
    assert stop.commands == (("nubot", MatchMode.STOPROBOT), ("rival", MatchMode.STOPROBOT))
    change = "; the teams change ends" if switch else ""
    assert stop.event == f"end of the first half (nubot 0, rival 0){change}"
    assert stop.switch_ends is switch, "the node turns the simulated field round on this"
    assert match.game.state().attack == ((-1, 1) if switch else (1, -1))
    assert match.game.game_time == pytest.approx(20.0)
    assert match.referee.phase is Phase.HALF_TIME
    assert match.run(4.75) == [], "half_time_break 5 s"
    second = match.step(0.25)
    assert match.game.half == 2 and match.game.game_time == 0.0
    assert match.modes() == restart_for("rival", "KICKOFF") and second.ball == (0.0, 0.0)
    assert not second.switch_ends
    match.run(4.0)
    match.step(0.25, touches=("rival1",))
    match.ball = (9.3, 0.0, 0.11)
    match.step(0.25, goals=(GoalSeen(1, "nubot4"),))  # the goal at +x: rival's target after the change
    match.run(4.0)
    match.step(0.25, touches=("nubot2" if switch else "rival2",))  # the conceding team takes the kickoff
    decisions = match.run(20.0)
    score = "nubot 0, rival 1" if switch else "nubot 1, rival 0"
    assert decisions[-1].event == f"end of the match ({score})" and not decisions[-1].switch_ends
    assert match.referee.phase is Phase.FINISHED
    match.ball = (0.0, 7.0, 0.11)
    assert match.run(30.0) == [], "nothing after the match"
    assert match.game.half == 2


def test_after_the_change_of_ends_goal_line_restarts_follow_the_new_sides(make_match):
    match = make_match(half_duration=5.0, half_time_break=1.0)
    match.kickoff_and_play()
    match.run(5.0)
    assert match.game.half == 1 and match.referee.phase is Phase.HALF_TIME
    match.run(1.0)
    match.run(4.25)  # the second half's kickoff and STARTROBOT
    match.step(0.25, touches=("rival1",))
    match.ball = (9.3, 3.0, 0.11)  # over the +x goal line; nubot now defends +x
    decision = match.step(0.25, last_touch="rival3")
    assert match.modes() == restart_for("nubot", "GOALKICK"), decision.event
    assert decision.ball == pytest.approx((7.25, 1.75))


def test_unknown_manual_command_is_refused_and_nothing_changes(match):
    match.kickoff_and_play()
    before, phase = match.game.state(), match.referee.phase
    with pytest.raises(NubotCommonError, match="unknown MatchMode 14"):
        match.referee.manual_command("nubot", "14", match.time)
    with pytest.raises(NubotCommonError, match="unknown team 'blue'"):
        match.referee.manual_command("blue", "STOPROBOT", match.time)
    assert match.game.state() == before and match.referee.phase is phase


def test_manual_stop_holds_the_referee_until_a_manual_restart(match):
    match.kickoff_and_play()
    text = match.referee.manual_command("rival", "STOPROBOT", match.time)
    assert text == "by hand: STOPROBOT" and match.game.last_event == text
    match.ball = (0.0, 7.0, 0.11)
    assert match.run(20.0) == [], "stopped by hand: no automatic decisions"
    match.ball = (1.0, 1.0, 0.11)
    match.referee.manual_command("rival", "OUR_FREEKICK", match.time)
    assert match.modes() == restart_for("rival", "FREEKICK")
    assert match.run(3.75) == []
    assert match.step(0.25).commands[0][1].name == "STARTROBOT"
    assert match.referee.restart_pending
    assert "rival did not take the free kick" in match.run(12.0)[-1].event


def test_manual_startrobot_during_setup_starts_play_at_once(match):
    match.step()
    match.referee.manual_command("nubot", 15, match.time + 1.0)
    assert match.game.running and match.referee.restart_pending
    assert match.game.status("nubot").previous.name == "OUR_KICKOFF"


def test_on_the_22_by_14_field_the_lines_are_its_lines(make_match):
    """A ball at y = 6.5 is out on the chapter's 18 x 12 field, in play on the current 22 x 14 one."""
    from nubot_common.world_description import load_world

    big = make_match(world=load_world("22x14"))
    big.kickoff_and_play()
    big.ball = (9.5, 6.5, 0.11)
    assert big.run(1.0) == [], "inside the 22 x 14 lines"
    big.ball = (0.0, 7.3, 0.11)
    throw_in = big.step(0.25, last_touch="rival2")
    assert "throw-in for nubot" in throw_in.event and throw_in.ball[1] == pytest.approx(7.0 - 0.1)
    big.kickoff_and_play()
    big.ball = (11.3, 3.0, 0.11)
    assert "goal kick" in big.step(0.25, last_touch="nubot2").event, "the goal line is at x = 11"

    small = make_match()
    small.kickoff_and_play()
    small.ball = (0.0, 6.5, 0.11)
    assert "throw-in" in small.step(0.25, last_touch="rival2").event


def test_a_half_whose_play_keeps_stopping_still_ends(make_match):
    """The game clock runs only in play: a half stopped again and again ends at half_limit_factor half lengths."""
    match = make_match(half_duration=20.0, half_time_break=5.0, half_limit_factor=3.0)
    match.kickoff_and_play()
    ends = []
    for _ in range(80):  # a foul every second: two robots of rival in their own penalty area, play stops
        match.robots = {"rival2": (7.0, 2.0), "rival3": (7.2, -2.0)}
        decision = match.step(1.0)
        if decision is not None and decision.commands[0][1].name == "STOPROBOT":
            ends.append(match.time)
            break
    assert ends and ends[0] == pytest.approx(3.0 * 20.0 + 5.0, abs=1.0)
    assert match.game.game_time < 20.0


def test_the_inputs_hand_over_what_happened_once_and_remember_the_last_touch_and_holder():
    inputs = RefereeInputs()
    inputs.touch("nubot2")
    inputs.kick("nubot3")
    inputs.goal(1, "nubot3")
    inputs.holder = "rival1"
    first = inputs.snapshot(4.0, (1.0, 2.0, 0.11), {"nubot3": (0.5, 0.5)})
    assert (first.time, first.ball, dict(first.robots)) == (4.0, (1.0, 2.0, 0.11), {"nubot3": (0.5, 0.5)})
    assert (first.touches, first.kicks, first.goals) == (("nubot2",), ("nubot3",), (GoalSeen(1, "nubot3"),))
    assert (first.last_touch, first.holder) == ("nubot3", "rival1"), "the kicker touched it last"
    second = inputs.snapshot(4.1, (1.0, 2.0, 0.11), {})
    assert (second.touches, second.kicks, second.goals) == ((), (), ()), "each event reaches the referee once"
    assert (second.last_touch, second.holder) == ("nubot3", "rival1"), "who touched and holds it stays known"
