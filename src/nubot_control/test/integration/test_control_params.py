"""nubot_control's and path_tracking's parameters over real ROS: a bad one is fatal and named; robot.launch on a
shared roscore: a launch refused for a bad config leaves nothing behind for the next one."""

import re
import subprocess
import time
import xmlrpc.client
from pathlib import Path

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot3"  # under its ns=: /nubot3/nubot_control
TOPIC = f"/{ROBOT}/nubotcontrol/velcmd"
RUN_TIMEOUT = 30.0  # [s] for a node that must refuse its parameters and exit


def _run_refused(ros_master, package: str, node: str, param: str) -> tuple[int, str]:
    """Run ``node`` with the bad private ``param`` (``_key:=value``), /world loaded; its exit status and output."""
    subprocess.run(["rosparam", "load", str(WORLD), "/world"], env=ros_master.env, check=True, timeout=30)
    name = "refused_" + re.sub(r"\W", "_", param.strip("_"))  # its own private namespace: no stale keys
    try:
        result = subprocess.run(["rosrun", package, node, param, f"__name:={name}"], env=ros_master.env,
                                capture_output=True, text=True, timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        raise AssertionError(f"{node} {param} still runs after {RUN_TIMEOUT} s") from None
    return result.returncode, result.stdout + result.stderr


def test_a_typo_in_the_config_is_refused_and_the_next_launch_without_it_comes_up(ros_master, tmp_path):
    typo = tmp_path / "typo.yaml"
    typo.write_text("motion:\n  max_sped: 2.0\n")
    args = ["roslaunch", "nubot_control", "robot.launch", f"robot:={ROBOT}", f"world:={WORLD}"]
    refused = ros_master.launch("robot_typo", [*args, f"config:={typo}"])
    try:
        wait_until(lambda: "exit code" in refused.log_text(), 60, "nubot_control to refuse the config", 0.05)
        log = refused.log_text()
    finally:
        refused.stop()
    assert "exit code 2" in log and "unknown parameter(s) max_sped" in log, log[-3000:]

    master = xmlrpc.client.ServerProxy(ros_master.uri)
    launch = ros_master.launch("robot_fixed", args)

    def outcome() -> str:
        if "exit code" in launch.log_text():
            return "refused"
        publishers = dict(master.getSystemState("/t")[2][0])
        return "publishing" if publishers.get(TOPIC) == [f"/{ROBOT}/nubot_control"] else ""

    try:
        result = wait_until(outcome, 60, f"{TOPIC} or nubot_control's exit", 0.05)
        assert result == "publishing", f"nubot_control refused a correct launch:\n{launch.log_text()[-3000:]}"
    finally:
        launch.stop()
        time.sleep(0.5)  # let the master forget the stopped nodes before the next module launches their own


@pytest.mark.parametrize(("node", "param", "message"), [
    ("nubot_control_node", "_target_period:=-1.0", "nubot_control: bad parameters: ~: target_period must be positive, "
                                                   "got -1.0"),
    ("nubot_control_node", "_robot:=nubot7", "nubot_control: bad parameters: ~agent_id (default: the one in ~robot) "
                                             "must lie in 1..5 (~play/team_size), got 7"),
    ("path_tracking", "_robot:=nubot1/", "path_tracking: bad parameters: ~: robot: a robot name is a team prefix "
                                         "and an AgentID from 1 (e.g. nubot2), got 'nubot1/'"),
], ids=["target_period_negative", "agent_7_of_5", "robot_with_slash"])
def test_a_bad_parameter_is_fatal_and_named(ros_master, node, param, message):
    status, output = _run_refused(ros_master, "nubot_control", node, param)
    assert status == 2 and message in output, output[-3000:]
    assert "Traceback" not in output
