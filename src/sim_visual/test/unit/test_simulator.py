"""Unit tests of the simulator core: locomotion, dribbling, kicking, goals, physics, reset."""

import itertools
import math
from dataclasses import astuple

import numpy as np
import pytest

from nubot_common.commands import BodyVelocity, KickCommand, KickKind, RobotCommand
from sim_visual import SimVisualError
from sim_visual.simulator import BallCaptured, BallKicked, GoalScored
from sim_visual.world import BallState, RobotState


def test_body_velocity_moves_the_robot_the_expected_distance(make_sim, run):
    sim = make_sim(robots=(("nubot1", 0.0, 0.0, math.pi / 2),))
    for _ in range(200):  # 1 s, commands faster than the 0.5 s timeout
        sim.command_velocity("nubot1", 2.0, 0.0, 0.0)
        run(sim, 0.005)
    state = sim.world.robot_state("nubot1")
    assert state.x == pytest.approx(0.0, abs=1e-6)
    ramp = 2.0 ** 2 / (2.0 * sim.plugin_params.max_linear_accel)  # what the base loses getting up to speed
    assert state.y == pytest.approx(2.0 - ramp, abs=0.02), "Vx is along the robot heading (+y here)"


def test_lateral_and_rotational_velocity(make_sim, run):
    sim = make_sim()
    sim.command_velocity("nubot1", 0.0, 1.0, 1.0)
    run(sim, 0.5)
    state = sim.world.robot_state("nubot1")
    assert state.theta == pytest.approx(0.5 - 1.0 / (2.0 * sim.plugin_params.max_angular_accel), abs=0.01)
    assert state.y > 0.3 and state.x < 0.0, "Vy is leftward in the body frame, which turns with the robot"


def test_command_timeout_stops_a_robot_nobody_drives(make_sim, run):
    sim = make_sim()
    sim.command_velocity("nubot1", 1.0, 0.0, 0.0)
    run(sim, 2.0)
    p = sim.plugin_params  # 0.5 s at 1 m/s, less the ramp up, and the way it takes to brake
    assert sim.world.robot_state("nubot1").x == pytest.approx(
        0.5 - 1.0 / (2.0 * p.max_linear_accel) + 1.0 / (2.0 * p.max_linear_brake), abs=0.02)


def test_robots_push_each_other_and_do_not_overlap(make_sim, run):
    sim = make_sim(robots=(("nubot1", 0.0, 0.0, 0.0), ("nubot2", 1.0, 0.0, 0.0)))
    for _ in range(300):
        sim.command_velocity("nubot1", 2.0, 0.0, 0.0)
        sim.command_velocity("nubot2", 0.0, 0.0, 0.0)
        run(sim, 0.005)
    a, b = sim.world.robot_state("nubot1"), sim.world.robot_state("nubot2")
    assert b.x - a.x > 2 * sim.config.robot.radius - 0.05


def test_robots_crashing_at_full_speed_stay_upright_on_the_carpet(make_sim, run):
    # Head-on at 5 m/s each while turning, and into a goal post: contacts push the robots only in the plane.
    sim = make_sim(robots=(("nubot1", -1.0, 0.0, 0.0), ("nubot2", 1.0, 0.1, math.pi), ("nubot3", 7.5, 0.9, 0.0)))
    worst_lift, worst_tilt = 0.0, 0.0
    for _ in range(200):
        for name in ("nubot1", "nubot2", "nubot3"):
            sim.command_velocity(name, 5.0, 0.0, 3.0 if name == "nubot1" else 0.0)
        run(sim, 0.005)
        for name, row in sim.world.bodies().items():
            if name is None:
                continue
            z, qx, qy = row[2], row[4], row[5]  # position x, y, z; orientation w, x, y, z
            worst_lift, worst_tilt = max(worst_lift, abs(z)), max(worst_tilt, 2 * math.hypot(qx, qy))
    assert worst_lift < 0.005, "a robot left the carpet"
    assert worst_tilt < 0.01, "a robot tipped over"
    a, b = sim.world.robot_state("nubot1"), sim.world.robot_state("nubot2")
    assert math.hypot(b.x - a.x, b.y - a.y) > 2 * sim.config.robot.radius - 0.05


