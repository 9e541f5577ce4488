"""kinect_ball's launch files, parsed (nothing started): robot.launch starts it for the goalie seeing through its
cameras only, with the shipped parameters, which load into KinectBallParams."""

from pathlib import Path

import pytest

from kinect_ball.pipeline import KinectBallParams
from nubot_common.launch_checks import launched, nested
from nubot_common.params import from_mapping, load_yaml

SRC = Path(__file__).resolve().parents[3]



@pytest.mark.parametrize("goalie, perception", [("true", "vision"), ("false", "vision"), ("true", "truth"),
                                              ("false", "truth")])
def test_robot_launch_starts_kinect_ball_for_the_goalie_seeing_through_its_cameras(goalie, perception):
    nodes = launched(SRC / "nubot_control" / "launch" / "robot.launch", "robot:=rival3", "goalie_id:=3",
                     f"goalie:={goalie}", f"perception:={perception}")
    assert ("/rival3/kinect_ball" in nodes) == (perception == "vision" and goalie == "true")


def test_the_node_gets_the_shipped_parameters_and_its_pose_topic():
    nodes = launched(SRC / "kinect_ball" / "launch" / "kinect_ball.launch", "robot:=nubot1")
    node = nodes["/nubot1/kinect_ball"]
    assert node["robot"] == "nubot1" and node["remap"]["pose"] == "/nubot1/omnivision/OmniVisionInfo"
    shipped = load_yaml(KinectBallParams, SRC / "kinect_ball" / "config" / "kinect_ball.yaml")
    own = nested(node, ("robot",))
    assert from_mapping(KinectBallParams, own) == shipped == KinectBallParams(), "the YAML states the defaults"
