from pathlib import Path

import pytest

from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator


@pytest.fixture
def config_dir() -> Path:
    return Path(__file__).resolve().parents[2] / "config"


@pytest.fixture
def make_sim():
    """Build a simulator with the given robots (name, x, y, theta) and ball start."""
    def build(robots=(("nubot1", 0.0, 0.0, 0.0),), ball=(3.0, 3.0), **overrides):
        spawns = tuple(RobotSpawn(*r) for r in robots)
        return Simulator(SimConfig(robots=spawns, ball_start=ball, **overrides))
    return build


@pytest.fixture
def run():
    """Step a simulator for some seconds of sim time; return all events."""
    def step_for(sim, seconds):
        events = []
        end = sim.time + seconds
        while sim.time < end - 1e-9:
            events += sim.step()
        return events
    return step_for
