"""front_vision's launch files, parsed (nothing started): robot.launch starts it for a robot seeing through its
cameras that is not its team's goalie, with the shipped parameters, camera and colour table, which all load."""

from __future__ import annotations

from pathlib import Path

import pytest

from front_vision.pipeline import FrontVisionParams
from nubot_common.camera_model import load_camera
from nubot_common.launch_checks import launched, nested
from nubot_common.params import from_mapping, load_yaml
from omni_vision.colors import ColorTable

SRC = Path(__file__).resolve().parents[3]



@pytest.mark.parametrize("goalie, perception", [("true", "vision"), ("false", "vision"), ("true", "truth"),
                                              ("false", "truth")])
def test_robot_launch_starts_front_vision_for_a_regular_robot_seeing_through_its_cameras(goalie, perception):
    nodes = launched(SRC / "nubot_control" / "launch" / "robot.launch", "robot:=rival3", "goalie_id:=3",
                     f"goalie:={goalie}", f"perception:={perception}")
    assert ("/rival3/front_vision" in nodes) == (perception == "vision" and goalie == "false")


def test_the_node_gets_the_shipped_parameters_camera_and_table():
    node = launched(SRC / "front_vision" / "launch" / "front_vision.launch", "robot:=nubot2")["/nubot2/front_vision"]
    assert node["robot"] == "nubot2" and node["remap"]["image"] == "/nubot2/front_camera/image_raw"
    load_camera(node["camera"])
    ColorTable.load(node["color_table"])
    own = nested(node, ("robot", "camera", "color_table"))
    shipped = load_yaml(FrontVisionParams, SRC / "front_vision" / "config" / "front_vision.yaml")
    assert from_mapping(FrontVisionParams, own) == shipped == FrontVisionParams(), "the YAML states the defaults"
