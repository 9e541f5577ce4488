"""robot.launch, parsed (nothing started): one node a robot by default, its two halves' parameters apart; two
nodes with processes:=two; anything else refused by roslaunch, naming the argument."""

import subprocess
from pathlib import Path

from nubot_common.launch_checks import launched, nested
from nubot_common.params import from_mapping
from nubot_control.params import ControlParams
from world_model.params import WorldModelParams

LAUNCH = Path(__file__).resolve().parents[2] / "launch" / "robot.launch"
NODE_KEYS = {"package", "type", "remap", "robot", "agent_id", "rate", "target_period", "flight_timeout"}


def test_by_default_a_robot_is_one_node_with_both_halves_parameters():
    nodes = launched(LAUNCH, "robot:=rival3", "goalie_id:=3", "tracker:=baseline")
    assert set(nodes) == {"/rival3/robot"}
    assert nodes["/rival3/robot"]["type"] == "robot_node"
    node = nested(nodes["/rival3/robot"])
    assert node["robot"] == "rival3"
    model = node.pop("world_model")
    from_mapping(WorldModelParams, {k: v for k, v in model.items() if k not in NODE_KEYS}, "~world_model")
    control = from_mapping(ControlParams, {k: v for k, v in node.items() if k not in NODE_KEYS}, "~")
    assert (control.play.goalie_id, control.motion.tracker) == (3, "baseline")


def test_with_two_processes_the_world_model_and_control_are_nodes_of_their_own():
    nodes = launched(LAUNCH, "robot:=nubot2", "processes:=two")
    assert set(nodes) == {"/nubot2/world_model", "/nubot2/nubot_control"}
    assert nodes["/nubot2/world_model"]["type"] == "world_model_node"
    assert nodes["/nubot2/nubot_control"]["type"] == "nubot_control_node"
    assert not any(key.startswith("world_model/") for key in nodes["/nubot2/nubot_control"])


def test_an_unknown_layout_is_refused_naming_the_argument():
    done = subprocess.run(["roslaunch", "--nodes", str(LAUNCH), "robot:=nubot2", "processes:=three"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "processes_must_be_one_or_two" in done.stdout + done.stderr
