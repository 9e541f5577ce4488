"""The fault suite: kill each kind of node in the middle of a refereed match (``run_match.py``, 2 vs 2;
1 vs 1 where only the match's own nodes die).

The stated outcomes: a dead simulator, recorder, referee or master ends the match at once with a clear
message and exit status 3 (``CUT_SHORT_STATUS``), leaving a complete, indexed bag up to the kill, a report
that says why the match was cut short, and no process behind; a dead robot node is reported and the match
goes on, the robot whose world model died stands still and drops out of its team's play.
"""

from __future__ import annotations

import contextlib
import json
import os
import queue
import re
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import pytest
from rosbags.rosbag1 import Reader

from nubot_match.bag_reader import build_typestore
from nubot_tools.node_watch import node_pid
from nubot_tools.ros.match_runner import CUT_SHORT_STATUS, RUN_FILE

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[3]


class RunningMatch:
    """``run_match.py`` as a user starts it, with its output read line by line."""

    def __init__(self, tmp_path: Path, teams: list[str], half_seconds: float, report: bool = True,
                 extra: tuple[str, ...] = (), sigint_ignored: bool = False):
        self.out = tmp_path / "matches"
        self.process = subprocess.Popen(
            [sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds", str(half_seconds),
             "--halves", "1", "--out", str(self.out), "--viewer-port", "-1", *([] if report else ["--no-report"]),
             *teams, *extra],
            stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True,
            # as a shell script's background job (`make match &`) starts: SIGINT ignored
            preexec_fn=(lambda: signal.signal(signal.SIGINT, signal.SIG_IGN)) if sigint_ignored else None)
        self.lines: queue.Queue[str] = queue.Queue()
        self.text = ""
        threading.Thread(target=self._read, daemon=True).start()
        self.master = self.wait_for("ROS master ").split()[2]

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.put(line)

    def wait_for(self, text: str, timeout: float = 240.0) -> str:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            try:
                line = self.lines.get(timeout=0.5)
            except queue.Empty:
                if self.process.poll() is not None and self.lines.empty():
                    break
                continue
            self.text += line
            if text in line:
                return line
        raise AssertionError(f"no line with {text!r} in:\n{self.text[-4000:]}")

    def sim_time(self) -> float:
        """The game's sim clock as the runner last printed it (its status line every 5 s)."""
        line = self.wait_for("  sim ")
        minutes, seconds = line.split()[1].rstrip(":").split(":")
        return 60 * int(minutes) + float(seconds)

    def kill(self, node: str) -> int:
        pid = node_pid(self.master, node)
        assert pid is not None, f"{node} is not up"
        os.kill(pid, signal.SIGKILL)
        return pid

    def finish(self, timeout: float) -> int:
        try:
            self.process.wait(timeout=timeout)
        finally:
            if self.process.poll() is None:  # a runner that hangs: it and every node of its match, which roslaunch
                os.killpg(self.process.pid, signal.SIGKILL)  # put in sessions of their own, so no later test meets them
                for entry in leftovers(self.master):
                    with contextlib.suppress(ProcessLookupError):
                        os.kill(int(entry.split(":", 1)[0]), signal.SIGKILL)
        time.sleep(0.5)
        while not self.lines.empty():
            self.text += self.lines.get()
        return self.process.returncode

    def folder(self) -> Path:
        return next(self.out.iterdir())


def read_bag(bag: Path, topics: set[str]) -> dict[str, list[tuple[float, object]]]:
    found: dict[str, list[tuple[float, object]]] = {t: [] for t in topics}
    with Reader(bag) as reader:
        typestore = build_typestore(reader.connections)
        conns = [c for c in reader.connections if c.topic in topics]
        for conn, stamp, raw in reader.messages(connections=conns):
            found[conn.topic].append((stamp * 1e-9, typestore.deserialize_ros1(raw, conn.msgtype)))
    return found


def bag_end(bag: Path) -> float:
    """Sim time of the last /clock the bag holds [s]."""
    clocks = read_bag(bag, {"/clock"})["/clock"]
    return clocks[-1][1].clock.sec + 1e-9 * clocks[-1][1].clock.nanosec


