"""kinect_ball's launch files, parsed (nothing started): robot.launch starts it for the goalie seeing through its
cameras only, with the shipped parameters, which load into KinectBallParams."""

from pathlib import Path

import pytest

from kinect_ball.pipeline import KinectBallParams
from nubot_common.launch_checks import launched, nested
from nubot_common.params import from_mapping, load_yaml

SRC = Path(__file__).resolve().parents[3]



@pytest.mark.parametrize("robot, goalie_id, perception, started", [
    ("nubot1", "1", "vision", True), ("nubot2", "1", "vision", False), ("rival3", "3", "vision", True),
    ("nubot1", "1", "truth", False), ("nubot11", "1", "vision", False),
])
def test_robot_launch_starts_kinect_ball_for_the_goalie_seeing_through_its_cameras(robot, goalie_id, perception,
                                                                                   started):
    nodes = launched(SRC / "nubot_control" / "launch" / "robot.launch", f"robot:={robot}",
                     f"goalie_id:={goalie_id}", f"perception:={perception}")
    assert (f"/{robot}/kinect_ball" in nodes) == started


def test_the_node_gets_the_shipped_parameters_and_its_pose_topic():
    nodes = launched(SRC / "kinect_ball" / "launch" / "kinect_ball.launch", "robot:=nubot1")
    node = nodes["/nubot1/kinect_ball"]
    assert node["robot"] == "nubot1" and node["remap"]["pose"] == "/nubot1/omnivision/OmniVisionInfo"
    shipped = load_yaml(KinectBallParams, SRC / "kinect_ball" / "config" / "kinect_ball.yaml")
    own = nested(node, ("robot",))
    assert from_mapping(KinectBallParams, own) == shipped == KinectBallParams(), "the YAML states the defaults"
