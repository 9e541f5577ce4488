"""The RobotAgent and its control stage: what reaches the robot interface, and the world_model -> control seam."""

import gc
import math
import tracemalloc

import pytest

from nubot_common import conversions as conv
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import MatchMode
from nubot_common.naming import RobotName
from nubot_common.percepts import BallPercept, RobotReport, RobotView
from nubot_common.team_play import Role, StrategyReport
from nubot_common.world_description import WorldDescription
from nubot_control.agent import DRIBBLE_RETRY, Controller, RobotAgent
from nubot_control.params import ControlParams

TEAMS = [("nubot1", -8.4, 0, 0), ("nubot2", -1.0, 0, 0), ("nubot3", -3, 2.5, 0), ("nubot4", -3, -2.5, 0),
         ("nubot5", -5.5, 0, 0), ("rival1", 8.4, 0, math.pi), ("rival2", 1.0, 0, math.pi),
         ("rival3", 3, -2.5, math.pi), ("rival4", 3, 2.5, math.pi), ("rival5", 5.5, 0, math.pi)]


def test_control_acts_the_same_on_the_world_model_message_as_on_the_world_model_itself(make_match):
    """WorldModelInfo carries the whole decision: the nubot_control node, reading it back, commands what the
    in-process agent commands (to float32 rounding), cycle after cycle, through a kickoff and open play. Until a choice
    that sits on its boundary goes the other way on the rounding (DEFEND against CHASE for a cycle), the commands
    agree within 2 mm/s; after it the two controllers follow plans of their own for a while (by up to a few dm/s),
    until they meet again: at most 1 % of the cycles decide otherwise, at most 10 % command more than 2 mm/s apart."""
    match = make_match(TEAMS)
    match.command("nubot", MatchMode.OUR_KICKOFF)
    worlds = []
    for k in range(200):  # 6 s: formation, then STARTROBOT and the kickoff pass
        if k == 120:
            match.command("nubot", MatchMode.STARTROBOT)
        match.run(1 / 33)
        worlds.append((match.sim.time, match.steps["nubot2"].world))
    direct, via_message = (Controller(ControlParams(), WorldDescription(), 2) for _ in range(2))
    roles, decided_otherwise, apart, first_otherwise = set(), 0, [], len(worlds)
    for t, world in worlds:
        decoded = conv.world_state(conv.world_model_info_msg(world), 2)
        assert decoded.game == world.game and decoded.pass_cmd == world.pass_cmd
        assert decoded.ball.known == world.ball.known
        assert [r.valid for r in decoded.robots] == [r.valid for r in world.robots]
        a, b = direct.step(t, world), via_message.step(t, decoded)
        otherwise = (a.report.role, a.report.action, a.command.ball_handle, a.command.kick) != \
            (b.report.role, b.report.action, b.command.ball_handle, b.command.kick)
        decided_otherwise += otherwise
        first_otherwise = min(first_otherwise, len(apart)) if otherwise else first_otherwise
        va, vb = a.command.velocity, b.command.velocity
        apart.append(max(abs(vb.vx - va.vx), abs(vb.vy - va.vy), abs(vb.w - va.w)))
        roles.add(a.report.role)
    assert decided_otherwise <= 0.01 * len(worlds)
    assert sum(d > 2e-3 for d in apart) <= 0.1 * len(worlds), sorted(apart)[-5:]
    assert max(apart[:first_otherwise], default=0.0) < 2e-3, "the same decisions give the same commands"
    assert {Role.PASSOFPASS, Role.CATCHOFPASS} & roles, "the sequence went through the kickoff"


def frame(t, holding=False, ball=(0.4, 0.0)):
    me = RobotReport(2, Pose2D(0.0, 0.0, 0.0), holding=holding)
    return RobotView(t, me, BallPercept(t, *ball) if ball else None)


def test_the_dribbler_is_asked_for_once_then_again_every_retry_period_until_the_ball_is_held():
    agent = RobotAgent(RobotName("nubot", 2), WorldDescription())
    agent.on_coach(0.0, MatchMode.STARTROBOT)
    requests = []
    for k in range(40):
        t = k / 33
        agent.on_vision(frame(t, holding=t > 0.8))
        step = agent.step(t)
        assert step.command.dribble or t > 0.8
        requests.append((round(t, 3), step.command.ball_handle))
    asked = [t for t, r in requests if r == 1]
    assert asked[0] == 0.0, "at once"
    assert all(b - a >= DRIBBLE_RETRY - 1e-9 for a, b in zip(asked, asked[1:])), "not every cycle"
    assert len(asked) == 4 and max(asked) < 0.8, "again every 0.2 s, not once the ball is held"


