"""Unit tests of the MSL fouls and goal conditions the automatic referee calls (coach4sim.fouls, docs/rules.md), on
hand-made snapshots of the 18 x 12 m field: nubot attacks +x, rival -x, each team's goalie is robot 1."""

import pytest

from coach4sim.fouls import in_penalty_area, restart_spot
from coach4sim.referee import GoalSeen
from nubot_common.field import FieldGeometry

FIELD = FieldGeometry()  # penalty areas from |x| = 6.75 m, |y| <= 3.25 m; goal areas from |x| = 8.25, |y| <= 1.75


def carry(match, path, holder="nubot2", dt=0.1):
    """``holder`` holds the ball and drives along ``path`` (ball positions): the decisions taken."""
    decisions = []
    for x, y in path:
        match.ball = (x, y, 0.11)
        match.robots = {**match.robots, holder: (x - 0.43, y)}
        decision = match.step(dt, holder=holder)
        if decision is not None:
            decisions.append(decision)
    return decisions


def straight(start, length, step=0.05):
    return [(start[0] + k * step, start[1]) for k in range(round(length / step) + 1)]


# --- carrying (RC-12.0.1) ---------------------------------------------------------------------------------------
@pytest.mark.parametrize(("length", "foul"), [(2.9, False), (3.1, True)])
def test_carrying_the_ball_more_than_3_m_from_where_it_was_caught(match, length, foul):
    match.kickoff_and_play()
    decisions = carry(match, straight((0.0, 1.0), length))
    if not foul:
        assert decisions == []
        return
    decision, = decisions
    call, = decision.calls
    assert (call.kind, call.team, call.robot, call.rule) == ("carrying", "nubot", "nubot2", "RC-12.0.1")
    assert match.modes() == {"nubot": "OPP_FREEKICK", "rival": "OUR_FREEKICK"}
    assert decision.ball == pytest.approx((3.05, 1.0)), "a free kick where the ball was, the first sample past 3 m"
    assert call.restart == "free kick for rival" and "carried the ball 3.05 m" in decision.event


def test_the_circle_moves_only_after_a_release_anyone_can_see(match):
    match.kickoff_and_play()
    assert carry(match, straight((0.0, 1.0), 2.5)) == []
    match.step(0.1)  # the dribbler lets go, but the ball stays at the robot: no release anyone could see
    assert carry(match, straight((2.55, 1.0), 0.6)) != [], "3.1 m from the first catch"


def test_a_release_and_a_new_catch_start_a_new_circle(match):
    match.kickoff_and_play()
    assert carry(match, straight((0.0, 1.0), 2.5)) == []
    match.ball = (3.4, 1.0, 0.11)  # pushed ahead: 1.3 m from the robot's centre
    match.step(0.1)
    assert carry(match, straight((3.4, 1.0), 2.5)) == []


# --- contact (RC-12.3.2) ----------------------------------------------------------------------------------------
def approach(match, mover, target, speed, seconds, dt=0.05):
    """``mover`` drives at ``speed`` towards ``target`` (which stands) for ``seconds``, stopping at its hull."""
    decisions = []
    for _ in range(round(seconds / dt)):
        (mx, my), (tx, ty) = match.robots[mover], match.robots[target]
        gap = ((tx - mx) ** 2 + (ty - my) ** 2) ** 0.5
        step = min(speed * dt, max(gap - 0.5, 0.0))  # it stops once its hull presses on the other's
        match.robots = {**match.robots, mover: (mx + step * (tx - mx) / gap, my + step * (ty - my) / gap)}
        decision = match.step(dt)
        if decision is not None:
            decisions.append(decision)
    return decisions


@pytest.mark.parametrize(("speed", "foul"), [(0.9, False), (1.1, True)])
def test_running_into_an_opponent_faster_than_1_m_s_is_charging(match, speed, foul):
    match.kickoff_and_play()
    match.robots = {"nubot2": (0.0, 3.0), "rival2": (1.5, 3.0)}
    decisions = approach(match, "nubot2", "rival2", speed, 1.2)
    calls = [c for d in decisions for c in d.calls]
    if not foul:
        assert calls == []
        return
    call, = calls
    assert (call.kind, call.team, call.robot) == ("charging", "nubot", "nubot2")
    assert match.modes() == {"nubot": "OPP_FREEKICK", "rival": "OUR_FREEKICK"}


