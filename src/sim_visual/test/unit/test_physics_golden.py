"""The compiled physics world holds to the golden trace recorded from the Python world before it moved to C++
(``python -m nubot_tools.golden physics --seeds 1 --seconds 15``): every change of the world in 15 s of a seeded
lockstep match, and after each of its 3000 steps every body's position, orientation and velocities."""

from pathlib import Path

import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.world_description import BallBody, RobotBody
from sim_visual.params import PhysicsParams
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
