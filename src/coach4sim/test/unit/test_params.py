"""Unit tests of the referee's configuration (coach4sim.params) and the shipped YAML and launch file."""

import xml.etree.ElementTree as ET

import pytest

from coach4sim.params import DEFAULT_TEAMS, RefereeNodeParams, RefereeParams, TeamSpec
from nubot_common import NubotCommonError
from nubot_common.field import FieldGeometry
from nubot_common.params import from_mapping, load_yaml


def test_shipped_config_has_the_briefed_numbers(config_dir):
    params = load_yaml(RefereeNodeParams, config_dir / "referee.yaml")
    assert params.teams == (TeamSpec("nubot", 1), TeamSpec("rival", -1)) == DEFAULT_TEAMS
    assert (params.setup_time, params.restart_timeout, params.stuck_time, params.stuck_distance) == (4, 20, 5, 0.3)
    assert (params.set_piece_time, params.carry_distance, params.area_time, params.area_robots) == (7, 3, 10, 1)
    assert (params.half_duration, params.halves, params.republish_period, params.auto) == (300, 2, 0.03, True)
    assert params.field == FieldGeometry(), "the field of /world (here the default world)"


def test_launch_file_loads_the_config_and_sets_the_briefed_arguments(config_dir):
    root = ET.parse(config_dir.parent / "launch" / "referee.launch").getroot()
    args = {a.get("name"): a.get("default") for a in root.iter("arg")}
    assert (args["auto"], args["half_duration"], args["halves"]) == ("true", "300.0", "2")
    node = root.find("node")
    assert (node.get("pkg"), node.get("type"), node.get("name")) == ("coach4sim", "referee", "referee")
    assert any("referee.yaml" in (r.get("file") or "") for r in node.iter("rosparam"))


def test_teams_come_from_a_list_of_mappings():
    params = from_mapping(RefereeNodeParams, {"teams": [{"prefix": "blue", "attack": -1}]})
    assert params.teams == (TeamSpec("blue", -1),)


@pytest.mark.parametrize(("data", "message"), [
    ({"teams": [{"prefix": "nubot", "attack": 1}, {"prefix": "rival", "attack": 1}]}, "opposite goals"),
    ({"teams": [{"prefix": "nubot2", "attack": 1}]}, "a team prefix is letters and underscores"),
    ({"teams": [{"prefix": "nubot", "attack": 0}]}, "attack must be 1 or -1, got 0"),
    ({"setup_time": 0.0}, "setup_time must be positive"),
    ({"halves": 0}, "halves must be at least 1"),
    ({"republish_period": -0.03}, r"republish_period must lie in \[0.005, 10\] s, got -0.03"),
    ({"republish_period": 1e300}, r"republish_period must lie in \[0.005, 10\] s, got 1e\+300"),  # wait() overflowed
    ({"republish_period": 1e-12}, r"republish_period must lie in \[0.005, 10\] s, got 1e-12"),  # a busy loop
    ({"stuck_tme": 5.0}, "unknown parameter"),
    ({"half_duration": "long"}, "half_duration: expected a number"),
    ({"goal_kick_distance": 8.5}, "past the halfway line"),
    ({"sim_namespace": "sim_visual"}, "must be absolute"),
])
def test_bad_values_are_refused_by_name(data, message):
    with pytest.raises(NubotCommonError, match=message):
        from_mapping(RefereeNodeParams, data)


def test_the_node_params_are_the_rules_params():
    params = RefereeNodeParams(half_duration=20.0)
    assert isinstance(params, RefereeParams) and params.half_duration == 20.0