def test_ball_handle_refuses_a_far_ball_and_holds_a_near_one(make_sim, run):
    sim = make_sim(ball=(2.0, 0.0))
    assert sim.ball_handle("nubot1", 1) is False
    sim.world.set_ball_state(BallState(0.45, 0.0, 0.11, 0, 0, 0))
    assert sim.ball_handle("nubot1", 1) is True
    assert sim.holder == "nubot1"


def test_held_ball_follows_a_moving_turning_robot(make_sim, run):
    sim = make_sim(ball=(0.45, 0.0))
    assert sim.ball_handle("nubot1", 1)
    for _ in range(400):
        sim.command_velocity("nubot1", 1.0, 0.0, 1.5)
        run(sim, 0.005)
    robot, ball = sim.world.robot_state("nubot1"), sim.world.ball_state()
    assert sim.holder == "nubot1"
    ahead = (robot.x + 0.43 * math.cos(robot.theta), robot.y + 0.43 * math.sin(robot.theta))
    assert (ball.x, ball.y) == pytest.approx(ahead, abs=1e-6)


def test_enabled_dribbler_catches_a_ball_rolling_in(make_sim, run):
    sim = make_sim(ball=(2.0, 0.0))
    sim.ball_handle("nubot1", 1)
    sim.world.set_ball_state(BallState(2.0, 0.0, 0.11, -3.0, 0.0, 0.0))
    events = run(sim, 1.0)
    assert any(isinstance(e, BallCaptured) and e.robot == "nubot1" for e in events)


def test_release_lets_the_ball_go(make_sim, run):
    sim = make_sim(ball=(0.45, 0.0))
    sim.ball_handle("nubot1", 1)
    assert sim.ball_handle("nubot1", 0) is False
    sim.command_velocity("nubot1", -1.0, 0.0, 0.0)
    run(sim, 0.4)
    assert sim.holder is None
    assert sim.world.ball_state().x == pytest.approx(0.45, abs=0.05)


def test_shoot_without_the_ball_does_nothing(make_sim):
    sim = make_sim(ball=(3.0, 0.0))
    assert sim.shoot("nubot1", 5, -1) == (False, None)
    assert sim.world.ball_state().vx == 0.0
    with pytest.raises(SimVisualError, match="ShootPos must be -1"):
        sim.shoot("nubot1", 5, 0)


def test_one_control_cycle_s_commands_go_through_the_interface_in_order(make_sim):
    """execute: the velocity, then BallHandle, then Shoot: a robot asking for a near ball and kicking it in one
    cycle kicks it; without the ball the shot is not done; without a kick there is nothing to report."""
    sim = make_sim(ball=(0.45, 0.0))
    assert sim.execute("nubot1", RobotCommand(BodyVelocity(0.5, 0.0, 0.0))) == (True, None)
    assert sim.world.command("nubot1") == BodyVelocity(0.5, 0.0, 0.0)
    done, event = sim.execute("nubot1", RobotCommand(BodyVelocity(), True, 1, KickCommand(KickKind.GROUND, 4)))
    assert done and isinstance(event, BallKicked) and event.robot == "nubot1"
    far = make_sim(ball=(3.0, 0.0))
    assert far.execute("nubot1", RobotCommand(BodyVelocity(), True, 1, KickCommand(KickKind.GROUND, 4))) == \
        (False, None)


def test_ground_pass_starts_at_the_commanded_speed_and_rolls_to_a_stop(make_sim, run):
    sim = make_sim(ball=(0.45, 0.0), robots=(("nubot1", 0.0, 0.0, math.pi / 2),))
    sim.world.set_robot_state("nubot1", RobotState(0.0, 0.0, 0.0, 0, 0, 0))
    sim.ball_handle("nubot1", 1)
    done, event = sim.shoot("nubot1", 3, -1)
    assert done and isinstance(event, BallKicked)
    run(sim, 0.05)
    ball = sim.world.ball_state()
    assert math.hypot(ball.vx, ball.vy) == pytest.approx(3.0, abs=0.1)
    assert ball.z == pytest.approx(0.11, abs=0.005), "a ground pass stays on the carpet"
    run(sim, 10.0)
    ball = sim.world.ball_state()
    decel = sim.config.ball.rolling_friction * 9.8
    assert math.hypot(ball.vx, ball.vy) < 0.01
    assert ball.x - 0.45 == pytest.approx(9.0 / (2 * decel), rel=0.05), "rolling friction: v^2 / (2 mu g)"


