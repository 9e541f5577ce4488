"""A robot driven by its wheels' rim speeds (the hardware controller's simulated drive) instead of by VelCmd."""

import math

import numpy as np
import pytest

from nubot_common.kinematics import GOALIE, REGULAR
from sim_visual import SimVisualError


@pytest.mark.parametrize("layout", [REGULAR, GOALIE], ids=["regular", "goalie"])
def test_wheel_speeds_move_the_robot_as_the_body_velocity_they_mean(make_sim, run, layout):
    sim = make_sim(robots=(("nubot1", 0.0, 0.0, math.pi / 2),))
    for _ in range(10):  # a drive sends its wheel speeds every cycle (the plugin stops a silent robot)
        sim.command_wheels("nubot1", layout, layout.wheel_speeds(1.0, 0.5, 0.0))
        run(sim, 0.1)
    state = sim.world.robot_state("nubot1")
    # heading +y: body forward is world +y, body left is world -x; the wheels' dynamics are their drive's, so the base
    # follows them at once
    assert (state.x, state.y) == pytest.approx((-0.5, 1.0), abs=0.05)
    assert sim.wheel_ground_speeds("nubot1", layout) == pytest.approx(layout.wheel_speeds(1.0, 0.5, 0.0), abs=0.02)


def test_a_robot_against_the_goal_gives_its_wheels_no_ground_speed(make_sim, run):
    sim = make_sim(robots=(("nubot1", 8.4, 0.0, 0.0),))
    ground = []
    for _ in range(60):
        sim.command_wheels("nubot1", REGULAR, REGULAR.wheel_speeds(2.0, 0.0, 0.0))
        run(sim, 0.05)
        ground.append(np.abs(sim.wheel_ground_speeds("nubot1", REGULAR)).mean())
    assert sim.world.robot_state("nubot1").x < 9.5  # held by the goal
    assert np.mean(ground[20:]) < 0.25 * np.abs(REGULAR.wheel_speeds(2.0, 0.0, 0.0)).mean()


def test_wheel_speeds_that_are_not_finite_are_refused(make_sim):
    sim = make_sim()
    with pytest.raises(SimVisualError, match="finite"):
        sim.command_wheels("nubot1", REGULAR, np.array([1.0, float("nan"), 0.0, 0.0]))
