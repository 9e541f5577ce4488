"""robot.launch on a shared roscore: a launch refused for a bad config leaves nothing behind for the next one."""

import time
import xmlrpc.client
from pathlib import Path

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot3"  # under its ns=: /nubot3/nubot_control
TOPIC = f"/{ROBOT}/nubotcontrol/velcmd"


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
