"""Every package's rostest scenarios (``src/<pkg>/test/rostest/*.test``), run as a ROS user runs them:
``rostest <pkg> <file>.test``. ``make test`` runs them here; ``catkin_make run_tests`` runs them too."""

import os
import re
import subprocess
from pathlib import Path
from xml.etree import ElementTree

import pytest

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[3]
SCENARIOS = sorted(ROOT.glob("src/*/test/rostest/*.test"))


def test_every_package_with_nodes_has_rostest_scenarios():
    packages = {p.parts[-4] for p in SCENARIOS}
    assert {"sim_visual", "nubot_control", "coach4sim"} <= packages


@pytest.mark.parametrize("scenario", SCENARIOS, ids=lambda p: f"{p.parts[-4]}/{p.name}")
def test_rostest_scenario_passes(scenario, tmp_path):
    package = scenario.parts[-4]
    env = dict(os.environ, ROS_IP="127.0.0.1", ROS_HOME=str(tmp_path), ROS_LOG_DIR=str(tmp_path / "log"))
    env.pop("ROS_HOSTNAME", None)
    env.pop("ROS_MASTER_URI", None)
    # rostest starts a master of its own on a free port
    result = subprocess.run(["rostest", "--text", f"--results-base-dir={tmp_path}", package, scenario.name],
                            env=env, capture_output=True, text=True, timeout=240)
    output = result.stdout + result.stderr
    assert result.returncode == 0, output[-5000:]
    # With --text, rostest's exit status does not tell a failed test: each test prints a summary of its own.
    tests = len(ElementTree.parse(scenario).getroot().findall(".//test"))
    results = re.findall(r"RESULT: (\w+)", output)
    assert results == ["SUCCESS"] * tests, f"results {results} for {tests} tests\n{output[-5000:]}"