def test_no_kick_is_sent_unless_the_ball_is_held_and_the_report_names_the_robot():
    agent = RobotAgent(RobotName("nubot", 2), WorldDescription())
    agent.on_coach(0.0, MatchMode.STARTROBOT)
    for k in range(100):
        t = k / 33
        agent.on_vision(frame(t, holding=False, ball=(7.0, 0.0)))
        step = agent.step(t)
        assert step.command.kick is None
    assert step.report.agent_id == 2 and step.report.role == Role.ACTIVE
    assert step.packet is not None and step.packet.robot.role == Role.ACTIVE, "teammates learn its role"
    assert step.world.me.report.target == pytest.approx(step.report.target, abs=1e-9), "and where it heads"


def test_a_robot_that_does_not_know_where_it_is_stands_still():
    agent = RobotAgent(RobotName("nubot", 2), WorldDescription())
    agent.on_coach(0.0, MatchMode.STARTROBOT)
    agent.on_vision(RobotView(0.0, RobotReport(2, Pose2D(0.0, 0.0, 0.0), valid=False), BallPercept(0.0, 3.0, 0.0)))
    step = agent.step(0.0)
    v = step.command.velocity
    assert (v.vx, v.vy, v.w, step.command.kick) == (0.0, 0.0, 0.0, None)


def test_a_robot_whose_world_model_stopped_stands_still_until_a_fresh_one_arrives(make_match):
    """The world model node died: control keeps being called with its last decision; after the timeout it
    stops the robot and says it is out of play; the next fresh decision puts it back into play. (The rivals' striker
    starts far from the ball: nubot2 has it to itself.)"""
    match = make_match([*TEAMS[:6], ("rival2", 4.0, 0, math.pi), *TEAMS[7:]])
    match.command("nubot", MatchMode.STARTROBOT)
    match.run(1.0)
    last = match.steps["nubot2"].world
    controller = Controller(ControlParams(), WorldDescription(), 2)
    timeout = controller.params.world_model_timeout
    moving = controller.step(last.stamp + 0.5 * timeout, last)
    assert not moving.stale and moving.command.dribble and moving.command.velocity.w != 0.0, "going for the ball"
    for late in (1.01 * timeout, 5.0, 60.0):
        step = controller.step(last.stamp + late, last)
        v = step.command.velocity
        assert step.stale and (v.vx, v.vy, v.w, step.command.kick, step.command.dribble) == (0, 0, 0, None, False)
    back = controller.step(last.stamp, last)
    assert not back.stale and back.output is not None


def test_a_robot_keeps_nothing_per_cycle_its_memory_stays_flat_after_a_warm_up():
    """A robot's nodes run for hours at 33 Hz: a few hundred bytes kept per cycle would be a MiB a minute.
    The scenario repeats every 400 cycles (set plays and open play, the ball held, lost and found again, the
    robot on a circle among moving opponents). After two rounds to warm up, four more add less than 48 KiB (30 B a
    cycle) in one of two such spans: what the robot holds at a round's end differs by up to about 35 KiB with the plan
    it is following then, and a table of the process's own (a cache, a registry) may grow once in a span, after
    other tests ran; a leak of 85 B a cycle would add 136 KiB to both."""
    agent = RobotAgent(RobotName("nubot", 2), WorldDescription())
    modes = (MatchMode.OUR_KICKOFF, MatchMode.STARTROBOT, MatchMode.OPP_FREEKICK, MatchMode.STARTROBOT,
             MatchMode.STOPROBOT)
    period = 400  # cycles: 80 per command

    def cycle(k: int) -> None:
        t, a = k / 33, 2.0 * math.pi * k / period
        if k % 80 == 0:
            agent.on_coach(t, modes[k // 80 % len(modes)])
        me = RobotReport(2, Pose2D(4.0 * math.cos(a), 3.0 * math.sin(a), a + 1.6), holding=100 <= k % period < 200)
        ball = None if k % period >= 300 else BallPercept(t, 4.0 * math.sin(2.0 * a), 3.0 * math.sin(a))
        seen = tuple((3.0 * math.cos(a + i), 2.0 * math.sin(a + i) + i - 1.0) for i in range(3))
        agent.on_vision(RobotView(t, me, ball, seen))
        for mate, role, x in ((1, Role.GOALIE, -8.0), (3, Role.PASSIVE, -3.0 + math.sin(a))):
            agent.on_teammate(t, RobotView(t, RobotReport(mate, Pose2D(x, -3.0 + mate, 0.0), role=role)))
            agent.on_teammate_strategy(t, StrategyReport(t, mate, role))
        agent.step(t)

    for k in range(period):
        cycle(k)
    started = not tracemalloc.is_tracing()
    tracemalloc.start()
    try:
        for k in range(period, 2 * period):  # traced, so that the state the next round replaces counts
            cycle(k)
        spans = []
        for first in (2, 6):
            gc.collect()
            before = tracemalloc.get_traced_memory()[0]
            for k in range(first * period, (first + 4) * period):
                cycle(k)
            gc.collect()
            spans.append(tracemalloc.get_traced_memory()[0] - before)
    finally:
        if started:
            tracemalloc.stop()
    grown = min(spans)
    assert grown < 48 * 1024, f"{spans} B kept in spans of {4 * period} cycles ({grown / (4 * period):.0f} B a cycle)"
