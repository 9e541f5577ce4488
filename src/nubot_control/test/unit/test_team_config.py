"""Team configurations: world poses and the generated team launch file."""

import math
import xml.etree.ElementTree as ET
from pathlib import Path

import pytest

from nubot_common import NubotCommonError
from nubot_common.params import from_mapping, load_yaml
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
    robots = [inc.find("arg[@name='robot']").get("value") for inc in root.findall("include")]
    assert robots == [f"rival{k}" for k in range(1, 6)]
    assert {inc.find("arg[@name='tracker']").get("value") for inc in root.findall("include")} == {""}
    chosen = ET.fromstring(team_launch_xml(team, "baseline"))
    assert {inc.find("arg[@name='tracker']").get("value") for inc in chosen.findall("include")} == {"baseline"}


def test_bad_team_configs_are_refused():
    with pytest.raises(NubotCommonError, match="attack must be 1 or -1"):
        from_mapping(TeamConfig, {"name": "x", "prefix": "x", "attack": 0, "goalie": 1, "robots": [{"x": 0, "y": 0}]})
    with pytest.raises(NubotCommonError, match="goalie must be one of the robots"):
        from_mapping(TeamConfig, {"name": "x", "prefix": "x", "attack": 1, "goalie": 3, "robots": [{"x": 0, "y": 0}]})
