"""The soak's measurements: each process found by its node name, and a growing one told from a flat one."""

import subprocess
import sys
import time

import pytest

from nubot_tools.resources import ResourceLog, growth, node_label, plot_resources

# 20 MiB per second of wall time, caught up after each sleep (a busy machine wakes it late). Each says "ready" once
# started (the flat one after taking its 16 MiB), and the test measures from then on: a busy machine can start a
# Python process more slowly than the warm-up.
GROWER = ("import time\nstart, held = time.monotonic(), []\nprint('ready', flush=True)\nwhile True:\n"
          "    while len(held) < 20 * (time.monotonic() - start):\n        held.append(bytearray(2**20))\n"
          "    time.sleep(0.05)\n")
FLAT = "import time\nheld = bytearray(2**24)\nprint('ready', flush=True)\nwhile True:\n    time.sleep(0.05)\n"


def test_node_label_is_the_nodes_full_name():
    log = "__log:=/tmp/x.log"
    assert node_label(["/usr/bin/python3", "world_model_node", "__name:=world_model", log],
                      {"ROS_NAMESPACE": "/nubot2"}) == "/nubot2/world_model"
    assert node_label(["sim_visual_node", "__name:=sim_visual"], {}) == "/sim_visual"
    assert node_label(["record", "__name:=match_recorder", "__ns:=/a"], {}) == "/a/match_recorder"
    assert node_label(["/usr/bin/rosmaster", "--core"], {}) == "rosmaster"


def test_a_growing_process_shows_a_slope_and_a_flat_one_does_not(tmp_path):
    children = [subprocess.Popen([sys.executable, "-c", code, f"__name:={name}"], stdout=subprocess.PIPE, text=True)
                for code, name in ((GROWER, "grower"), (FLAT, "flat"))]
    try:
        assert [c.stdout.readline().strip() for c in children] == ["ready", "ready"]
        log = ResourceLog(lambda: [c.pid for c in children], clock=time.monotonic)
        start = time.monotonic()
        while time.monotonic() - start < 3.0:
            log.sample(time.monotonic())
            time.sleep(0.25)
    finally:
        for child in children:
            child.kill()
            child.wait()
    slopes = growth(log.samples, warmup=0.5)
    assert slopes["/grower"]["slope_mib_per_min"] == pytest.approx(20 * 60, rel=0.3)
    assert abs(slopes["/flat"]["slope_mib_per_min"]) < 5.0
    plot_resources(log.samples, tmp_path / "soak.png", 0.5, "test")
    assert (tmp_path / "soak.png").stat().st_size > 10_000
