"""Start and stop ROS processes for tests, benchmarks and the match runner (no rospy here).

Provides: ``free_port``, ``wait_until`` (poll a condition on the wall clock), ``RosMaster``
(a ``roscore`` on a free port, never 11311, with the environment that points clients at
it), ``Launched`` (a ``roslaunch`` or ``rosrun`` process in its own process group, stopped with
everything it started) and ``process_table`` (every process's /proc stat fields, read once for several
look-ups).
Logs go to ``log_dir`` so that a failing test can show them. No launched process outlives the process that
launched it, however that one ends (SIGKILL, an out-of-memory kill, a CI timeout): the kernel sends each one SIGINT
when its launcher dies (``PR_SET_PDEATHSIG``), and roslaunch, given SIGINT, stops everything it started, as Ctrl-C
would (a recording bag is closed).
"""

from __future__ import annotations

import contextlib
import ctypes
import functools
import os
import signal
import socket
import subprocess
import time
import xmlrpc.client
from collections.abc import Callable, Sequence
from dataclasses import dataclass
from pathlib import Path
from typing import IO, Any, TypeVar

T = TypeVar("T")

DEFAULT_MASTER_PORT = 11311


def free_port() -> int:
    """A TCP port on loopback that nothing listens on now (never the default master port)."""
    while True:
        with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as sock:
            sock.bind(("127.0.0.1", 0))
            port: int = sock.getsockname()[1]
        if port != DEFAULT_MASTER_PORT:
            return port


_PR_SET_PDEATHSIG = 1  # prctl(2): the signal this process gets when the thread that started it ends
try:
    _prctl: Any = ctypes.CDLL(None, use_errno=True).prctl  # looked up now: the child may only call it
except (OSError, AttributeError):  # not Linux: processes are still stopped by stop(), not by the kernel
    _prctl = None


def ending_with_this_process() -> Callable[[], None]:
    """A ``preexec_fn`` for ``subprocess.Popen``: the child gets SIGINT when this process (its launching thread) ends,
    however it ends, and SIGINT at its default."""
    return functools.partial(_child_setup, os.getpid())


def _child_setup(launcher: int) -> None:
    """In the child before it runs the command: SIGINT back to its default (started from a background job, `make
    match &` or nohup, it would inherit it ignored, and stop() could only kill it: rosbag would leave its bag
    unclosed), and SIGINT from the kernel when its launcher dies; a launcher gone already ends it at once."""
    signal.signal(signal.SIGINT, signal.SIG_DFL)
    if _prctl is not None:
        _prctl(_PR_SET_PDEATHSIG, signal.SIGINT, 0, 0, 0)
        if os.getppid() != launcher:
            os.kill(os.getpid(), signal.SIGINT)


class Launched:
    """A child process in its own session; ``stop`` ends the whole group (SIGINT, then SIGKILL)."""

    def __init__(self, args: Sequence[str], env: dict[str, str], log_path: Path):
        self.args = list(args)
        self.log_path = log_path
        self._log: IO[bytes] = open(log_path, "wb")  # noqa: SIM115 - closed in stop()
        # Launched from the main thread (the parent-death signal follows the thread that started the child).
        self.process = subprocess.Popen(self.args, env=env, stdout=self._log, stderr=subprocess.STDOUT,
                                        stdin=subprocess.DEVNULL, start_new_session=True,
                                        preexec_fn=ending_with_this_process())
        self._seen: set[tuple[int, str]] = set()  # (pid, start time) of every descendant remember() saw
        self._stopping: list[int] | None = None  # the processes interrupt() asked to stop

    def remember(self, table: dict[int, list[str]] | None = None) -> None:
        """Note the processes below this one now: ``stop`` ends them even if their parent died in between
        (a node whose launcher was killed is re-parented and would otherwise outlive the match). ``table``:
        a ``process_table()`` to read them from, read once for several launches."""
        table = process_table() if table is None else table
        self._seen |= {(pid, start) for pid in _descendants(self.process.pid, table)
                       if (start := _start_time(pid, table)) is not None}

    def alive(self) -> bool:
        return self.process.poll() is None

    def log_text(self) -> str:
        if not self._log.closed:
            self._log.flush()
        return self.log_path.read_text(errors="replace")

    def interrupt(self) -> None:
        """SIGINT to the whole group, without waiting: ``stop`` then waits for it (several children at once end
        in the time of the slowest, not of all of them in turn)."""
        if self._stopping is not None:
            return
        # roslaunch puts each node in a process group of its own: remember them all before asking to stop.
        descendants = _descendants(self.process.pid)
        self._stopping = descendants + [pid for pid, start in self._seen
                                        if pid not in descendants and _start_time(pid) == start]
        if self.alive():
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signal.SIGINT)

    def stop(self, timeout: float = 10.0) -> None:
        """SIGINT to the whole group, wait for all of it (e.g. rosbag's recorder closing its bag), then SIGKILL."""
        deadline = time.monotonic() + timeout
        self.interrupt()
        descendants = self._stopping or []
        try:
            self.process.wait(timeout=timeout)
        except subprocess.TimeoutExpired:
            with contextlib.suppress(ProcessLookupError):
                os.killpg(self.process.pid, signal.SIGKILL)
            self.process.wait(timeout=timeout)
        while time.monotonic() < deadline and self._group_alive():
            time.sleep(0.05)
        while time.monotonic() < deadline and any(_running(pid) for pid in descendants):
            time.sleep(0.05)
        try:
            os.killpg(self.process.pid, signal.SIGKILL)  # stragglers the group left behind
        except ProcessLookupError:
            pass
        for pid in descendants:  # and nodes in groups of their own that outlived their launcher
            if _running(pid):
                try:
                    os.kill(pid, signal.SIGKILL)
                except ProcessLookupError:
                    pass
        self._log.close()

    def _group_alive(self) -> bool:
        """True while a member of the process group still runs (zombies do not count)."""
        return any(fields[0] != "Z" and int(fields[2]) == self.process.pid for fields in process_table().values())


