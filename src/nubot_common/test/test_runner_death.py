"""A match's processes end with the process that started them, however it ends: a runner holding a roscore and a
recording rosbag is killed with SIGKILL (an out-of-memory kill, a CI timeout, kill -9), and nothing it started is
left, with the bag closed, not left .active."""

import os
import signal
import subprocess
import sys
from pathlib import Path

import pytest

from nubot_common.processes import _descendants, process_table, wait_until

pytestmark = pytest.mark.integration

RUNNER = """
import sys, time
from pathlib import Path
from nubot_common.processes import RosMaster
folder = Path(sys.argv[1])
master = RosMaster(folder / "logs").__enter__()
master.launch("recorder", ["rosbag", "record", "-O", str(folder / "run.bag"), "/rosout"])
print("up", flush=True)
time.sleep(600)
"""


def _alive(pid: int) -> bool:
    try:
        return Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0] != "Z"
    except OSError:
        return False


def test_nothing_a_killed_runner_started_outlives_it_and_its_bag_is_closed(tmp_path):
    runner = subprocess.Popen([sys.executable, "-c", RUNNER, str(tmp_path)], stdout=subprocess.PIPE, text=True)
    started: list[int] = []
    try:
        assert runner.stdout.readline().strip() == "up"
        wait_until(lambda: (tmp_path / "run.bag.active").exists(), 30.0, "the recording")
        started = _descendants(runner.pid, process_table())
        assert len(started) >= 4, started  # roscore's roslaunch, rosmaster, rosout, rosbag's record
        runner.kill()
        runner.wait(timeout=5)
        wait_until(lambda: not any(_alive(pid) for pid in started), 30.0, "the end of every process it started")
        assert (tmp_path / "run.bag").exists() and not (tmp_path / "run.bag.active").exists()
    finally:
        runner.kill()
        runner.wait(timeout=5)
        for pid in started:  # left running (the test failed): not beyond the test
            if _alive(pid):
                os.kill(pid, signal.SIGKILL)