def test_lob_from_six_metres_scores(make_sim, run):
    sim = make_sim(robots=(("nubot1", 2.57, 0.3, 0.0),), ball=(3.0, 0.3))
    assert sim.ball_handle("nubot1", 1)
    assert sim.shoot("nubot1", 0, 1)[0]
    peak = 0.0
    goals = []
    for _ in range(600):
        goals += [e for e in sim.step() if isinstance(e, GoalScored)]
        peak = max(peak, sim.world.ball_state().z)
    assert peak > 1.0, "a lob flies"
    assert len(goals) == 1 and goals[0].side == 1 and goals[0].last_touch == "nubot1"
    assert goals[0].ball.z < sim.config.field.goal_height


def test_kicker_cannot_recatch_at_once(make_sim, run):
    sim = make_sim(ball=(0.45, 0.0))
    sim.ball_handle("nubot1", 1)
    sim.shoot("nubot1", 1, -1)
    sim.ball_handle("nubot1", 1)
    run(sim, 0.1)
    assert sim.holder is None


def test_ball_rolling_wide_of_the_post_is_no_goal(make_sim, run):
    sim = make_sim(ball=(7.0, 2.0))
    sim.world.set_ball_state(BallState(7.0, 2.0, 0.11, 6.0, 0.0, 0.0, 0.0, 6.0 / 0.11, 0.0))
    assert not [e for e in run(sim, 3.0) if isinstance(e, GoalScored)]


def test_ball_over_the_bar_is_no_goal(make_sim, run):
    sim = make_sim(ball=(7.0, 0.0))
    sim.world.set_ball_state(BallState(8.0, 0.0, 1.5, 6.0, 0.0, 2.0))
    assert not [e for e in run(sim, 3.0) if isinstance(e, GoalScored)]


def test_ball_rolling_into_the_goal_scores_once_and_the_net_stops_it(make_sim, run):
    sim = make_sim(ball=(7.0, 0.0), robots=())
    sim.world.set_ball_state(BallState(-7.0, 0.5, 0.11, -6.0, 0.0, 0.0, 0.0, -6.0 / 0.11, 0.0))
    goals = [e for e in run(sim, 4.0) if isinstance(e, GoalScored)]
    assert [g.side for g in goals] == [-1]
    ball = sim.world.ball_state()
    assert -sim.config.field.half_length - sim.config.field.goal_depth < ball.x < -sim.config.field.half_length


@pytest.mark.parametrize("ball", [BallState(-8.0, 0.95, 0.44, -5.08, 0.68, 2.13),
                                  BallState(-8.0, 1.02, 0.26, -7.1, 0.49, 2.01)])
def test_a_lob_that_grazes_a_post_on_its_way_in_scores(make_sim, run, ball):
    """Wholly behind the line it was still beside the post (not yet between the posts): it is a goal all the same,
    once it is inside, as the referee sees it."""
    sim = make_sim(robots=())
    sim.world.set_ball_state(ball)
    goals = [e for e in run(sim, 1.5) if isinstance(e, GoalScored)]
    assert [g.side for g in goals] == [-1]
    assert abs(goals[0].ball.y) > sim.config.field.goal_width / 2 - sim.config.ball.radius, "it came in at a post"
    end = sim.world.ball_state()
    assert sim.config.field.goal_holding(end.x, end.y, end.z, sim.config.ball.radius) == -1


def test_ball_bounces_off_a_robot(make_sim, run):
    sim = make_sim(ball=(-2.0, 0.0))
    sim.world.set_ball_state(BallState(-2.0, 0.0, 0.11, 4.0, 0.0, 0.0, 0.0, 4.0 / 0.11, 0.0))
    run(sim, 1.0)
    assert sim.world.ball_state().vx < 0.0
    assert sim.last_touch == "nubot1"


def test_dropped_ball_bounces_and_settles(make_sim, run):
    sim = make_sim(ball=(3.0, 3.0))
    sim.world.set_ball_state(BallState(3.0, 3.0, 2.0, 0, 0, 0))
    heights = []
    for _ in range(800):
        sim.step()
        heights.append(sim.world.ball_state().z)
    first_contact = next(i for i, z in enumerate(heights) if z < 0.12)
    assert max(heights[first_contact:]) > 0.3, "it bounces"
    assert heights[-1] == pytest.approx(0.11, abs=0.005), "then rests on the carpet"


