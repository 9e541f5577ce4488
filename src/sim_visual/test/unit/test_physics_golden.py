"""The compiled physics world holds to the golden traces recorded from the Python before it moved to C++:
``physics.npz`` (``python -m nubot_tools.golden physics --seeds 1 --seconds 15``), every change of the world in 15 s
of a seeded lockstep match and after each of its 3000 steps every body's position, orientation and velocities; and
``drive.npz``, every call of the Python base model (``limit_drive``) over 2 x 10 s of seeded matches (seeds 0 and 1)."""

import dataclasses
import math
from pathlib import Path

import numpy as np
import pytest

from nubot_common.commands import BodyVelocity
from nubot_common.field import FieldGeometry
from nubot_common.world_description import BallBody, RobotBody
from sim_visual.params import PhysicsParams, PluginParams
from sim_visual.rules import drive_limits, limit_drive
from sim_visual.world import BallState, PhysicsWorld, RobotState

TRACE = Path(__file__).resolve().parents[1] / "golden" / "physics.npz"
ADD, REMOVE, SET_ROBOT, DRIVE, SET_BALL, HOLDER, STEP, ROBOT, BALL = range(9)  # nubot_tools.golden.PHYSICS_OPS


def _replay(restore_each_step: bool):
    """Feed the trace to new worlds; yield (step, body, got, want) after every step. With ``restore_each_step`` every
    body is put back where the trace had it after the step before, so that each step is judged on its own."""
    trace = np.load(TRACE)
    worlds: dict[int, PhysicsWorld] = {}
    names: dict[int, list[str]] = {}
    recorded: dict[int, dict] = {}
    got: dict = {}
    steps = 0
    for (w, op, robot), v in zip(trace["index"].tolist(), trace["values"]):
        if w not in worlds:
            worlds[w] = PhysicsWorld(FieldGeometry(), PhysicsParams(), RobotBody(), BallBody())
            names[w], recorded[w] = [], {}
        world = worlds[w]
        name = names[w][robot] if op not in (ADD, STEP) and 0 <= robot < len(names[w]) else None
        if op == ADD:
            names[w].append(f"robot{robot}")
            world.add_robot(names[w][-1], *v[:3])
        elif op == REMOVE:
            world.remove_robot(name)
        elif op == SET_ROBOT:
            world.set_robot_state(name, RobotState(*v[:6]))
        elif op == DRIVE:
            world.drive_robot(name, *v[:3], world_frame=bool(v[3]))
        elif op == SET_BALL:
            world.set_ball_state(BallState(*v[:9]))
        elif op == HOLDER:
            world.set_ball_collides_with(name)
        elif op == STEP:
            touched = world.step(float(v[0]))
            steps += 1
            assert touched == {names[w][i] for i in range(len(names[w])) if robot >> i & 1}, f"step {steps}"
            got = world.bodies()
        else:
            key = name if op == ROBOT else None
            recorded[w][key] = tuple(v)
            yield steps, key, np.array(got[key]), v
            if op == BALL and restore_each_step:  # the ball's row ends a step's: the next changes start from here
                world.set_bodies(recorded[w])


@pytest.mark.parametrize("restore_each_step", [False, True], ids=["free-running", "step-by-step"])
def test_the_compiled_world_steps_as_the_recorded_one(restore_each_step):
    """Free-running, the same library (Debian's libode) fed the same calls in the same order gives the same numbers
    to the last bit on this platform; step by step, from the recorded bodies, within 1e-9 (a body put back is
    renormalised by ODE, which moves its quaternion by an ulp)."""
    worst, where, steps = 0.0, None, 0
    for steps, body, got, want in _replay(restore_each_step):
        diff = float(np.max(np.abs(got - want)))
        if diff > worst:
            worst, where = diff, (steps, body)
    assert steps == 3000
    assert worst <= (1e-9 if restore_each_step else 0.0), f"worst difference {worst:.3g} at step and body {where}"


def test_the_compiled_base_model_gives_the_recorded_velocities():
    """``limit_drive`` against every call of the Python one in ``drive.npz``: within 1e-12 m/s (libm's hypot and
    Python's may differ in the last bit)."""
    calls = np.load(TRACE.with_name("drive.npz"))["calls"]
    assert len(calls) == 40000
    worst = 0.0
    for row in calls:
        accel, brake, turn = row[7:10]
        params = dataclasses.replace(PluginParams(), max_linear_accel=accel, max_linear_brake=brake,
                                     max_angular_accel=turn)
        got = limit_drive(tuple(row[0:3]), tuple(row[3:6]), float(row[6]), params)
        worst = max(worst, float(np.max(np.abs(np.array(got) - row[10:13]))))
    assert worst <= 1e-12


