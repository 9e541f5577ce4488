"""The strategy in an in-process match (simulator core, no ROS): kickoff, set pieces, open play."""

import math

import pytest

from nubot_common.match_mode import MatchMode
from nubot_control.roles import Role

TEAMS = [("nubot1", -8.4, 0, 0), ("nubot2", -1.0, 0, 0), ("nubot3", -3, 2.5, 0), ("nubot4", -3, -2.5, 0),
         ("nubot5", -5.5, 0, 0), ("rival1", 8.4, 0, math.pi), ("rival2", 1.0, 0, math.pi),
         ("rival3", 3, -2.5, math.pi), ("rival4", 3, 2.5, math.pi), ("rival5", 5.5, 0, math.pi)]


def test_kickoff_formation_then_the_static_pass(make_match):
    match = make_match(TEAMS)
    match.command("nubot", MatchMode.OUR_KICKOFF)
    match.run(4.0)
    for name in ("rival2", "rival3", "rival4", "rival5"):
        s = match.sim.world.robot_state(name)
        assert s.x > 0.0 and math.hypot(s.x, s.y) > 2.0, f"{name} respects the opponent kickoff"
    taker = next(n for n, o in match.outputs.items() if o.role == Role.PASSOFPASS)
    receiver = next(n for n, o in match.outputs.items() if o.role == Role.CATCHOFPASS)
    assert taker.startswith("nubot") and receiver.startswith("nubot")
    match.command("nubot", MatchMode.STARTROBOT)
    kicks = []
    for _ in range(200):
        match.run(0.05)
        if match.sim.holder is not None and match.sim.holder != taker:
            kicks.append(match.sim.holder)
            break
    assert kicks and kicks[0] == receiver, "the kickoff pass reaches the receiver"


def test_a_short_match_moves_the_ball_and_everyone_keeps_a_role(make_match):
    match = make_match(TEAMS, mode=MatchMode.STARTROBOT)
    match.command("nubot", MatchMode.STARTROBOT)
    positions = []
    for _ in range(30):
        match.run(1.0)
        b = match.sim.world.ball_state()
        positions.append((b.x, b.y))
    travelled = sum(math.dist(a, b) for a, b in zip(positions, positions[1:]))
    assert travelled > 15.0
    for team in ("nubot", "rival"):
        roles = [o.role for n, o in match.outputs.items() if n.startswith(team)]
        assert roles.count(Role.GOALIE) == 1 and roles.count(Role.ACTIVE) <= 2


def test_stop_halts_every_robot(make_match):
    match = make_match(TEAMS)
    match.command("nubot", MatchMode.STARTROBOT)
    match.run(2.0)
    match.command("nubot", MatchMode.STOPROBOT)
    match.run(1.5)
    for name in match.strategies:
        s = match.sim.world.robot_state(name)
        assert math.hypot(s.vx, s.vy) < 0.05, f"{name} still moves"


def test_the_midfielder_marks_an_opponent_lurking_in_our_half():
    from nubot_common.geometry import Pose2D
    from nubot_control.behaviours import Action
    from nubot_control.params import ControlParams
    from nubot_control.strategy import Strategy
    from nubot_control.team_state import Ball, Mate, TeamState

    # With the ball at (4, 0) the support spots are: passive (-3.2, 0), assistant (6.5, 3), midfield (1.5, -2.5).
    mates = (Mate(1, Pose2D(-8.5, 0, 0)), Mate(2, Pose2D(3.5, 0, 0)), Mate(3, Pose2D(6, 3, 0)),
             Mate(5, Pose2D(-3, 0, 0)))
    me = Mate(4, Pose2D(1.5, -2.4, 0))
    lurker = (-5.0, -2.0)
    state = TeamState(1.0, me, mates, Ball(4.0, 0.0), (lurker, (5.0, 1.0)), MatchMode.STARTROBOT)
    out = Strategy(ControlParams(), 4).step(state)
    assert out.role == Role.MIDFIELD and out.action == Action.MARK
    # Between the lurker and the own goal, 1 m from the lurker.
    assert math.dist(out.target, lurker) == pytest.approx(1.0)
    assert -9.0 < out.target[0] < lurker[0]


@pytest.mark.parametrize("mode", [MatchMode.OUR_THROWIN, MatchMode.OPP_THROWIN])
def test_robots_walking_into_a_set_play_formation_do_not_push_the_ball(make_match, mode):
    # Everyone starts inside the field of a ball placed on the side line; the taker's spot is beyond it.
    robots = [("nubot1", -8.4, 0, 0), ("nubot2", 2.0, 5.0, 0), ("nubot3", 2.0, 3.5, 0), ("nubot4", 1.0, 4.5, 0),
              ("nubot5", 3.0, 4.2, 0)]
    match = make_match(robots, ball=(0.0, 5.9))
    match.command("nubot", mode)
    match.run(6.0)
    ball = match.sim.world.ball_state()
    assert math.hypot(ball.x, ball.y - 5.9) < 0.05, "the placed ball stays where the referee put it"
    if mode == MatchMode.OUR_THROWIN:
        name = next(n for n, out in match.outputs.items() if out.role == Role.PASSOFPASS)
        taker = match.sim.world.robot_state(name)
        assert math.hypot(taker.x - ball.x, taker.y - ball.y) < 0.7, "the taker reached its spot at the ball"
