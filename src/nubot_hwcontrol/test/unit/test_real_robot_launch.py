"""real_robot.launch, parsed (nothing started): the robot's world model and control run as one node, /robot, by
default, with each half's parameters; two nodes with processes:=two; the world model alone with control:=false;
any other layout refused by roslaunch, naming the argument."""

import subprocess
from pathlib import Path

from nubot_common.launch_checks import launched, nested
from nubot_common.params import from_mapping
from nubot_control.params import ControlParams
from world_model.params import WorldModelParams

LAUNCH = Path(__file__).resolve().parents[2] / "launch" / "real_robot.launch"
NODE_KEYS = {"package", "type", "remap", "robot", "agent_id", "rate", "target_period", "flight_timeout"}
ALWAYS = {"/omni_vision", "/nubot_hwcontrol", "/nubot3/team_link"}


def test_by_default_the_world_model_and_control_are_one_node_under_the_robot_s_own_names():
    nodes = launched(LAUNCH, "robot:=3", "tracker:=baseline")
    assert set(nodes) == ALWAYS | {"/robot"}
    node = nodes["/robot"]
    assert (node["type"], node["robot"], node["play/goalie_id"]) == ("robot_node", "nubot3", 1)
    # the robot's un-prefixed names: what the two nodes published, the one node publishes
    assert node["remap"]["/nubot3/worldmodel/worldmodelinfo"] == "/worldmodel/worldmodelinfo"
    assert node["remap"]["/nubot3/nubotcontrol/velcmd"] == "/nubotcontrol/velcmd"
    control = nested(node, NODE_KEYS)
    model = control.pop("world_model")
    from_mapping(WorldModelParams, {k: v for k, v in model.items() if k not in NODE_KEYS}, "~world_model")
    assert from_mapping(ControlParams, control, "~").motion.tracker == "baseline"


def test_two_processes_and_no_control_keep_their_nodes():
    assert set(launched(LAUNCH, "robot:=3", "processes:=two")) == ALWAYS | {"/world_model", "/nubot_control"}
    assert set(launched(LAUNCH, "robot:=3", "control:=false")) == ALWAYS | {"/world_model"}


def test_an_unknown_layout_is_refused_naming_the_argument():
    done = subprocess.run(["roslaunch", "--nodes", str(LAUNCH), "robot:=3", "processes:=three"],
                          capture_output=True, text=True, timeout=60)
    assert done.returncode != 0 and "processes_must_be_one_or_two" in done.stdout + done.stderr


def test_every_node_of_the_robot_is_required_so_a_robot_that_cannot_run_one_stops_whole():
    """real_robot.launch robot:=9 once left the simulator and hardware control driving after the world model and the
    team link died with FATAL errors: a required node's end ends the launch, and roslaunch names it."""
    for args in ((), ("processes:=two",), ("control:=false",), ("backend:=sim",)):
        nodes = launched(LAUNCH, "robot:=3", *args)
        robot = {name: node["required"] for name, node in nodes.items() if name != "/referee"}  # the field's, not it
        assert len(robot) >= 4 and all(robot.values()), robot
