"""match.launch on a shared roscore: a launch refused for a typo (its config or its world) leaves nothing behind for
the next one."""

from pathlib import Path

import pytest

from nubot_common.launch_checks import refused_then_up, serves

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
    log = refused_then_up(ros_master, f"match_{arg}", ["roslaunch", "sim_visual", "match.launch"],
                          [f"{arg}:={path}"], serves(SPAWN))
    assert "exit code 2" in log and refusal in log, log[-3000:]
