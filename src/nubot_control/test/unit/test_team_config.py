"""Team configurations: world poses and the generated team launch file."""

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping, load_yaml
from nubot_common.world_description import load_world
from nubot_control.team_config import TeamConfig, team_launch_xml

TEAMS = Path(__file__).resolve().parents[2] / "config" / "teams"


def test_both_shipped_teams_load_and_face_each_other():
    nubot, rival = load_yaml(TeamConfig, TEAMS / "nubot.yaml"), load_yaml(TeamConfig, TEAMS / "rival.yaml")
    assert nubot.robot_names() == [f"nubot{k}" for k in range(1, 6)]
    assert (nubot.attack, rival.attack) == (1, -1)
    for (_, x1, y1, t1), (_, x2, y2, t2) in zip(nubot.world_poses(), rival.world_poses()):
        assert (x2, y2) == pytest.approx((-x1, -y1)), "the same formation, mirrored"
        assert abs(math.remainder(t2 - t1, 2 * math.pi)) == pytest.approx(math.pi)
    assert all(x < 0 for _, x, _, _ in nubot.world_poses()) and all(x > 0 for _, x, _, _ in rival.world_poses())


def test_launch_file_prefixes_every_robot():
    team = load_yaml(TeamConfig, TEAMS / "rival.yaml")
    root = ET.fromstring(team_launch_xml(team))
    relay = root.find("node")
    assert relay.get("type") == "sim_interface" and relay.get("ns") == "rival"
    assert relay.get("clear_params") == "true", "a key an earlier team launch left cannot refuse the relay"
    robots = [inc.find("arg[@name='robot']").get("value") for inc in root.findall("include")]
    assert robots == [f"rival{k}" for k in range(1, 6)]
    goalies = [inc.find("arg[@name='goalie']").get("value") for inc in root.findall("include")]
    assert goalies == ["true" if k == team.goalie else "false" for k in range(1, 6)] and goalies.count("true") == 1
    assert {inc.find("arg[@name='tracker']").get("value") for inc in root.findall("include")} == {""}
    chosen = ET.fromstring(team_launch_xml(team, "baseline"))
    assert {inc.find("arg[@name='tracker']").get("value") for inc in chosen.findall("include")} == {"baseline"}
    for processes in ("one", "two"):
        split = ET.fromstring(team_launch_xml(team, processes=processes))
        assert {inc.find("arg[@name='processes']").get("value") for inc in split.findall("include")} == {processes}
    with pytest.raises(NubotCommonError, match="processes per robot: one or two, not 'three'"):
        team_launch_xml(team, processes="three")


def test_bad_team_configs_are_refused():
    with pytest.raises(NubotCommonError, match=r"attack must be 1 \(the goal at \+x\) or -1 \(the goal at -x\), got 0"):
        from_mapping(TeamConfig, {"name": "x", "prefix": "x", "attack": 0, "goalie": 1, "robots": [{"x": 0, "y": 0}]})
    with pytest.raises(NubotCommonError, match="goalie must be one of the robots"):
        from_mapping(TeamConfig, {"name": "x", "prefix": "x", "attack": 1, "goalie": 3, "robots": [{"x": 0, "y": 0}]})
    with pytest.raises(NubotCommonError, match="a team prefix is letters and underscores"):
        from_mapping(TeamConfig, {"name": "x", "prefix": "x2", "attack": 1, "goalie": 1, "robots": [{"x": 0, "y": 0}]})


def test_start_poses_are_checked_against_the_match_field():
    team = from_mapping(TeamConfig, {"name": "x", "prefix": "x", "attack": -1, "goalie": 1,
                                     "robots": [{"x": -8.4, "y": 0}, {"x": -10.5, "y": 6.5}]})
    team.check_field(load_world("22x14").field)
    with pytest.raises(ValueError, match=r"x2 starts at \(-10.5, 6.5\), off the 18 x 12 m field"):
        team.check_field(load_world("18x12").field)