@pytest.mark.parametrize(("speed", "foul"), [(0.1, False), (0.3, True)])
def test_driving_on_into_an_opponent_for_1_s_is_pushing(match, speed, foul):
    match.kickoff_and_play()
    match.robots = {"nubot2": (0.0, 3.0), "rival2": (0.53, 3.0)}  # in contact, standing
    calls = []
    for _ in range(30):  # 1.5 s: nubot2 keeps moving into rival2, which gives way
        (nx, ny), (rx, ry) = match.robots["nubot2"], match.robots["rival2"]
        match.robots = {"nubot2": (nx + speed * 0.05, ny), "rival2": (rx + speed * 0.05, ry)}
        decision = match.step(0.05)
        calls += decision.calls if decision is not None else []
    if not foul:
        assert calls == []
        return
    call, = calls
    assert (call.kind, call.robot) == ("pushing", "nubot2")
    assert "kept pushing rival2 for 1.0 s" in call.text


def test_pushing_in_the_own_penalty_area_gives_a_penalty_kick(match):
    match.kickoff_and_play()
    # rival defends the goal at +x: rival2 pushes nubot2 inside rival's penalty area
    match.robots = {"nubot2": (7.0, 0.0), "rival2": (7.53, 0.0), "rival1": (8.6, 0.0)}
    decisions = []
    for _ in range(30):
        (nx, ny), (rx, ry) = match.robots["nubot2"], match.robots["rival2"]
        match.robots = {**match.robots, "nubot2": (nx - 0.015, ny), "rival2": (rx - 0.015, ry)}
        decision = match.step(0.05)
        decisions += [decision] if decision is not None else []
    decision = decisions[0]
    assert decision.calls[0].kind == "pushing" and decision.calls[0].penalty
    assert match.modes() == {"nubot": "OUR_PENALTY", "rival": "OPP_PENALTY"}
    assert decision.ball == pytest.approx((FIELD.half_length - FIELD.penalty_mark_distance, 0.0))


# --- the penalty areas (RC-12.3.4, RC-12.3.5, RC-12.3.10) ------------------------------------------------------------
def test_the_goalie_and_one_defender_may_stay_in_their_penalty_area_a_second_defender_may_not(match):
    match.kickoff_and_play()
    match.robots = {"rival1": (8.6, 0.0), "rival2": (7.0, 2.0), "nubot2": (0.0, 0.0)}
    assert match.run(5.0) == []
    match.robots = {**match.robots, "rival3": (7.2, -2.0)}  # a third robot of rival in its own area
    decision = match.step(0.25)
    call, = decision.calls
    assert (call.kind, call.team, call.robot, call.rule) == ("illegal_defence", "rival", "rival3", "RC-12.3.4")
    assert match.modes() == {"nubot": "OUR_FREEKICK", "rival": "OPP_FREEKICK"}
    assert decision.ball == pytest.approx(restart_spot(*match.ball[:2], FIELD, 1.0))


def test_a_defender_may_stay_10_s_in_its_penalty_area(match):
    match.kickoff_and_play()
    match.robots = {"rival2": (7.0, 2.0), "nubot2": (0.0, 0.0)}
    assert match.run(10.0) == []
    call, = match.step(0.5).calls
    assert call.kind == "illegal_defence" and "for more than 10 s" in call.text


def test_two_attackers_in_the_opponents_penalty_area_are_illegal_attack(match):
    match.kickoff_and_play()
    match.robots = {"nubot2": (7.0, 2.0), "nubot3": (7.5, -1.0), "rival1": (8.6, 0.0)}
    call, = match.step(0.25).calls
    assert (call.kind, call.team) == ("illegal_attack", "nubot")


def test_an_attacker_in_the_opponents_goal_area_is_illegal_attack(match):
    match.kickoff_and_play()
    match.robots = {"nubot2": (8.4, 0.5), "rival1": (8.8, -0.5)}
    call, = match.step(0.25).calls
    assert (call.kind, call.robot, call.rule) == ("illegal_attack", "nubot2", "RC-12.3.10")


