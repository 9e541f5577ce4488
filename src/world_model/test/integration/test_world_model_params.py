"""world_model's parameters over real ROS: a bad one is fatal and named; world_model.launch on a shared roscore:
a launch refused for a bad config leaves nothing behind for the next one."""

from pathlib import Path

import pytest

from nubot_common.launch_checks import publishes, refused_then_up, run_refused

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
ROBOT = "nubot4"  # under its ns=: /nubot4/world_model
TOPIC = f"/{ROBOT}/worldmodel/worldmodelinfo"


def test_a_typo_in_the_config_is_refused_and_the_next_launch_without_it_comes_up(ros_master, tmp_path):
    typo = tmp_path / "typo.yaml"
    typo.write_text("teammate_timout: 0.3\n")
    log = refused_then_up(ros_master, "world_model", ["roslaunch", "world_model", "world_model.launch",
                                                      f"robot:={ROBOT}", f"world:={WORLD}"], [f"config:={typo}"],
                          publishes(TOPIC, f"/{ROBOT}/world_model"))
    assert "exit code 2" in log and "unknown parameter(s) teammate_timout" in log, log[-3000:]


@pytest.mark.parametrize(("param", "message"), [
    ("_rate:=.inf", "~.rate: expected a finite number, got inf"),
    ("_agent_id:=2.5", "~.agent_id: expected an integer, got 2.5"),
], ids=["rate_inf", "agent_id_2.5"])
def test_a_bad_parameter_is_fatal_and_named(ros_master, param, message):
    status, output = run_refused(ros_master, "world_model", "world_model_node", param, WORLD)
    assert status == 2 and f"world_model: bad parameters: {message}" in output, output[-3000:]
    assert "Traceback" not in output
