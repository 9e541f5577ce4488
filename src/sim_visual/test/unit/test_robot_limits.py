"""Unit tests of the physical limits of robots and ball (docs/physical_figures.md): the base's acceleration and
braking, what the ball handler keeps, a kick's spread, the ball's rolling and its bounce off a robot."""

import math

import numpy as np
import pytest

from sim_visual.params import PluginParams
from sim_visual.simulator import BallReleased
from sim_visual.world import BallState


def speed(sim, name="nubot1"):
    state = sim.world.robot_state(name)
    return math.hypot(state.vx, state.vy)


def drive_for(sim, run, seconds, vx, vy=0.0, w=0.0, name="nubot1"):
    events = []
    for _ in range(round(seconds / 0.03)):
        sim.command_velocity(name, vx, vy, w)
        events += run(sim, 0.03)
    return events


def test_the_base_speeds_up_at_its_acceleration_and_brakes_harder(make_sim, run):
    sim = make_sim()
    p = sim.plugin_params
    drive_for(sim, run, 0.3, 3.0)
    assert speed(sim) == pytest.approx(p.max_linear_accel * 0.3, abs=0.05)
    drive_for(sim, run, 1.0, 3.0)
    assert speed(sim) == pytest.approx(3.0, abs=1e-6)
    drive_for(sim, run, 0.3, 0.0)
    assert speed(sim) == pytest.approx(3.0 - p.max_linear_brake * 0.3, abs=0.05)
    drive_for(sim, run, 0.9, 0.0, w=4.0)
    assert sim.world.robot_state("nubot1").w == pytest.approx(min(4.0, p.max_angular_accel * 0.9), abs=0.1)


def test_turning_aside_at_speed_is_an_acceleration_too(make_sim, run):
    sim = make_sim()
    drive_for(sim, run, 1.5, 2.0)
    drive_for(sim, run, 0.3, 0.0, 2.0)  # the same speed, sideways: 2.8 m/s of change, at 3.5 m/s^2
    state = sim.world.robot_state("nubot1")
    assert state.vx == pytest.approx(2.0 - 2.0 / math.hypot(2.0, 2.0) * 3.5 * 0.3, abs=0.05)


def hold(make_sim, run, **plugin):
    sim = make_sim(ball=(0.45, 0.0), plugin=PluginParams(**plugin))
    assert sim.ball_handle("nubot1", 1)
    return sim


@pytest.mark.parametrize(("vx", "vy", "w", "kept"), [
    (1.5, 0.0, 0.0, True),  # forwards within the grip
    (-0.5, 0.0, 0.0, True),  # backwards within it
    (0.0, 0.5, 0.0, True),
    (0.0, 0.0, 2.5, True),
    (-1.0, 0.0, 0.0, False),  # backwards faster than the grip keeps
    (0.0, -1.0, 0.0, False),  # sideways
    (0.0, 0.0, 5.0, False),  # turning
])
def test_the_ball_handler_keeps_the_ball_only_within_its_grip(make_sim, run, vx, vy, w, kept):
    sim = hold(make_sim, run)
    events = drive_for(sim, run, 1.5, vx, vy, w)
    assert (sim.holder == "nubot1") is kept
    released = [e for e in events if isinstance(e, BallReleased)]
    assert len(released) == (0 if kept else 1)
    if not kept:  # it slipped once the speed was over the limit for hold_slip_time; the ball rolls on
        ball = sim.world.ball_state()
        assert math.dist((ball.x, ball.y), (sim.world.robot_state("nubot1").x,
                                            sim.world.robot_state("nubot1").y)) > 0.3


def test_running_faster_than_the_grip_pushes_the_ball_ahead(make_sim, run):
    sim = hold(make_sim, run)
    events = drive_for(sim, run, 1.5, 3.0)
    slips = [e for e in events if isinstance(e, BallReleased)]
    assert slips and slips[0].time < 0.2 + 2.2 / sim.plugin_params.max_linear_accel + 0.1


def test_a_ball_lost_from_the_grip_is_not_taken_again_at_once(make_sim, run):
    sim = hold(make_sim, run, kick_recapture_delay=1.0)
    events = drive_for(sim, run, 0.6, -1.2)
    slip = next(e for e in events if isinstance(e, BallReleased))
    drive_for(sim, run, 0.3, 0.0)
    assert sim.holder is None and sim.time - slip.time < 1.0


def kick_spread(make_sim, kicks, **plugin):
    directions, speeds = [], []
    sim = make_sim(ball=(0.45, 0.0), plugin=PluginParams(**plugin))
    for _ in range(kicks):
        sim.set_model_state(sim.config.ball_name, BallState(0.45, 0.0, 0.11, 0.0, 0.0, 0.0))
        sim.world.set_no_capture_until("nubot1", 0.0)
        assert sim.ball_handle("nubot1", 1)
        _, kick = sim.shoot("nubot1", 8, -1)
        directions.append(math.degrees(math.atan2(kick.velocity[1], kick.velocity[0])))
        speeds.append(math.hypot(*kick.velocity))
    return np.array(directions), np.array(speeds)


def test_kicks_scatter_in_direction_and_speed_as_configured(make_sim):
    directions, speeds = kick_spread(make_sim, 600)
    p = PluginParams()
    assert np.std(directions) == pytest.approx(p.kick_direction_std_deg, rel=0.15)
    assert abs(np.mean(directions)) < 0.2
    assert np.std(speeds / 8.0) == pytest.approx(p.kick_speed_std, rel=0.15)
    exact_directions, exact_speeds = kick_spread(make_sim, 5, kick_direction_std_deg=0.0, kick_speed_std=0.0)
    assert np.allclose(exact_directions, 0.0) and np.allclose(exact_speeds, 8.0)


def test_a_rolling_ball_slows_at_its_rolling_deceleration(make_sim, run):
    sim = make_sim(robots=(("nubot1", -8.0, 5.0, 0.0),), ball=(-6.0, 0.0))
    sim.set_model_state(sim.config.ball_name, BallState(-6.0, 0.0, 0.11, 3.0, 0.0, 0.0, 0.0, 3.0 / 0.11, 0.0))
    run(sim, 2.0)
    decel = sim.config.ball.rolling_friction * 9.8
    assert sim.world.ball_state().vx == pytest.approx(3.0 - 2.0 * decel, abs=0.05)


def test_a_ball_bounces_off_a_robot_with_the_bodys_restitution(make_sim, run):
    sim = make_sim(robots=(("nubot1", 2.0, 0.0, 0.0),), ball=(0.0, 0.0))
    sim.set_model_state(sim.config.ball_name, BallState(0.0, 0.0, 0.11, 4.0, 0.0, 0.0, 0.0, 4.0 / 0.11, 0.0))
    before, after = 0.0, 0.0
    for _ in range(200):
        sim.command_velocity("nubot1", 0.0, 0.0, 0.0)
        run(sim, 0.005)
        vx = sim.world.ball_state().vx
        before, after = (vx, after) if vx > 0.0 else (before, min(after, vx))
    # right after the impact, before the carpet turns its spin into a slide (the robot, driven, does not give way)
    assert -after / before == pytest.approx(sim.config.ball.body_restitution, abs=0.08)