def test_a_robot_behind_its_own_goal_line_is_outside_the_field_not_in_its_areas(match):
    """A field robot trapped beside its own goal, behind the goal line, was called for illegal defence at every
    restart (84 times in one evaluation match): the areas end at the goal line."""
    match.kickoff_and_play()
    match.robots = {"nubot4": (-9.74, 1.56), "nubot3": (-9.3, -2.5), "rival1": (8.6, 0.0), "rival2": (0.0, 0.0)}
    assert match.run(12.0) == []
    match.robots = {**match.robots, "nubot4": (-9.0, 1.56)}  # on the goal line: in the goal area
    call, = match.step(0.25).calls
    assert (call.kind, call.robot, call.rule) == ("illegal_defence", "nubot4", "RC-12.3.10")


def test_a_free_kick_from_a_penalty_area_is_taken_from_the_nearest_restart_point():
    assert in_penalty_area(8.0, 1.0, -1, FIELD) and not in_penalty_area(8.0, 1.0, 1, FIELD)
    assert restart_spot(8.0, 1.0, FIELD, 1.0) == pytest.approx((6.0, 3.0))
    assert restart_spot(-7.5, -2.5, FIELD, 1.0) == pytest.approx((-6.0, -3.0))
    assert restart_spot(2.0, 5.8, FIELD, 1.0) == pytest.approx((2.0, 5.0))  # elsewhere: where the ball is


# --- the goals that count (RC-8.4.1, RC-8.6, RC-10.1.1, RC-13) --------------------------------------------------------
def kicked_off(match):
    match.step()
    match.run(4.0)
    assert match.game.running


def test_a_goal_straight_from_the_kickoff_does_not_count_and_the_other_team_kicks_off(match):
    kicked_off(match)
    match.step(0.25, touches=("nubot1",))
    match.ball = (9.3, 0.0, 0.11)
    decision = match.step(0.25, goals=(GoalSeen(1, "nubot1"),))
    assert match.game.state().score == (0, 0)
    assert match.modes() == {"nubot": "OPP_KICKOFF", "rival": "OUR_KICKOFF"}
    call, = decision.calls
    assert (call.kind, call.team, call.rule) == ("goal_disallowed", "nubot", "RC-8.4.1")


def test_after_a_second_robot_of_the_kicking_team_touched_the_ball_a_goal_counts(match):
    kicked_off(match)
    match.step(0.25, touches=("nubot1",))
    match.step(0.25, touches=("nubot2",))
    match.ball = (9.3, 0.0, 0.11)
    assert match.step(0.25, goals=(GoalSeen(1, "nubot2"),)).calls == ()
    assert match.game.state().score == (1, 0)


def test_a_goal_from_a_shot_in_the_own_half_does_not_count(match):
    match.kickoff_and_play()
    match.robots = {**match.robots, "nubot3": (-1.0, 2.0)}  # shoots from its own half
    match.step(0.25, kicks=("nubot3",))
    match.ball = (9.3, 0.0, 0.11)
    decision = match.step(0.25, goals=(GoalSeen(1, "nubot3"),))
    assert match.game.state().score == (0, 0)
    assert (decision.calls[0].kind, decision.calls[0].rule) == ("goal_disallowed", "RC-10.1.1")
    assert match.modes() == {"nubot": "OPP_GOALKICK", "rival": "OUR_GOALKICK"}


def test_a_goal_from_a_dropped_ball_needs_two_robots_to_have_touched_it(match):
    match.kickoff_and_play()
    match.referee.manual_command("nubot", "DROPBALL", match.time)
    match.run(4.0)
    match.step(0.25, touches=("nubot2",))
    match.ball = (9.3, 0.0, 0.11)
    match.step(0.25, goals=(GoalSeen(1, "nubot2"),))
    assert match.game.state().score == (0, 0)


def test_an_own_goal_counts(match):
    match.kickoff_and_play()
    match.step(0.25, touches=("rival2",))
    match.ball = (-9.3, 0.0, 0.11)
    match.step(0.25, goals=(GoalSeen(-1, "nubot1"),))
    assert match.game.state().score == (0, 1)


def test_fouls_false_calls_no_foul(make_match):
    match = make_match(fouls=False)
    match.kickoff_and_play()
    match.robots = {"rival2": (7.0, 2.0), "rival3": (7.2, -2.0)}
    assert match.run(12.0) == []
