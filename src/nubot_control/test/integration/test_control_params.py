"""nubot_control's and path_tracking's parameters over real ROS: a bad one is fatal and named; robot.launch on a
shared roscore: a launch refused for a bad config leaves nothing behind for the next one."""

from pathlib import Path

import pytest

from nubot_common.launch_checks import publishes, refused_then_up, run_refused

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot3"  # under its ns=: /nubot3/robot (world model and control in one node)
TOPIC = f"/{ROBOT}/nubotcontrol/velcmd"


def test_a_typo_in_the_config_is_refused_and_the_next_launch_without_it_comes_up(ros_master, tmp_path):
    typo = tmp_path / "typo.yaml"
    typo.write_text("motion:\n  max_sped: 2.0\n")
    log = refused_then_up(ros_master, "robot", ["roslaunch", "nubot_control", "robot.launch", f"robot:={ROBOT}",
                                                f"world:={WORLD}"], [f"config:={typo}"],
                          publishes(TOPIC, f"/{ROBOT}/robot"))
    assert "exit code 2" in log and "unknown parameter(s) max_sped" in log, log[-3000:]


@pytest.mark.parametrize(("node", "param", "message"), [
    ("nubot_control_node", "_target_period:=-1.0", "nubot_control: bad parameters: ~: target_period must be positive, "
                                                   "got -1.0"),
    ("nubot_control_node", "_robot:=nubot7", "nubot_control: bad parameters: ~agent_id (default: the one in ~robot) "
                                             "must lie in 1..5 (~play/team_size), got 7"),
    ("path_tracking", "_robot:=nubot1/", "path_tracking: bad parameters: ~: robot: a robot name is a team prefix "
                                         "and an AgentID from 1 (e.g. nubot2), got 'nubot1/'"),
    ("robot_node", "_world_model/sensor_timeout:=-1.0", "robot: bad parameters: ~world_model: sensor_timeout must "
                                                        "be positive"),
    ("robot_node", "_world_model/robot:=nubot2", "robot: bad parameters: ~world_model/robot and agent_id (nubot2, 2) "
                                                 "are not ~robot and agent_id (nubot1, 1)"),
], ids=["target_period_negative", "agent_7_of_5", "robot_with_slash", "robot_node_world_model_param",
        "robot_node_two_robots"])
def test_a_bad_parameter_is_fatal_and_named(ros_master, node, param, message):
    status, output = run_refused(ros_master, "nubot_control", node, param, WORLD)
    assert status == 2 and message in output, output[-3000:]
    assert "Traceback" not in output
