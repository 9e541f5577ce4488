"""Several machines (chapter 7.2), built from network namespaces on this machine.

Computer A runs the master, the simulator and the recorder; computer B one team, the referee and the
coach; computer C the other team. They share a LAN (one bridge, 10.77.0.0/24, in a namespace of its own)
and nothing else: each machine reaches the others only through its ``ROS_MASTER_URI`` and ``ROS_IP``,
exactly as the README's setup on real machines. A short match is played across them and reported from
the bag A recorded.
"""

from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from nubot_common.processes import Launched, wait_until

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[3]
SUBNET = "10.77.0"
MACHINES = {"a": 1, "b": 2, "c": 3}


def ip(*args: str) -> None:
    subprocess.run(["ip", *args], check=True, capture_output=True)


@pytest.fixture
def lan():
    """Three namespaces (A, B, C) on one bridge; yields {machine: (namespace, address)}."""
    tag = f"nb{os.getpid() % 100000}"
    switch = f"{tag}-lan"
    made = [switch]
    ip("netns", "add", switch)
    try:
        ip("-n", switch, "link", "add", "br0", "type", "bridge")
        ip("-n", switch, "link", "set", "br0", "up")
        machines = {}
        for name, host in MACHINES.items():
            ns = f"{tag}-{name}"
            ip("netns", "add", ns)
            made.append(ns)
            ip("link", "add", f"{tag}{name}", "netns", ns, "type", "veth", "peer", "name", f"{tag}{name}p",
               "netns", switch)
            ip("-n", switch, "link", "set", f"{tag}{name}p", "master", "br0", "up")
            ip("-n", ns, "addr", "add", f"{SUBNET}.{host}/24", "dev", f"{tag}{name}")
            ip("-n", ns, "link", "set", f"{tag}{name}", "up")
            ip("-n", ns, "link", "set", "lo", "up")
            machines[name] = (ns, f"{SUBNET}.{host}")
        yield machines
    finally:
        for ns in made:
            pids = subprocess.run(["ip", "netns", "pids", ns], capture_output=True, text=True).stdout.split()
            for pid in pids:
                subprocess.run(["kill", "-9", pid], capture_output=True)
            subprocess.run(["ip", "netns", "del", ns], capture_output=True)


class Machine:
    def __init__(self, name: str, ns: str, address: str, master: str, logs: Path):
        self.name, self.ns, self.address, self.logs = name, ns, address, logs
        self.env = dict(os.environ, ROS_MASTER_URI=master, ROS_IP=address, ROS_LOG_DIR=str(logs / f"ros_{name}"),
                        PYTHONUNBUFFERED="1")
        self.env.pop("ROS_HOSTNAME", None)
        self.started: list[Launched] = []

    def start(self, label: str, *args: str) -> Launched:
        child = Launched(["ip", "netns", "exec", self.ns, *args], self.env, self.logs / f"{self.name}_{label}.log")
        self.started.append(child)
        return child

    def run(self, *args: str, timeout: float = 60.0) -> subprocess.CompletedProcess:
        return subprocess.run(["ip", "netns", "exec", self.ns, *args], env=self.env, capture_output=True, text=True,
                              timeout=timeout)

    def heard(self, topic: str) -> bool:
        return self.run("rostopic", "echo", "-n", "1", "--noarr", topic, timeout=30).returncode == 0


def test_a_match_across_three_machines_is_played_recorded_and_reported(lan, tmp_path, two_vs_two):
    """A 2 vs 2 match (a goalie and a field player each): what crosses the LAN is the same as in 5 vs 5."""
    home, away = two_vs_two[1], two_vs_two[3]
    master = f"http://{lan['a'][1]}:11311"
    a, b, c = (Machine(n, *lan[n], master, tmp_path) for n in ("a", "b", "c"))
    bag = tmp_path / "match.bag"
    try:
        a.start("roscore", "roscore", "-p", "11311")
        wait_until(lambda: a.run("rosparam", "get", "/rosversion", timeout=10).returncode == 0, 30, "the master on A")
        a.start("sim", "roslaunch", "--skip-log-check", "sim_visual", "match.launch")
        wait_until(lambda: a.run("rosservice", "info", "/sim_visual/spawn_model", timeout=10).returncode == 0, 60,
                   "the simulator on A")
        recorder = a.start("record", "rosbag", "record", "-a", "-O", str(bag), "__name:=match_recorder")
        b.start("team", sys.executable, str(ROOT / "scripts" / "spawn_team.py"), home)
        c.start("team", sys.executable, str(ROOT / "scripts" / "spawn_team.py"), away)
        for robot in ("nubot2", "rival2"):
            wait_until(lambda r=robot: a.heard(f"/{r}/worldmodel/worldmodelinfo"), 180, f"{robot} seen from A")
        teams = tmp_path / "referee_teams.yaml"
        teams.write_text("teams:\n  - {prefix: nubot, attack: 1}\n  - {prefix: rival, attack: -1}\n")
        referee = b.start("referee", "roslaunch", "--skip-log-check", "coach4sim", "referee.launch",
                          "half_duration:=20", "halves:=1", f"config:={teams}")
        watched = b.run("rosrun", "coach4sim", "coach", "--watch", "rival2", "--count", "2", timeout=60)
        assert watched.returncode == 0 and "rival2" in watched.stdout, watched.stdout + watched.stderr
        wait_until(lambda: "end of the match" in referee.log_text(), 240, "full time, refereed from B")
        recorder.stop(timeout=30)
    finally:
        for machine in (c, b, a):
            for child in reversed(machine.started):
                child.stop(timeout=15)
    report = subprocess.run([sys.executable, str(ROOT / "scripts" / "match_report.py"), str(bag)],
                            capture_output=True, text=True, timeout=300)
    assert report.returncode == 0, report.stdout + report.stderr
    summary = json.loads((tmp_path / "report.json").read_text())
    robots = {f"{p}{k}" for p in ("nubot", "rival") for k in (1, 2)}
    assert set(summary["distance_run_m"]) == robots, "all four robots, from B and C, are in A's bag"
    assert summary["distance_run_m"]["nubot2"] > 3.0 and summary["distance_run_m"]["rival2"] > 3.0, \
        "the field players of both teams ran"
    assert summary["score_agrees"], "the referee on B and the simulator on A agree on the score"
    assert summary["possession"]["nobody"]["share"] < 0.6, "robots reached the ball"