def test_driving_every_base_at_once_is_driving_each_within_its_limits():
    """``drive_robots``: each robot's command turned into the world frame by its heading, reached within the limits
    (or at once for a robot its wheels drive), and the robot driven so; a command older than the timeout is a stop."""
    world = PhysicsWorld(FieldGeometry(), PhysicsParams(), RobotBody(), BallBody())
    world.add_robot("a", -2.0, 0.0, math.pi / 2)
    world.add_robot("b", 2.0, 0.0, 0.0)
    world.add_robot("c", 0.0, 3.0, 0.0)
    params = PluginParams()
    world.set_command("a", BodyVelocity(2.0, 0.0, 1.0), 0.0)
    world.set_command("b", BodyVelocity(1.0, 0.5, 0.0), 0.0)
    world.set_driven_by_wheels("b")
    world.set_command("c", BodyVelocity(1.0, 0.0, 0.0), -1.0)  # older than the timeout below
    world.set_base_drive("c", 0.0, 0.5, 0.0)
    world.drive_robots(0.005, 0.0, 0, 0.5, drive_limits(params), (4, 0.3, 0.2, 1.0))
    drive_a = limit_drive((0.0, 0.0, 0.0), (0.0, 2.0, 1.0), 0.005, params)
    assert world.base_drive("a") == pytest.approx(drive_a, abs=1e-12)
    assert world.base_drive("b") == pytest.approx((1.0, 0.5, 0.0))
    assert world.base_drive("c") == tuple(limit_drive((0.0, 0.5, 0.0), (0.0, 0.0, 0.0), 0.005, params))
    assert world.bodies()["a"][7:9] == pytest.approx(drive_a[:2]) and world.bodies()["a"][12] == drive_a[2]
    assert world.command("a") == BodyVelocity(2.0, 0.0, 1.0) and not world.stuck("a")
    with pytest.raises(ValueError, match="finite"):
        world.set_command("a", BodyVelocity(math.nan, 0.0, 0.0), 0.0)
    world.reset_base("a")
    assert world.command("a") == BodyVelocity() and world.base_drive("a") == (0.0, 0.0, 0.0)


def _handling_world() -> PhysicsWorld:
    """Two robots near the ball, their handlers on: one takes it and then turns faster than its grip holds."""
    from sim_visual.rules import handler_params

    world = PhysicsWorld(FieldGeometry(), PhysicsParams(), RobotBody(), BallBody())
    world.add_robot("a", 0.0, 0.0, 0.0)
    world.add_robot("b", 1.0, 1.0, math.pi)
    world.set_ball_state(BallState(0.42, 0.0, 0.11, 0.0, 0.0, 0.0))
    world.set_ball_handler(handler_params(PluginParams(), 0.11))
    for name in ("a", "b"):
        world.set_dribbling(name, True)
    return world


def test_advancing_the_world_is_its_parts_in_order():
    """``advance``: the bases driven, the holder's grip checked (the ball let go when it slips), the step, a capture
    after it and the carried ball, as the separate calls make them; bodies the same to the last bit."""
    one, parts = _handling_world(), _handling_world()
    params = PluginParams()
    limits, stuck = drive_limits(params), (4, 0.3, 0.2, params.stuck_time)
    one.set_drive_params(params.command_timeout, limits, stuck)
    holders: list[str | None] = [None, None]
    seen = {"captured": 0, "slipped": 0, "quiet": 0}
    dt = 0.005
    for k in range(400):
        time = k * dt
        turn = 6.0 if 100 <= k < 200 else 0.5  # faster than the grip's 4 rad/s for 0.5 s: the ball slips
        for world in (one, parts):
            world.set_command("a", BodyVelocity(0.3, 0.0, turn), time)
            world.set_command("b", BodyVelocity(0.5, 0.0, 0.0), time)
        happened = one.advance(dt, time, k, holders[0])
        seen["quiet"] += happened is None
        touched, slipped, captured = happened if happened is not None else (set(), False, None)
        holders[0] = None if slipped else holders[0]
        holders[0] = captured if captured is not None else holders[0]
        parts.drive_robots(dt, time, k, params.command_timeout, limits, stuck)
        slipped_parts = holders[1] is not None and parts.grip_slips(holders[1], dt, time)
        holder = None if slipped_parts else holders[1]
        parts.set_ball_collides_with(holder)
        touched_parts = parts.step(dt)
        captured_parts = parts.first_capture((k + 1) * dt) if holder is None else None
        holder = captured_parts if holder is None else holder
        if holder is not None:
            parts.carry_ball(holder)
        holders[1] = holder
        assert (touched, slipped, captured) == (touched_parts, slipped_parts, captured_parts), k
        assert one.bodies() == parts.bodies(), k
        seen["captured"] += captured is not None
        seen["slipped"] += slipped
    assert seen["captured"] >= 1 and seen["slipped"] >= 1 and seen["quiet"] >= 1, seen
    assert one.step_seconds > 0.0


def test_the_usual_step_says_nothing_and_a_ball_at_a_goal_line_always_speaks():
    """``advance`` answers None alone when the ball was not touched, slipped or taken and lies short of both goal
    lines; a ball on or past a goal line is always reported, so that the simulator looks for a goal."""
    from sim_visual.rules import handler_params

    world = PhysicsWorld(FieldGeometry(), PhysicsParams(), RobotBody(), BallBody())
    with pytest.raises(RuntimeError, match="set_base_params"):
        world.advance(0.005, 0.0, 0, None)
    params = PluginParams()
    world.set_drive_params(params.command_timeout, drive_limits(params), (4, 0.3, 0.2, params.stuck_time))
    world.set_ball_handler(handler_params(params, 0.11))
    world.add_robot("a", -3.0, 0.0, 0.0)
    half = world.field.half_length
    for x, quiet in ((0.0, True), (half - 0.2, True), (half + 0.05, False), (-half - 0.3, False)):
        world.set_ball_state(BallState(x, 2.0, 0.11, 0.0, 0.0, 0.0))
        assert (world.advance(0.005, 0.0, 0, None) is None) == quiet, x
    assert world.advance(0.005, 0.005, 1, None) == (set(), False, None)  # still past its line
    with pytest.raises(ValueError, match="finite"):
        world.set_drive_params(math.nan, drive_limits(params), (4, 0.3, 0.2, params.stuck_time))
    with pytest.raises(ValueError, match="stuck_every"):
        world.set_drive_params(0.3, drive_limits(params), (0, 0.3, 0.2, params.stuck_time))
