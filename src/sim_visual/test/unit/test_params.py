"""Unit tests of the simulator's configuration (sim_visual.params)."""

import pytest
import yaml

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping, load_yaml
from sim_visual.params import PhysicsParams, PluginParams, RobotSpawn, SimConfig, SimNodeParams


def test_shipped_config_loads_with_the_chapter_numbers(config_dir):
    params = load_yaml(SimNodeParams, config_dir / "sim_visual.yaml")
    sim = params.sim
    assert sim.physics.step_size <= 0.007 and sim.physics.gravity == -9.8
    assert (sim.robot.mass, sim.robot.inertia_zz, sim.robot.friction) == (31.0, 2.86, 0.1)
    assert (sim.ball.radius, sim.ball.mass) == (0.11, 0.41)
    assert (sim.field.length, sim.field.width, sim.field.goal_width, sim.field.goal_height) == (18, 12, 2.4, 1.0)
    assert sim.plugin.dribble_distance == 0.5 and sim.plugin.dribble_angle_deg == 30.0


def test_single_robot_world_has_nubot1_attacking_plus_x(config_dir):
    data = yaml.safe_load((config_dir / "single_robot.yaml").read_text())
    params = from_mapping(SimNodeParams, data)
    assert params.sim.robots == (RobotSpawn("nubot1", -2.0, 0.0, 0.0, 1),)


def test_step_size_above_the_chapter_maximum_is_refused():
    with pytest.raises(ValueError, match="step_size must lie in"):
        PhysicsParams(step_size=0.01)


def test_bad_values_are_named():
    with pytest.raises(NubotCommonError, match="dribble_distance must be positive"):
        from_mapping(SimConfig, {"plugin": {"dribble_distance": -1.0}})
    with pytest.raises(NubotCommonError, match="unknown parameter"):
        from_mapping(SimConfig, {"plugin": {"dribble_distanse": 0.4}})
    with pytest.raises(ValueError, match="unique"):
        SimConfig(robots=(RobotSpawn("nubot1"), RobotSpawn("nubot1")))
    with pytest.raises(ValueError, match="attack must be 1 or -1"):
        RobotSpawn("nubot1", attack=0)


def test_dribble_half_angle_is_half_the_cone():
    assert PluginParams(dribble_angle_deg=30.0).dribble_half_angle == pytest.approx(0.2617993878)
