"""Unit tests of the single-robot demo behaviour, run in-process against the simulator core."""

import math

import pytest

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.percepts import BallPercept, RobotReport, RobotView
from sim_visual.demo import DemoBehaviour, DemoParams, DemoState
from sim_visual.episode import run_demo_episode
from sim_visual.params import NoiseParams, PluginParams


def seen(t, ball, holding):
    """What the demo perceives at ``t``: itself at the origin facing +x, the ball at ``ball`` (None: unseen)."""
    return RobotView(t, RobotReport(1, Pose2D(), holding=holding), BallPercept(t, *ball) if ball else None)


def demo():
    return DemoBehaviour(DemoParams(), FieldGeometry())


ORDER = ["CHASE_BALL", "DRIBBLE_BALL/MOVE_BALL", "DRIBBLE_BALL/ROTATE_BALL", "KICK_BALL", "RESET", "HOME"]


EXACT_KICKS = PluginParams(kick_direction_std_deg=0.0, kick_speed_std=0.0)  # a kick without spread always scores


@pytest.mark.parametrize("shot", ["lob", "ground"])
def test_demo_runs_the_state_machine_and_scores(make_sim, shot):
    sim = make_sim(robots=(("nubot1", -2.0, 0.0, 0.0),), ball=(1.0, 2.0), plugin=EXACT_KICKS)
    log = run_demo_episode(sim, "nubot1", DemoParams(shot=shot), 60.0)
    states = [log.transitions[0][1]] + [t[2] for t in log.transitions]
    assert states == ORDER
    assert len(log.goals) == 1 and log.goals[0].side == 1
    assert log.goals[0].time < 20.0


def test_demo_speed_respects_its_profile(make_sim):
    sim = make_sim(robots=(("nubot1", -2.0, 0.0, 0.0),), ball=(6.0, -4.0))
    log = run_demo_episode(sim, "nubot1", DemoParams(), 30.0)
    dt = sim.config.physics.step_size
    speeds = [math.dist(a[:2], b[:2]) / dt for a, b in zip(log.robot, log.robot[1:])]
    assert max(speeds) <= 3.0 + 0.05
    assert max(speeds) > 2.5, "long chases reach the top speed"


def test_demo_without_ball_in_sight_turns_to_look():
    action, _ = demo().step(seen(0.0, None, False))
    assert action.velocity.w > 0.0 and action.ball_handle is None


def test_demo_asks_for_the_ball_only_when_close_and_facing_it():
    behaviour = demo()
    far, _ = behaviour.step(seen(0.0, (2.0, 0.0), False))
    near, _ = behaviour.step(seen(0.03, (0.42, 0.0), False))
    assert far.ball_handle is None and near.ball_handle == 1


def test_demo_losing_the_ball_goes_back_to_chasing():
    behaviour = demo()
    behaviour.step(seen(0.0, (0.43, 0.0), True))
    assert behaviour.state == DemoState.MOVE_BALL
    _, transitions = behaviour.step(seen(0.03, (3.0, 0.0), False))
    assert transitions[-1] == (DemoState.MOVE_BALL, DemoState.CHASE_BALL)


def test_demo_with_noisy_perception_still_scores(make_sim):
    sim = make_sim(robots=(("nubot1", -2.0, 0.0, 0.0),), ball=(-4.0, -3.0), plugin=EXACT_KICKS,
                   noise=NoiseParams(position_std=0.05, velocity_std=0.1, self_position_std=0.02, heading_std=0.01))
    log = run_demo_episode(sim, "nubot1", DemoParams(), 60.0)
    assert len(log.goals) == 1


def test_bad_demo_params_are_refused():
    with pytest.raises(ValueError, match="shot must be 'lob' or 'ground'"):
        DemoParams(shot="bicycle")


def test_on_the_22_by_14_field_the_demo_shoots_at_its_goal(make_sim):
    from nubot_common.world_description import load_world

    sim = make_sim(robots=(("nubot1", -2.0, 0.0, 0.0),), ball=(1.0, 2.0), world=load_world("22x14"))
    log = run_demo_episode(sim, "nubot1", DemoParams(shot="ground"), 60.0)
    assert len(log.goals) == 1 and log.goals[0].ball.x > 11.0, "in the goal at x = 11"
    kick = next(t for t, _, state in log.transitions if state == "RESET")
    x = log.robot[log.times.index(next(t for t in log.times if t >= kick))][0]
    assert x == pytest.approx(11.0 - 6.0, abs=0.3), "dribbled to 6 m before the 22 x 14 goal line"
