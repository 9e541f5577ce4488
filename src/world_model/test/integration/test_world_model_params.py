"""world_model.launch on a shared roscore: a launch refused for a bad config leaves nothing behind for the next one."""

import time
import xmlrpc.client
from pathlib import Path

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot4"  # under its ns=: /nubot4/world_model
TOPIC = f"/{ROBOT}/worldmodel/worldmodelinfo"


def test_a_typo_in_the_config_is_refused_and_the_next_launch_without_it_comes_up(ros_master, tmp_path):
    typo = tmp_path / "typo.yaml"
    typo.write_text("teammate_timout: 0.3\n")
    args = ["roslaunch", "world_model", "world_model.launch", f"robot:={ROBOT}", f"world:={WORLD}"]
    refused = ros_master.launch("world_model_typo", [*args, f"config:={typo}"])
    try:
        wait_until(lambda: "exit code" in refused.log_text(), 60, "world_model to refuse the config", 0.05)
        log = refused.log_text()
    finally:
        refused.stop()
    assert "exit code 2" in log and "unknown parameter(s) teammate_timout" in log, log[-3000:]

    master = xmlrpc.client.ServerProxy(ros_master.uri)
    launch = ros_master.launch("world_model_fixed", args)

    def outcome() -> str:
        if "exit code" in launch.log_text():
            return "refused"
        publishers = dict(master.getSystemState("/t")[2][0])
        return "publishing" if publishers.get(TOPIC) == [f"/{ROBOT}/world_model"] else ""

    try:
        result = wait_until(outcome, 60, f"{TOPIC} or world_model's exit", 0.05)
        assert result == "publishing", f"world_model refused a correct launch:\n{launch.log_text()[-3000:]}"
    finally:
        launch.stop()
        time.sleep(0.5)  # let the master forget the stopped node before the next module launches its own
