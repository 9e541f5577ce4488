"""team_link's parameters over a real roscore: a bad one is fatal and named, before the node opens any socket."""

from pathlib import Path

import pytest

from nubot_common.launch_checks import run_refused

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"  # not read: any YAML


@pytest.mark.parametrize(("param", "message"), [
    ("_lcm_url:=239.255.76.67:7667", "~: lcm_url must be an LCM URL like udpm://239.255.76.67:7667?ttl=1"),
    ("_robot:=nubot7", "~: AgentID 7 of nubot7 is beyond team_size 5"),
], ids=["url", "robot"])
def test_a_bad_parameter_is_fatal_and_named(ros_master, param, message):
    status, output = run_refused(ros_master, "nubot_comm", "team_link", param, WORLD)
    assert status == 2 and f"team_link: bad parameters: {message}" in output, output[-3000:]
    assert "Traceback" not in output