def wait_until(predicate: Callable[[], T], timeout: float, what: str, poll: float = 0.01) -> T:
    """Poll ``predicate`` on the wall clock until it returns something truthy; return that, or raise AssertionError."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        value = predicate()
        if value:
            return value
        time.sleep(poll)
    raise AssertionError(f"timed out after {timeout} s waiting for {what}")


def _proc_stat(pid: int) -> list[str] | None:
    """The fields after the command name in /proc/<pid>/stat (state, ppid, pgrp, ...), or None."""
    try:
        with open(f"/proc/{pid}/stat") as stat:
            return stat.read().rsplit(")", 1)[1].split()
    except (OSError, IndexError):
        return None


def process_table() -> dict[int, list[str]]:
    """Every process's ``/proc/<pid>/stat`` fields after the command name, by pid: one pass over /proc."""
    table = {}
    for name in os.listdir("/proc"):
        if name.isdigit() and (fields := _proc_stat(int(name))) is not None:
            table[int(name)] = fields
    return table


def _start_time(pid: int, table: dict[int, list[str]] | None = None) -> str | None:
    """When ``pid`` started (clock ticks after boot): with the pid, it names one process even if pids are reused.
    From ``table`` (a ``process_table()``) if given, else from /proc now."""
    fields = _proc_stat(pid) if table is None else table.get(pid)
    return fields[19] if fields is not None and len(fields) > 19 else None


def _running(pid: int) -> bool:
    fields = _proc_stat(pid)
    return fields is not None and fields[0] != "Z"


def _descendants(root: int, table: dict[int, list[str]] | None = None) -> list[int]:
    """Every live process below ``root`` (children, grandchildren, ...), from ``table`` or /proc now."""
    children: dict[int, list[int]] = {}
    for pid, fields in (process_table() if table is None else table).items():
        children.setdefault(int(fields[1]), []).append(pid)
    found, todo = [], [root]
    while todo:
        for child in children.get(todo.pop(), []):
            found.append(child)
            todo.append(child)
    return found


@dataclass(frozen=True)
class RosGraph:
    """Who publishes, subscribes to and serves what, by topic or service name (the master's getSystemState)."""

    publishers: dict[str, set[str]]
    subscribers: dict[str, set[str]]
    services: dict[str, set[str]]


def ros_graph(master_uri: str) -> RosGraph:
    """The graph the master at ``master_uri`` knows now."""
    answer: Any = xmlrpc.client.ServerProxy(master_uri).getSystemState("/nubot_probe")
    code, message, state = answer
    if code != 1:
        raise RuntimeError(f"the master at {master_uri} refused getSystemState: {message}")
    return RosGraph(*({name: set(nodes) for name, nodes in rows} for rows in state))


class RosMaster:
    """A private ``roscore`` on a free port; use as a context manager."""

    def __init__(self, log_dir: Path, port: int | None = None):
        self.port = port or free_port()
        self.uri = f"http://127.0.0.1:{self.port}/"
        self.log_dir = Path(log_dir)
        self.log_dir.mkdir(parents=True, exist_ok=True)
        self.env = dict(os.environ, ROS_MASTER_URI=self.uri, ROS_IP="127.0.0.1",
                        ROS_LOG_DIR=str(self.log_dir / "ros"), PYTHONUNBUFFERED="1")
        self.env.pop("ROS_HOSTNAME", None)
        self.children: list[Launched] = []
        self.core: Launched | None = None

    def __enter__(self) -> RosMaster:
        self.core = Launched(["roscore", "-p", str(self.port)], self.env, self.log_dir / "roscore.log")
        self.wait_until_up()
        return self

    def __exit__(self, *_exc: object) -> None:
        self.stop()

    def use_in_this_process(self) -> None:
        """Point this process at the master (ROS_MASTER_URI, ROS_IP, ROS_LOG_DIR): rospy reads them at init_node."""
        os.environ.update({k: self.env[k] for k in ("ROS_MASTER_URI", "ROS_IP", "ROS_LOG_DIR")})

    def wait_until_up(self, timeout: float = 30.0) -> None:
        deadline = time.monotonic() + timeout
        proxy = xmlrpc.client.ServerProxy(self.uri)
        while time.monotonic() < deadline:
            try:
                answer: Any = proxy.getParam("/nubot_probe", "/rosversion")
                code = answer[0]
                if code == 1:
                    return
            except OSError:
                pass
            if self.core is not None and not self.core.alive():
                raise RuntimeError(f"roscore exited:\n{self.core.log_text()}")
            time.sleep(0.1)
        raise TimeoutError(f"roscore on port {self.port} did not come up in {timeout} s")

    def graph(self) -> RosGraph:
        """Who publishes, subscribes to and serves what, now."""
        return ros_graph(self.uri)

    def launch(self, name: str, args: Sequence[str]) -> Launched:
        """Start ``args`` (e.g. ``["roslaunch", "sim_visual", "single_robot.launch"]``) against this master."""
        child = Launched(args, self.env, self.log_dir / f"{name}.log")
        self.children.append(child)
        return child

    def stop(self) -> None:
        for child in reversed(self.children):
            child.interrupt()
        for child in reversed(self.children):
            child.stop()
        self.children.clear()
        if self.core is not None:
            self.core.stop()
            self.core = None
