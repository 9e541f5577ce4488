"""match.launch on a shared roscore: a launch refused for a typo (its config or its world) leaves nothing behind for
the next one."""

import time
import xmlrpc.client
from pathlib import Path

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
SPAWN = "/sim_visual/spawn_model"


@pytest.mark.parametrize(("arg", "typo", "refusal"), [
    ("config", "vision_rat: 30.0\n", "unknown parameter(s) vision_rat"),
    ("world", WORLD.read_text() + "gravty: -9.8\n", "unknown parameter(s) gravty"),
], ids=["config", "world"])
def test_a_typo_is_refused_and_the_next_launch_without_it_comes_up(ros_master, tmp_path, arg, typo, refusal):
    path = tmp_path / "typo.yaml"
    path.write_text(typo)
    refused = ros_master.launch(f"match_{arg}_typo", ["roslaunch", "sim_visual", "match.launch", f"{arg}:={path}"])
    try:
        wait_until(lambda: "exit code" in refused.log_text(), 60, "the simulator to refuse the typo", 0.05)
        log = refused.log_text()
    finally:
        refused.stop()
    assert "exit code 2" in log and refusal in log, log[-3000:]

    master = xmlrpc.client.ServerProxy(ros_master.uri)
    launch = ros_master.launch(f"match_after_{arg}_typo", ["roslaunch", "sim_visual", "match.launch"])

    def outcome() -> str:
        if "exit code" in launch.log_text():
            return "refused"
        return "served" if master.lookupService("/t", SPAWN)[0] == 1 else ""

    try:
        result = wait_until(outcome, 60, f"{SPAWN} or the simulator's exit", 0.05)
        assert result == "served", f"the simulator refused a correct launch:\n{launch.log_text()[-3000:]}"
    finally:
        launch.stop()
        time.sleep(0.5)  # let the master forget the stopped node before the next module launches its own