def test_reset_restores_the_initial_state(make_sim, run):
    sim = make_sim(ball=(0.45, 0.0), robots=(("nubot1", -1.0, 0.5, 0.3),))
    sim.world.set_robot_state("nubot1", RobotState(0.0, 0.0, 0.0, 0, 0, 0))
    sim.ball_handle("nubot1", 1)
    sim.command_velocity("nubot1", 2.0, 1.0, 1.0)
    run(sim, 1.0)
    sim.reset()
    assert sim.holder is None
    state = sim.world.robot_state("nubot1")
    assert (state.x, state.y, state.theta, state.vx, state.vy, state.w) == pytest.approx((-1.0, 0.5, 0.3, 0, 0, 0))
    ball = sim.world.ball_state()
    assert (ball.x, ball.y, ball.vx, ball.vy) == pytest.approx((0.45, 0.0, 0.0, 0.0))
    run(sim, 0.5)
    assert sim.world.robot_state("nubot1").x == pytest.approx(-1.0, abs=1e-6), "old commands are gone"


def test_unknown_robot_and_bad_state_are_refused(make_sim):
    sim = make_sim()
    with pytest.raises(SimVisualError, match="no robot named 'nubot7'"):
        sim.command_velocity("nubot7", 1, 0, 0)
    with pytest.raises(SimVisualError, match="must be finite"):
        sim.set_model_state("nubot1", RobotState(math.nan, 0, 0, 0, 0, 0))


def test_spawn_and_delete_robots(make_sim):
    sim = make_sim()
    from sim_visual.params import RobotSpawn
    sim.spawn_robot(RobotSpawn("rival1", 3.0, 0.0, math.pi, -1))
    assert sim.model_names == ["nubot1", "rival1", "football"]
    with pytest.raises(SimVisualError, match="already exists"):
        sim.spawn_robot(RobotSpawn("rival1"))
    sim.delete_robot("rival1")
    assert sim.model_names == ["nubot1", "football"]


def test_stuck_robot_is_flagged(make_sim, run):
    sim = make_sim(robots=(("nubot1", 8.5, 0.0, 0.0),))
    for _ in range(400):
        sim.command_velocity("nubot1", 2.0, 0.0, 0.0)  # into the goal post/net
        sim.step()
    assert sim.observe("nubot1").robot.stuck


@pytest.mark.parametrize("speed", [4.0, 8.0, 12.0])
def test_the_net_swallows_a_hard_shot(make_sim, run, speed):
    sim = make_sim(ball=(6.0, 0.3), robots=())
    sim.world.set_ball_state(BallState(6.0, 0.3, 0.11, speed, 0.0, 0.0, 0.0, speed / 0.11, 0.0))
    run(sim, 6.0)
    ball, field = sim.world.ball_state(), sim.config.field
    assert field.half_length < ball.x < field.half_length + field.goal_depth, "the ball stays in the goal"
    assert ball.z == pytest.approx(0.11, abs=0.01), "and drops to the ground instead of clinging to the net"


def test_ball_bounces_off_a_goal_post(make_sim, run):
    sim = make_sim(robots=())
    (px, py), _ = sim.config.field.goal_posts(1)
    sim.world.set_ball_state(BallState(px - 2.0, py, 0.11, 5.0, 0.0, 0.0, 0.0, 5.0 / 0.11, 0.0))
    events = run(sim, 1.0)
    assert sim.world.ball_state().vx < 0.0, "it comes back off the post"
    assert not [e for e in events if isinstance(e, GoalScored)]


def test_larger_field_by_configuration(make_sim, run):
    from nubot_common.world_description import load_world

    sim = make_sim(robots=(), world=load_world("22x14"))
    sim.world.set_ball_state(BallState(9.5, 0.0, 0.11, 6.0, 0.0, 0.0, 0.0, 6.0 / 0.11, 0.0))
    goals = [e for e in run(sim, 2.0) if isinstance(e, GoalScored)]
    assert len(goals) == 1 and goals[0].ball.x > 11.0, "the goal line is at 11 m on a 22 m field"


