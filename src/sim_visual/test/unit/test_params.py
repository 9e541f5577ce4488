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


def test_every_reconfigurable_parameter_has_an_upper_bound_that_is_enforced():
    import dataclasses

    from sim_visual.params import NOISE_UPPER_BOUNDS, PLUGIN_UPPER_BOUNDS, NoiseParams

    for cls, bounds in ((PluginParams, PLUGIN_UPPER_BOUNDS), (NoiseParams, NOISE_UPPER_BOUNDS)):
        assert set(bounds) == {f.name for f in dataclasses.fields(cls)}
        for name, high in bounds.items():
            cls(**{name: high})
            with pytest.raises(ValueError, match=f"{name} must be at most {high:g}, got"):
                cls(**{name: high * 1.01})


def test_physically_absurd_values_are_refused_with_their_bound():
    with pytest.raises(NubotCommonError, match="max_linear_speed must be at most 10, got 100"):
        from_mapping(SimConfig, {"plugin": {"max_linear_speed": 100.0}})
    with pytest.raises(NubotCommonError, match="real_time_factor must be at most 100, got 1000"):
        from_mapping(SimNodeParams, {"real_time_factor": 1000.0})
    for nice in (-5, 20):
        with pytest.raises(NubotCommonError, match=rf"cpu_nice must lie in \[0, 19\] \(0: the default priority\), "
                                                   rf"got {nice}"):
            from_mapping(SimNodeParams, {"cpu_nice": nice})
    with pytest.raises(ValueError, match=r"gravity must be negative \(down\) and at least -50, got -1000000000000"):
        PhysicsParams(gravity=-1e12)
    with pytest.raises(ValueError, match="seed must not be negative, got -1"):
        SimConfig(seed=-1)


def test_start_poses_must_lie_inside_the_arena_of_the_world():
    from nubot_common.world_description import load_world

    with pytest.raises(NubotCommonError, match=r"nubot1's start at \(1e\+12, 0\) is outside the arena"):
        from_mapping(SimConfig, {"robots": [{"name": "nubot1", "x": 1e12}]})
    with pytest.raises(NubotCommonError, match=r"ball_start at \(0, 1e\+12\) is outside the arena"):
        from_mapping(SimConfig, {"ball_start": [0.0, 1e12]})
    with pytest.raises(ValueError, match="nubot1's heading theta must be finite, got nan"):
        RobotSpawn("nubot1", theta=float("nan"))
    with pytest.raises(ValueError, match=r"outside the arena: \|x\| <= 10 m"):
        SimConfig(robots=(RobotSpawn("nubot1", 11.5),))
    assert SimConfig(world=load_world("22x14"), robots=(RobotSpawn("nubot1", 11.5),)).robots[0].x == 11.5


def test_the_robot_list_is_limited():
    from sim_visual.params import MAX_ROBOTS

    robots = [{"name": f"nubot{k}", "x": 0.4 * k - 8.0} for k in range(1, MAX_ROBOTS + 2)]
    with pytest.raises(NubotCommonError, match=f"at most {MAX_ROBOTS} robots, got {MAX_ROBOTS + 1}"):
        from_mapping(SimConfig, {"robots": robots})
    assert len(from_mapping(SimConfig, {"robots": robots[:MAX_ROBOTS]}).robots) == MAX_ROBOTS


@pytest.mark.parametrize(("params", "message"), [
    ({"rate": 0}, "rate must be positive, got 0"),
    ({"rate": 1e9}, "rate must be at most 1000 Hz"),
    ({"team_size": 0}, r"team_size must lie in \[1, 20\], got 0"),
    ({"team": "nubot1"}, "a team prefix is letters and underscores"),
    ({"team": 7}, "team: expected a string, got 7"),
    ({"max_age": -1.0}, "max_age must be positive, got -1"),
])
def test_sim_interface_parameters_are_checked(params, message):
    from sim_visual.params import SimInterfaceParams

    assert from_mapping(SimInterfaceParams, {"team": "rival", "team_size": 3}).team_size == 3
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(SimInterfaceParams, params, "~")


def test_each_team_s_goalie_is_the_one_goalies_names_else_the_agent_id_goalie_id():
    params = SimNodeParams(goalies="nubot3,rival1")
    assert [n for n in ("nubot1", "nubot3", "rival1", "rival3") if params.is_goalie(n)] == ["nubot3", "rival1"]
    partly = SimNodeParams(goalie_id=2, goalies="rival4")
    assert [n for n in ("nubot1", "nubot2", "rival2", "rival4", "other2") if partly.is_goalie(n)] == \
        ["nubot2", "rival4", "other2"]
    assert not any(SimNodeParams(goalie_id=0).is_goalie(n) for n in ("nubot1", "rival1"))
    with pytest.raises(ValueError, match="two robots of one team"):
        SimNodeParams(goalies="nubot1,nubot2")
    with pytest.raises(ValueError, match="not all"):
        SimNodeParams(goalies="all")
    with pytest.raises(ValueError, match="goalies: .*'keeper' is not a robot name"):
        from_mapping(SimNodeParams, {"goalies": "keeper"})
