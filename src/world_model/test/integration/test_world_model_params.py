"""world_model's parameters over real ROS: a bad one is fatal and named; world_model.launch on a shared roscore:
a launch refused for a bad config leaves nothing behind for the next one."""

import re
import subprocess
import time
import xmlrpc.client
from pathlib import Path

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot4"  # under its ns=: /nubot4/world_model
TOPIC = f"/{ROBOT}/worldmodel/worldmodelinfo"
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


@pytest.mark.parametrize(("param", "message"), [
    ("_rate:=.inf", "~.rate: expected a finite number, got inf"),
    ("_agent_id:=2.5", "~.agent_id: expected an integer, got 2.5"),
], ids=["rate_inf", "agent_id_2.5"])
def test_a_bad_parameter_is_fatal_and_named(ros_master, param, message):
    status, output = _run_refused(ros_master, "world_model", "world_model_node", param)
    assert status == 2 and f"world_model: bad parameters: {message}" in output, output[-3000:]
    assert "Traceback" not in output
