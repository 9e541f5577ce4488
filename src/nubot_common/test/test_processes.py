"""Tests for nubot_common.processes: free ports and process groups that stop cleanly (no roscore here)."""

import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from nubot_common import processes
from nubot_common.processes import DEFAULT_MASTER_PORT, Launched, free_port


def live_group_members(pgid: int) -> list[int]:
    """Pids of the processes in group ``pgid`` that are not zombies (read from /proc)."""
    members = []
    for entry in Path("/proc").iterdir():
        if not entry.name.isdigit():
            continue
        try:
            stat = (entry / "stat").read_text()
        except OSError:
            continue
        state, _ppid, group = stat.rsplit(")", 1)[1].split()[:3]
        if int(group) == pgid and state != "Z":
            members.append(int(entry.name))
    return members


def wait_until(predicate, timeout: float = 5.0) -> bool:
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if predicate():
            return True
        time.sleep(0.02)
    return predicate()


@pytest.fixture
def launched(tmp_path):
    started: list[Launched] = []

    def start(args: list[str]) -> Launched:
        child = Launched(args, dict(os.environ), tmp_path / f"child{len(started)}.log")
        started.append(child)
        return child

    yield start
    for child in started:
        if child.alive() or live_group_members(child.process.pid):
            os.killpg(child.process.pid, signal.SIGKILL)
            child.process.wait(timeout=5)


def test_free_port_is_bindable_and_not_the_master_port():
    for _ in range(20):
        port = free_port()
        assert port != DEFAULT_MASTER_PORT
        assert 0 < port < 65536
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
            sock.bind(("127.0.0.1", port))
            sock.listen()


def test_free_port_skips_the_master_port_when_the_os_offers_it(monkeypatch):
    offered = iter([DEFAULT_MASTER_PORT, DEFAULT_MASTER_PORT, 40123])

    class FakeSocket:
        def __init__(self, *_args):
            self.port = next(offered)

        def __enter__(self):
            return self

        def __exit__(self, *_exc):
            return False

        def bind(self, address):
            assert address == ("127.0.0.1", 0)

        def getsockname(self):
            return ("127.0.0.1", self.port)

    monkeypatch.setattr(processes.socket, "socket", FakeSocket)
    assert free_port() == 40123
    assert next(offered, None) is None


def test_launched_runs_in_its_own_process_group(launched):
    child = launched(["sleep", "30"])
    assert child.alive()
    assert os.getpgid(child.process.pid) == child.process.pid
    assert os.getpgid(child.process.pid) != os.getpgid(0)
    child.stop()


def running_program(child: Launched) -> str:
    """The program the child runs now (its command name once it has exec'd)."""
    return Path(f"/proc/{child.process.pid}/comm").read_text().strip()


def test_stop_ends_the_process_and_its_group(launched):
    child = launched(["sleep", "30"])
    assert child.alive()
    # A SIGINT that lands between fork and exec is lost (the forked child still has Python's handler).
    assert wait_until(lambda: running_program(child) == "sleep")
    started = time.monotonic()
    child.stop(timeout=5.0)
    assert time.monotonic() - started < 5.0, "sleep should end on SIGINT, not need the SIGKILL fallback"
    assert not child.alive()
    assert child.process.returncode == -signal.SIGINT
    with pytest.raises(ProcessLookupError):
        os.killpg(child.process.pid, 0)


def test_stop_ends_a_child_even_when_this_process_ignores_sigint(launched):
    previous = signal.signal(signal.SIGINT, signal.SIG_IGN)  # as in a background job of a shell script
    try:
        child = launched(["sleep", "30"])
    finally:
        signal.signal(signal.SIGINT, previous)
    assert wait_until(lambda: running_program(child) == "sleep")
    child.stop(timeout=5.0)
    assert child.process.returncode == -signal.SIGINT, "the child hears SIGINT again"