def test_touches_are_reported_when_the_toucher_changes(make_sim, run):
    from sim_visual.simulator import BallTouched

    sim = make_sim(robots=(("nubot1", 0.0, 0.0, 0.0), ("rival1", 3.0, 0.0, math.pi)), ball=(0.45, 0.0))
    assert sim.ball_handle("nubot1", 1)
    first = [e for e in run(sim, 0.1) if isinstance(e, BallTouched)]
    assert [e.robot for e in first] == ["nubot1"], "a capture is a touch"
    sim.shoot("nubot1", 4, -1)
    events = [e for e in run(sim, 2.0) if isinstance(e, BallTouched)]
    assert [e.robot for e in events] == ["rival1"], "the pass hits rival1; nubot1's own kick is no new touch"


def test_switching_ends_keeps_every_robot_where_it_was_in_its_own_team_frame(make_sim, run):
    sim = make_sim(robots=(("nubot1", -3.0, 1.0, 0.2, 1), ("rival1", 4.0, -2.0, 2.5, -1)), ball=(1.0, 2.0))
    before = {name: sim.observe(name) for name in ("nubot1", "rival1")}
    sim.switch_ends()
    world = sim.world.robot_state("nubot1")
    assert (world.x, world.y, world.theta) == pytest.approx((3.0, -1.0, 0.2 - math.pi)), "turned round the centre"
    assert [sim.plugins[n].spawn.attack for n in ("nubot1", "rival1")] == [-1, 1]
    ball = sim.world.ball_state()
    assert (ball.x, ball.y, ball.vx, ball.vy) == pytest.approx((-1.0, -2.0, 0.0, 0.0))
    for name, old in before.items():
        new = sim.observe(name)
        assert (new.robot.pose.x, new.robot.pose.y) == pytest.approx((old.robot.pose.x, old.robot.pose.y), abs=0.15)
        assert math.cos(new.robot.pose.theta - old.robot.pose.theta) > 0.99
        assert (new.ball.x, new.ball.y) == pytest.approx((old.ball.x, old.ball.y), abs=0.3), "the ball too"
    sim.reset()
    start = sim.world.robot_state("rival1")
    assert (start.x, start.y) == pytest.approx((-4.0, 2.0)), "reset uses the start poses of the new ends"


# --- hostile input: refused with a message naming the bad value, nothing changed, the simulator still steps ---

@pytest.mark.parametrize(("name", "state", "message"), [
    ("nubot1", RobotState(1e10, 0.0, 0.0, 0.0, 0.0, 0.0), r"nubot1 at \(1e\+10, 0\) is outside the arena"),
    ("nubot1", RobotState(0.0, -7.5, 0.0, 0.0, 0.0, 0.0), r"nubot1 at \(0, -7.5\) is outside the arena"),
    ("nubot1", RobotState(0.0, 0.0, 0.0, 100.0, 0.0, 0.0), "speed 100 m/s exceeds max_linear_speed 5 m/s"),
    ("nubot1", RobotState(0.0, 0.0, 0.0, 0.0, 0.0, 1e6), "turn rate 1e\\+06 rad/s exceeds max_angular_speed"),
    ("football", BallState(1e10, 0.0, 0.11, 0.0, 0.0, 0.0), r"football at \(1e\+10, 0\) is outside the arena"),
    ("football", BallState(50.0, 0.0, 0.11, 0.0, 0.0, 0.0), r"football at \(50, 0\) is outside the arena"),
    ("football", BallState(0.0, 0.0, 0.11, 1e30, 0.0, 0.0), "speed 1e\\+30 m/s exceeds 30 m/s"),
    ("football", BallState(0.0, 0.0, 1e5, 0.0, 0.0, 0.0), r"height z=100000 m must lie in \[0, 20\] m"),
    ("football", BallState(0.0, 0.0, -1.0, 0.0, 0.0, 0.0), r"height z=-1 m must lie in \[0, 20\] m"),
    ("football", BallState(0.0, 0.0, 0.11, 0.0, 0.0, 0.0, 0.0, 0.0, 1e4), "spin 10000 rad/s exceeds"),
])
def test_absurd_model_states_are_refused_and_change_nothing(make_sim, name, state, message):
    sim = make_sim()
    robot_before, ball_before = sim.world.robot_state("nubot1"), sim.world.ball_state()
    with pytest.raises(SimVisualError, match=message):
        sim.set_model_state(name, state)
    assert sim.world.robot_state("nubot1") == robot_before and sim.world.ball_state() == ball_before
    for _ in range(100):
        sim.step()
    assert sim.world.robot_state("nubot1").x == pytest.approx(0.0, abs=1e-6)


