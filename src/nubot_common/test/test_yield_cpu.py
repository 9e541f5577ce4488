"""yield_cpu in real child processes: a session leader (as roslaunch starts every node) lowers its session's
CPU share, anything else only its own threads, never its parent's session."""

from __future__ import annotations

import os
import subprocess
import sys
import time
from pathlib import Path

import pytest

from nubot_common.node_io import yield_cpu

CHILD = """
import sys, threading, time
from nubot_common.node_io import yield_cpu
threading.Thread(target=time.sleep, args=(60,), daemon=True).start()  # a thread that exists before
print(yield_cpu(int(sys.argv[1])), flush=True)
time.sleep(60)
"""
BASE = os.getpriority(os.PRIO_PROCESS, 0)  # what children inherit (make test runs the unit tests at nice 10)
AUTOGROUPS = Path("/proc/sys/kernel/sched_autogroup_enabled").exists() and \
    Path("/proc/sys/kernel/sched_autogroup_enabled").read_text().strip() == "1"


def child(nice: int, session: bool) -> tuple[subprocess.Popen, str]:
    process = subprocess.Popen([sys.executable, "-c", CHILD, str(nice)], stdout=subprocess.PIPE, text=True,
                               start_new_session=session)
    return process, process.stdout.readline().strip()


def threads_nice(pid: int) -> set[int]:
    return {int((task / "stat").read_text().rsplit(")", 1)[1].split()[16])
            for task in Path(f"/proc/{pid}/task").iterdir()}


def autogroup(pid: int | str) -> str:
    return Path(f"/proc/{pid}/autogroup").read_text().strip()


@pytest.mark.skipif(not AUTOGROUPS, reason="the kernel does not group tasks by session")
def test_a_session_leader_lowers_its_sessions_share():
    process, said = child(7, session=True)
    try:
        assert said == "its session's CPU share at nice 7"
        assert autogroup(process.pid).endswith("nice 7")
        assert autogroup(process.pid) != autogroup("self"), "a session of its own"
    finally:
        process.kill()
        process.wait()


def test_a_process_in_another_session_lowers_only_its_own_threads():
    mine = autogroup("self")
    process, said = child(5, session=False)
    try:
        want = max(5, BASE)  # never less nice than it started
        assert said == f"its threads at nice {want}"
        time.sleep(0.1)
        assert threads_nice(process.pid) == {want}, "every thread, the one started before too"
        assert autogroup("self") == mine, "the session it shares is left alone"
    finally:
        process.kill()
        process.wait()


def test_nice_zero_changes_nothing_and_a_bad_value_is_refused():
    process, said = child(0, session=True)
    try:
        assert said == "the default CPU priority"
        assert autogroup(process.pid).endswith("nice 0") and threads_nice(process.pid) == {BASE}
    finally:
        process.kill()
        process.wait()
    for bad in (-1, 20):
        with pytest.raises(ValueError, match=f"a nice value from 0 to 19, not {bad}"):
            yield_cpu(bad)