def test_stop_kills_grandchildren_left_in_the_group(launched):
    # A non-interactive shell starts background jobs with SIGINT ignored, so only the SIGKILL sweep ends them.
    child = launched(["sh", "-c", "sleep 30 & echo started $!; wait"])
    assert wait_until(lambda: "started" in child.log_text())
    assert len(live_group_members(child.process.pid)) == 2
    child.stop(timeout=5.0)
    assert not child.alive()
    assert wait_until(lambda: not live_group_members(child.process.pid)), "the background sleep survived stop()"


def test_stop_falls_back_to_sigkill_when_sigint_is_ignored(launched):
    script = (
        "import signal, sys, time; signal.signal(signal.SIGINT, signal.SIG_IGN); print('ready', flush=True); "
        "time.sleep(30)"
    )
    child = launched([sys.executable, "-c", script])
    assert wait_until(lambda: "ready" in child.log_text())
    child.stop(timeout=0.5)
    assert child.process.returncode == -signal.SIGKILL
    assert not live_group_members(child.process.pid)


def test_stop_of_a_process_that_already_exited_is_harmless(launched):
    child = launched(["true"])
    child.process.wait(timeout=5)
    child.stop()
    child.stop()
    assert child.process.returncode == 0


def test_log_text_returns_stdout_and_stderr_of_the_child(launched):
    child = launched(["sh", "-c", "echo hello from child; echo oops >&2"])
    assert child.process.wait(timeout=5) == 0
    text = child.log_text()
    assert "hello from child\n" in text
    assert "oops\n" in text
    assert child.log_path.read_text() == text


def test_log_text_of_a_running_child(launched):
    child = launched([sys.executable, "-u", "-c", "import time; print('tick'); time.sleep(30)"])
    assert wait_until(lambda: "tick" in child.log_text())
    assert child.alive()
    child.stop()


def test_child_gets_the_given_environment(tmp_path):
    env = {"PATH": os.environ["PATH"], "ROS_MASTER_URI": "http://127.0.0.1:1/"}
    child = Launched(["sh", "-c", 'echo "master=$ROS_MASTER_URI home=${HOME:-unset}"'], env, tmp_path / "env.log")
    assert child.process.wait(timeout=5) == 0
    assert child.log_text() == "master=http://127.0.0.1:1/ home=unset\n"
    child.stop()


def test_log_text_after_stop_still_returns_the_log(launched):
    child = launched(["sh", "-c", "echo last words"])
    child.process.wait(timeout=5)
    child.stop()
    assert "last words" in child.log_text()


def test_stop_lets_group_members_finish_after_the_leader_exits(tmp_path):
    """Like ``rosbag record``: the wrapper exits on SIGINT, its recorder still has to close the bag."""
    done = tmp_path / "closed"
    member = (f"import signal, sys, time\n"
              f"def close(*_):\n    time.sleep(0.5)\n    open({str(done)!r}, 'w').write('ok')\n    sys.exit(0)\n"
              f"signal.signal(signal.SIGINT, close)\nprint('ready', flush=True)\n"
              f"while True:\n    time.sleep(0.05)\n")
    wrapper = (f"import subprocess, sys\nchild = subprocess.Popen([sys.executable, '-c', {member!r}])\n"
               f"try:\n    child.wait()\nexcept KeyboardInterrupt:\n    sys.exit(1)\n")
    child = Launched([sys.executable, "-c", wrapper], dict(os.environ), tmp_path / "log.txt")
    wait_until(lambda: "ready" in child.log_text(), timeout=10.0)
    child.stop(timeout=5)
    assert done.read_text() == "ok", "the member was killed before it finished"