def test_the_ball_may_be_put_into_a_goal_but_that_is_no_goal(make_sim, run):
    sim = make_sim()
    x = sim.config.field.half_length + 0.3
    sim.set_model_state("football", BallState(x, 0.0, 0.11, 0.0, 0.0, 0.0))
    assert sim.world.ball_state().x == pytest.approx(x)
    assert not [e for e in run(sim, 1.0) if isinstance(e, GoalScored)], "it never crossed the goal line"
    sim.set_model_state("football", BallState(8.0, 0.0, 0.11, 6.0, 0.0, 0.0, 0.0, 6.0 / 0.11, 0.0))
    assert [g.side for g in run(sim, 1.0) if isinstance(g, GoalScored)] == [1], "rolled in from the field, it is"


def test_a_ball_far_beyond_the_goal_line_is_no_goal(make_sim, run):
    sim = make_sim(robots=())
    sim.world.set_ball_state(BallState(50.0, 0.0, 0.11, 0.0, 0.0, 0.0))  # past the checks, e.g. a glitch
    assert not [e for e in run(sim, 0.1) if isinstance(e, GoalScored)], "only a ball inside the goal scores"


@pytest.mark.parametrize(("spawn", "message"), [
    (("rival1", math.nan, 0.0, 0.0, -1), r"rival1 must be at a finite position, got \(nan, 0.0\)"),
    (("rival1", 1e12, 0.0, 0.0, -1), r"rival1 at \(1e\+12, 0\) is outside the arena"),
])
def test_spawn_refuses_a_position_off_the_arena(make_sim, spawn, message):
    from sim_visual.params import RobotSpawn

    sim = make_sim()
    with pytest.raises(SimVisualError, match=message):
        sim.spawn_robot(RobotSpawn(*spawn))
    assert sim.model_names == ["nubot1", "football"]
    sim.step()


def test_spawn_refuses_more_than_the_maximum_number_of_robots(make_sim):
    from sim_visual.params import MAX_ROBOTS, RobotSpawn

    sim = make_sim()
    for k in range(2, MAX_ROBOTS + 1):
        sim.spawn_robot(RobotSpawn(f"nubot{k}", -8.0 + 0.8 * k, 5.0))
    with pytest.raises(SimVisualError, match=f"cannot spawn 'rival1': the simulator holds at most {MAX_ROBOTS}"):
        sim.spawn_robot(RobotSpawn("rival1", 0.0, -5.0))
    assert len(sim.plugins) == MAX_ROBOTS
    sim.delete_robot("nubot2")
    sim.spawn_robot(RobotSpawn("rival1", 0.0, -5.0))


def test_a_huge_velocity_command_is_clamped_to_a_speed_the_walls_stop(make_sim, run):
    from dataclasses import replace

    from sim_visual.params import PLUGIN_UPPER_BOUNDS

    sim = make_sim(robots=(("nubot1", 5.0, 0.0, 0.0),))
    with pytest.raises(ValueError, match="max_linear_speed must be at most 10, got 1e"):
        replace(sim.plugin_params, max_linear_speed=1e300)
    sim.update_params(replace(sim.plugin_params, max_linear_speed=PLUGIN_UPPER_BOUNDS["max_linear_speed"]))
    command, clamped = sim.command_velocity("nubot1", 1e200, 1e200, 0.0)
    assert clamped and math.hypot(command.vx, command.vy) == pytest.approx(10.0)
    for _ in range(400):  # 2 s at 10 m/s: far into the corner's walls
        sim.command_velocity("nubot1", 1e200, 1e200, 0.0)
        sim.step()
    state = sim.world.robot_state("nubot1")
    field = sim.config.field
    assert field.is_inside(state.x, state.y, field.border), f"the walls hold the robot, got {state}"