def leftovers(master: str) -> list[str]:
    """Processes still running that belong to the match (they name its master's port)."""
    port = master.rstrip("/").rsplit(":", 1)[1]
    found = []
    for proc in Path("/proc").iterdir():
        if not proc.name.isdigit():
            continue
        try:
            environ = (proc / "environ").read_bytes()
            cmdline = (proc / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if f":{port}/".encode() in environ or f"-p {port}" in cmdline:
            found.append(f"{proc.name}: {cmdline[:120]}")
    return found


def listeners(pids: set[int]) -> dict[str, list[str]]:
    """The TCP listening addresses of these processes, by executable name."""
    table = subprocess.run(["ss", "-ltnpH"], capture_output=True, text=True, check=True).stdout
    found: dict[str, list[str]] = {}
    for line in table.splitlines():
        for name, pid in re.findall(r'\("([^"]+)",pid=(\d+)', line):
            if int(pid) in pids:
                found.setdefault(name, []).append(line.split()[3])
    return found


def match_pids(runner: int) -> set[int]:
    import psutil

    return {p.pid for p in psutil.Process(runner).children(recursive=True)} | {runner}


def test_dead_robot_nodes_are_reported_and_a_dead_recorder_cuts_the_match_short_with_its_bag_recovered(
        tmp_path, two_vs_two):
    # each robot's world model and control in two nodes: a dead world model leaves a control node to notice it
    match = RunningMatch(tmp_path, two_vs_two, half_seconds=120, extra=("--processes", "two"))
    match.wait_for("kickoff for")
    time.sleep(4.0)
    # Every node of ours listens on loopback only; ROS's own C++ rosout and rosbag record open their XML-RPC
    # server on every address (xmlrpcpp has no option for it): the README says how to confine them.
    found = listeners(match_pids(match.process.pid))
    assert len(found) >= 8, found
    ours = {name: addrs for name, addrs in found.items() if name not in ("rosout", "record")}
    assert all(a.startswith("127.0.0.1:") for addrs in ours.values() for a in addrs), ours
    assert all(sum(not a.startswith("127.0.0.1:") for a in found.get(n, [])) <= 1 for n in ("rosout", "record"))
    killed_at = match.sim_time()
    match.kill("/nubot2/world_model")
    match.wait_for("node /nubot2/world_model died", timeout=10)
    match.kill("/rival2/nubot_control")
    match.wait_for("node /rival2/nubot_control died", timeout=10)
    time.sleep(8.0)
    assert match.process.poll() is None, "the match goes on without a robot node"
    recorder_killed = match.sim_time()
    match.kill("/match_recorder")
    match.wait_for("MATCH CUT SHORT: required node /match_recorder died", timeout=10)
    status = match.finish(timeout=120)
    assert status == CUT_SHORT_STATUS, match.text[-3000:]
    folder = match.folder()
    bag = folder / "match.bag"
    assert bag.exists() and not (folder / "match.bag.active").exists(), "the bag is reindexed and named as usual"
    assert bag_end(bag) > recorder_killed - 1.0, "the bag holds the match up to the recorder's death"
    run = json.loads((folder / RUN_FILE).read_text())
    assert run["ended"] == "cut short" and "/match_recorder" in run["reason"]
    died = {e["node"] for e in run["events"] if e.get("change") == "died"}
    assert {"/nubot2/world_model", "/rival2/nubot_control", "/match_recorder"} <= died
    report = json.loads((folder / "report.json").read_text())
    assert report["run"]["ended"] == "cut short", "the report says the match was cut short"
    assert "CUT SHORT" in match.text

    # The robot without a world model: zero velocity within the timeout, and its teammate drops it.
    found = read_bag(bag, {"/nubot2/nubotcontrol/velcmd", "/nubot1/worldmodel/worldmodelinfo",
                           "/nubot2/nubotcontrol/strategy"})
    # (the recorder runs on sim time: a message's bag stamp is the sim time it was recorded at)
    late = [m for t, m in found["/nubot2/nubotcontrol/velcmd"] if t > killed_at + 6.0]
    assert late and all((m.Vx, m.Vy, m.w) == (0.0, 0.0, 0.0) for m in late), "it stands still"
    assert not [t for t, _ in found["/nubot2/nubotcontrol/strategy"] if t > killed_at + 6.0], \
        "it stops announcing itself to the team"
    seen_by_mate = [(t, m.robotinfo[1].isvalid) for t, m in found["/nubot1/worldmodel/worldmodelinfo"]]
    assert any(valid for t, valid in seen_by_mate if t < killed_at), "valid before"
    assert not any(valid for t, valid in seen_by_mate if t > killed_at + 8.0), "its teammate treats it as absent"
    log = (folder / "logs" / "ros").rglob("*nubot2-nubot_control*.log")
    assert any("world model stale" in p.read_text(errors="replace") for p in log), "and it says so"


@pytest.fixture
def one_vs_one(tmp_path) -> list[str]:
    """``--team`` arguments for nubot and rival with one robot each: the fewest nodes a match has."""
    args = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = tmp_path / f"{prefix}_alone.yaml"
        path.write_text(f"{{name: {prefix}, prefix: {prefix}, attack: {attack}, goalie: 1, "
                        "robots: [{x: -1.0, y: 0.5}]}")
        args += ["--team", str(path)]
    return args


@pytest.mark.parametrize("node", ["/sim_visual", "/referee", "/master"])
def test_a_dead_simulator_referee_or_master_ends_the_match_at_once_with_a_complete_bag(tmp_path, one_vs_one, node):
    """(The report of a match cut short: the test above.)"""
    match = RunningMatch(tmp_path, one_vs_one, half_seconds=120, report=False)
    match.wait_for("kickoff for")
    time.sleep(3.0)
    if node == "/sim_visual":  # first a robot's node (one a robot, the default) dies: reported, the match goes on
        match.kill("/nubot1/robot")
        match.wait_for("node /nubot1/robot died", timeout=10)
        assert match.process.poll() is None, "the match goes on without a robot node"
    before = match.sim_time()
    if node == "/master":
        port = match.master.rstrip("/").rsplit(":", 1)[1]
        pids = subprocess.run(["pgrep", "-f", f"rosmaster --core -p {port}"], capture_output=True, text=True)
        assert pids.stdout.split(), "the match's master runs"
        for pid in pids.stdout.split():
            os.kill(int(pid), signal.SIGKILL)
    else:
        match.kill(node)
    killed = time.monotonic()
    match.wait_for(f"MATCH CUT SHORT: required node {node} died", timeout=15)
    assert time.monotonic() - killed < 5.0, "noticed at once"
    status = match.finish(timeout=120)
    assert status == CUT_SHORT_STATUS, match.text[-3000:]
    folder = match.folder()
    run = json.loads((folder / RUN_FILE).read_text())
    assert run["ended"] == "cut short" and node in run["reason"]
    # up to the kill: the last clock ticks the simulator sent as it died may reach the runner and not the recorder
    assert bag_end(folder / "match.bag") >= before - 0.1, "the bag is closed and holds the match up to the kill"
    assert leftovers(match.master) == [], "nothing of the match runs on"


def test_an_interrupted_match_stops_every_node_and_closes_its_bag_even_started_as_a_background_job(
        tmp_path, one_vs_one):
    """``kill -INT`` (Ctrl-C) on a match a script started in the background, where SIGINT comes ignored."""
    match = RunningMatch(tmp_path, one_vs_one, half_seconds=120, report=False, sigint_ignored=True)
    match.wait_for("kickoff for")
    before = match.sim_time()
    match.process.send_signal(signal.SIGINT)
    sent = time.monotonic()
    status = match.finish(timeout=60)
    assert status == 130 and "match interrupted: every node of the match is stopped" in match.text, match.text[-3000:]
    assert time.monotonic() - sent < 30.0
    # up to the stop: the recorder, stopped with every node, may not have written the last clock ticks it was sent
    assert bag_end(match.folder() / "match.bag") >= before - 0.1, "the bag is closed and holds the match up to the stop"
    assert leftovers(match.master) == [], "nothing of the match runs on"


def test_a_simulator_that_refuses_to_start_ends_the_run_at_once_saying_why(tmp_path, one_vs_one):
    """The simulator is the one judge of its parameters: the runner hands its refusal on, not a timeout later."""
    started = time.monotonic()
    done = subprocess.run(
        [sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds", "10", "--halves", "1",
         "--out", str(tmp_path / "matches"), "--viewer-port", "-1", "--real-time-factor", "500", *one_vs_one],
        capture_output=True, text=True, timeout=120)
    took = time.monotonic() - started
    assert done.returncode == 1, done.stdout + done.stderr
    assert "match not started: the simulator's launch ended at start" in done.stderr
    assert "real_time_factor must be at most 100" in done.stderr, done.stderr  # the end of its log
    assert "Traceback" not in done.stderr.split("the end of")[0]
    assert took < 45.0, f"{took:.0f} s: the runner waited for a simulator that was gone"