def test_stop_also_ends_descendants_that_left_the_group(tmp_path):
    """roslaunch starts each node in a session of its own; those must not outlive the launch."""
    escapee = ("import os, time\nos.setsid()\nprint('ready', flush=True)\n"
               "while True:\n    time.sleep(0.05)\n")
    launcher = (f"import signal, subprocess, sys, time\nsignal.signal(signal.SIGINT, signal.SIG_IGN)\n"
                f"subprocess.Popen([sys.executable, '-c', {escapee!r}])\nwhile True:\n    time.sleep(0.05)\n")
    child = Launched([sys.executable, "-c", launcher], dict(os.environ), tmp_path / "log.txt")
    wait_until(lambda: "ready" in child.log_text(), timeout=10.0)
    escaped = processes._descendants(child.process.pid)
    assert escaped, "the launcher has a child"
    child.stop(timeout=1)
    time.sleep(0.2)
    assert not [pid for pid in escaped if processes._running(pid)], "a descendant outlived stop()"


def test_stop_ends_remembered_descendants_whose_launcher_died(tmp_path):
    """A node whose roslaunch was killed is re-parented: what remember() noted (from one process_table() for every
    launch, as the match runner polls) is still ended by stop()."""
    escapee = ("import os, time\nos.setsid()\nprint('ready', flush=True)\n"
               "while True:\n    time.sleep(0.05)\n")
    launcher = (f"import subprocess, sys, time\nsubprocess.Popen([sys.executable, '-c', {escapee!r}])\n"
                f"while True:\n    time.sleep(0.05)\n")
    first = Launched([sys.executable, "-c", launcher], dict(os.environ), tmp_path / "first.txt")
    second = Launched([sys.executable, "-c", launcher], dict(os.environ), tmp_path / "second.txt")
    wait_until(lambda: "ready" in first.log_text() and "ready" in second.log_text(), timeout=10.0)
    table = processes.process_table()
    escaped = processes._descendants(first.process.pid, table)
    assert len(escaped) == 1 and escaped[0] not in processes._descendants(second.process.pid, table)
    first.remember(table)
    second.remember(table)
    os.kill(first.process.pid, signal.SIGKILL)
    first.process.wait(timeout=5)
    assert processes._running(escaped[0]) and escaped[0] not in processes._descendants(first.process.pid)
    first.stop(timeout=2)
    second.stop(timeout=2)
    time.sleep(0.2)
    assert not processes._running(escaped[0]), "a remembered node outlived its dead launcher's stop()"


RUNNER = """
import sys, time
from pathlib import Path
from nubot_common.processes import Launched
folder = Path(sys.argv[1])
child = Launched([sys.executable, "-c", sys.argv[2], str(folder)], dict(__import__("os").environ),
                 folder / "child.log")
print(child.process.pid, flush=True)
time.sleep(600)
"""
TRAPPING_CHILD = """
import signal, sys, time
from pathlib import Path
def closed(*_):
    (Path(sys.argv[1]) / "closed").write_text("SIGINT")
    sys.exit(0)
signal.signal(signal.SIGINT, closed)
(Path(sys.argv[1]) / "ready").write_text("")
time.sleep(600)
"""


def test_a_launched_process_gets_sigint_and_ends_when_its_launcher_is_killed(tmp_path):
    """However the launcher ends (here SIGKILL: no stop(), no atexit), the kernel interrupts what it launched."""
    runner = subprocess.Popen([sys.executable, "-c", RUNNER, str(tmp_path), TRAPPING_CHILD], stdout=subprocess.PIPE,
                              text=True)
    child = 0
    try:
        child = int(runner.stdout.readline())
        processes.wait_until(lambda: (tmp_path / "ready").exists(), 10.0, "the child's start")
        runner.kill()
        runner.wait(timeout=5)
        processes.wait_until(lambda: (tmp_path / "closed").exists(), 10.0, "the child's SIGINT")
        processes.wait_until(lambda: not Path(f"/proc/{child}").exists() or
                             Path(f"/proc/{child}/stat").read_text().rsplit(")", 1)[1].split()[0] == "Z",
                             10.0, "the child's end")
    finally:
        runner.kill()
        runner.wait(timeout=5)
        if child and Path(f"/proc/{child}").exists():  # left running (the test failed): not beyond the test
            os.kill(child, signal.SIGKILL)