def test_a_robot_state_read_again_shows_every_change(make_sim, run):
    sim = make_sim([("nubot1", 0.0, 0.0, 0.0), ("nubot2", 2.0, 0.0, 0.0)])
    before = sim.world.robot_state("nubot1")
    assert sim.world.robot_state("nubot1") == before
    sim.world.drive_robot("nubot1", 1.0, 0.5, 0.2)  # heading 0: its own frame is the world's
    assert (sim.world.robot_state("nubot1").vx, sim.world.robot_state("nubot1").vy) == (1.0, 0.5)
    sim.set_model_state("nubot1", RobotState(-1.0, 1.0, 0.3, 0.0, 0.0, 0.0))
    assert astuple(sim.world.robot_state("nubot1")) == pytest.approx((-1.0, 1.0, 0.3, 0.0, 0.0, 0.0))
    sim.command_velocity("nubot1", 1.0, 0.0, 0.0)
    run(sim, 0.1)
    assert sim.world.robot_state("nubot1").x > -0.99
    ball = sim.world.ball_state()
    sim.set_model_state(sim.config.ball_name, BallState(1.0, 1.0, 0.11, 0.5, 0.0, 0.0))
    assert sim.world.ball_state() != ball and sim.world.ball_state().x == 1.0


def test_only_pairs_that_can_touch_reach_the_collision_callback(make_sim, run):
    sim = make_sim([("nubot1", 0.0, 0.0, 0.0), ("nubot2", 0.5, 0.0, 0.0)], ball=(0.3, 0.3))
    run(sim, 0.2)
    kinds = sim.world.pairs_offered()
    assert kinds, "robots, ball and carpet still meet"
    assert all("ball" in pair or "robot" in pair for pair in kinds), "no static geometry against itself"
    assert frozenset(("ground", "robot")) not in kinds, "robots glide above the carpet"



@pytest.mark.parametrize("start", [(9.3, 1.6, -math.pi / 2), (-9.3, -2.2, math.pi / 2)])
def test_a_robot_pressed_into_the_corner_of_a_goal_s_nets_leaves_the_solver_nothing_it_cannot_solve(make_sim, start):
    """Beside a goal and behind its line, pressed towards the wall: ODE's exact solver printed 'LCP internal error'
    a step after another where the robot wedged between the nets' corner and the wall."""
    sim = make_sim(robots=(("nubot1", *start),))
    for step in range(600):
        if step % 6 == 0:
            sim.command_velocity("nubot1", 3.0, 0.5, 0.0)
        sim.step()
    assert sim.world.solver_errors == 0


def test_ten_robots_jostling_at_full_speed_by_the_goals_and_walls_leave_the_solver_nothing_it_cannot_solve(make_sim):
    """Robots pressed into each other against the nets, the posts and the walls, turning (seeded): the contacts of a
    robot with another body came as two with one normal, and ODE's solver failed on them ('LCP internal error', 32
    times in these 5 s)."""
    rng = np.random.default_rng(0)
    names = [f"nubot{i}" for i in range(1, 6)] + [f"rival{i}" for i in range(1, 6)]
    starts = [(rng.uniform(7.5, 9.5) * rng.choice([-1, 1]), rng.uniform(-6.5, 6.5)) for _ in names]
    sim = make_sim(robots=[(n, x, y, rng.uniform(-3, 3), 1 if n.startswith("n") else -1)
                           for n, (x, y) in zip(names, starts)], ball=(8.0, 0.5))
    targets = {n: (rng.uniform(8.5, 10.5) * np.sign(x), rng.uniform(-7, 7)) for n, (x, _) in zip(names, starts)}
    for step in range(1000):
        if step % 6 == 0:
            for n in names:
                s = sim.world.robot_state(n)
                if step % 600 == 0:
                    targets[n] = (rng.uniform(8.0, 10.5) * rng.choice([-1, 1]), rng.uniform(-7, 7))
                dx, dy = targets[n][0] - s.x, targets[n][1] - s.y
                c, sn, k = math.cos(-s.theta), math.sin(-s.theta), 5.0 / max(math.hypot(dx, dy), 1e-6)
                sim.command_velocity(n, (c * dx - sn * dy) * k, (sn * dx + c * dy) * k, rng.uniform(-5, 5))
        sim.step()
    assert sim.world.solver_errors == 0
    for a, b in itertools.combinations(names, 2):  # and the robots still do not overlap
        sa, sb = sim.world.robot_state(a), sim.world.robot_state(b)
        assert math.hypot(sa.x - sb.x, sa.y - sb.y) > 2 * sim.config.robot.radius - 0.05, (a, b)
