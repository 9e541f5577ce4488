"""Play a refereed 5 vs 5 match on this machine, record it to a rosbag, and report on it.

Starts a private roscore on a free port, the simulator (``sim_visual match.launch``, which loads
the match's world description into /world for every node), a recorder (``rosbag record -a``),
both teams through the spawner (each robot's world model and nubot_control under its prefix, in one
node or, with ``--processes two``, in two; one relay per team) and the automatic referee. Shows the
game clock, the score and the last referee event while it plays; at the end writes
``matches/match-<time>/match.bag`` and the match report (report.json, heatmap.png, trajectories.png)
from the bag alone.
Parameters: ``--field`` (18x12, 22x14 or a world description YAML), ``--half-seconds`` [s of game
time], ``--halves``, ``--real-time-factor``, ``--seed``, ``--team`` (twice), ``--tracker``,
``--processes``, ``--out``.
"""

from __future__ import annotations

import argparse
import os
import re
import signal
import subprocess
import sys
import time
from dataclasses import replace
from datetime import datetime
from pathlib import Path

import psutil
import rosbag
import rosgraph
import rospy
from rosgraph_msgs.msg import Clock

from nubot_common import NubotCommonError
from nubot_common.json_text import strict_json
from nubot_common.msg import GameState
from nubot_common.naming import RobotSelection, parse_agent_ids
from nubot_common.node_io import wait_for_robots
from nubot_common.params import load_yaml
from nubot_common.processes import Launched, RosMaster, process_table
from nubot_common.world_description import load_world, world_file
from nubot_control.team_config import TeamConfig
from nubot_tools.node_watch import NodeEvent, NodeWatch
from nubot_tools.progress import SimProgress
from nubot_tools.report import match_report
from nubot_tools.resources import ResourceLog
from nubot_tools.workspace import MATCHES, TEAMS


class GameWatcher:
    """Follows /referee/state and /clock."""

    def __init__(self) -> None:
        self.clock = 0.0
        self.state = None
        self.events: list[tuple[float, str]] = []
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1)
        rospy.Subscriber("/referee/state", GameState, self._on_state, queue_size=10)

    def _on_clock(self, msg) -> None:
        self.clock = msg.clock.to_sec()

    def _on_state(self, msg) -> None:
        self.state = msg
        if msg.last_event and (not self.events or self.events[-1][1] != msg.last_event):
            self.events.append((self.clock, msg.last_event))
            print(f"  [{_clock(self.clock)}] {msg.last_event}", flush=True)

    def line(self) -> str:
        s = self.state
        if s is None:
            return f"  sim {_clock(self.clock)}: waiting for the referee"
        score = " - ".join(f"{team} {goals}" for team, goals in zip(s.teams, s.score))
        status = "running" if s.running else "stopped"
        return f"  sim {_clock(self.clock)} | half {s.half} {_clock(s.game_time)} | {score} | {status}"


class PerfMonitor:
    """Measures a running match: real-time factor, each robot's control rate, CPU and memory per node kind."""

    KINDS = ("sim_visual_node", "robot_node", "world_model_node", "nubot_control_node", "sim_interface", "referee",
             "record", "viewer", "match_markers", "rosmaster", "rosout")

    def __init__(self, robots: list[str], launched: list, rate: float = 33.0) -> None:
        self.rate = rate
        self.launched = launched
        self.robots = robots
        self.samples: list[dict[str, float]] = []
        self.start: tuple[float, float] | None = None  # (wall, sim) when measuring began
        self.end: tuple[float, float] | None = None
        self.subscribers: dict[str, int] = {}  # topic -> subscribing nodes, once every node is up
        self._known: dict[int, object] = {}  # psutil measures CPU between two calls on the same Process object

    def cycles(self, bag: Path) -> dict[str, int]:
        """Each robot's control cycles while measuring: its StrategyInfo messages (one a cycle) in the match's bag,
        by their sim time; counted from the bag, not by subscribing, so that measuring adds no messages to a match
        whose cost is mostly rospy's per message."""
        assert self.start is not None and self.end is not None
        topics = {f"/{r}/nubotcontrol/strategy": r for r in self.robots}
        counts = dict.fromkeys(self.robots, 0)
        with rosbag.Bag(str(bag)) as recorded:
            for topic, _msg, stamp in recorded.read_messages(topics=list(topics), raw=True):
                if self.start[1] <= stamp.to_sec() <= self.end[1]:
                    counts[topics[topic]] += 1
        return counts

    def _processes(self):
        procs = []
        for launched in self.launched:
            try:
                root = psutil.Process(launched.process.pid)
                procs += [root, *root.children(recursive=True)]
            except psutil.NoSuchProcess:
                continue
        return [self._known.setdefault(p.pid, p) for p in procs]

    def begin(self, clock: float) -> None:
        for proc in self._processes():
            try:
                proc.cpu_percent(None)
            except Exception:  # noqa: BLE001 - a process may end between listing and asking
                pass
        self.start = (time.monotonic(), clock)
        self.subscribers = subscriber_counts()

    def sample(self) -> None:
        kinds: dict[str, float] = {}
        memory = 0.0
        for proc in self._processes():
            try:
                cmd = " ".join(proc.cmdline())
                cpu = proc.cpu_percent(None) / 100.0
                memory += proc.memory_info().rss
            except Exception:  # noqa: BLE001
                continue
            kind = next((k for k in self.KINDS if k in cmd), "other")
            kinds[kind] = kinds.get(kind, 0.0) + cpu
        kinds["rss_mib"] = memory / 2**20
        self.samples.append(kinds)

    def stop(self, clock: float) -> None:
        self.end = (time.monotonic(), clock)

    def result(self, bag: Path) -> dict:
        assert self.start is not None and self.end is not None
        wall, sim = self.end[0] - self.start[0], self.end[1] - self.start[1]
        expected = self.rate * sim
        counts = self.cycles(bag)
        rates = {r: n / sim for r, n in counts.items()} if sim > 0 else {}
        # a robot's cycle just inside the window's edge is not a cycle another robot missed
        missed = {r: max(0.0, expected - n) for r, n in counts.items()}
        samples = self.samples[1:] or self.samples
        kinds = sorted({k for s in samples for k in s} - {"rss_mib"})
        cpu = {k: round(sum(s.get(k, 0.0) for s in samples) / len(samples), 3) for k in kinds}
        return {
            "wall_seconds": round(wall, 1), "sim_seconds": round(sim, 1),
            "achieved_real_time_factor": round(sim / wall, 3) if wall > 0 else None,
            "control_rate_hz": {r: round(v, 2) for r, v in rates.items()},
            "control_rate_min_hz": round(min(rates.values()), 2) if rates else None,
            "missed_cycles": {r: round(m) for r, m in missed.items()},
            "missed_cycle_share": round(sum(missed.values()) / (expected * len(counts)), 4) if expected > 0 else None,
            "cpu_cores_by_kind": cpu, "cpu_cores_total": round(sum(cpu.values()), 2),
            # What a simulated second costs, however fast the saturated machine let the match run.
            "cpu_core_seconds_per_sim_second": round(sum(cpu.values()) * wall / sim, 2) if sim > 0 else None,
            "rss_mib_total": round(max(s["rss_mib"] for s in samples), 1),
            "cpus": os.cpu_count(),
            "subscribers": self.subscribers,
        }


def subscriber_counts() -> dict[str, int]:
    """How many nodes subscribe to each topic (the master's system state): each message costs every one of them."""
    _publishers, subscribers, _services = rosgraph.Master("/match_runner").getSystemState()
    return {topic: len(nodes) for topic, nodes in subscribers}


# Camera images (20 MB/s per robot at 30 Hz) and RGB-D clouds stay out of a match's bag; record them apart when
# needed. tf and the RViz markers stay out too: match_markers makes them again from the bag's model states, referee
# and paths.
UNRECORDED = (r"/tf|/match_markers/.*|"
              r".*/(camera/image_raw|camera/labels|omnivision/debug_image|front_camera/image_raw|kinect/\w+/points)")
CUT_SHORT_STATUS = 3  # exit status of a match that did not reach full time
RUN_FILE = "run.json"  # beside the bag: how the match ended, and every node that died or came back


class MatchRun:
    """Watches every node of the match: a dead simulator, recorder, referee or master cuts the match short;
    a dead robot node (robot, or world_model and nubot_control with two ``processes`` a robot; a team's relay) is
    reported and the match goes on."""

    POLL = 0.5  # [s, wall]

    def __init__(self, master: RosMaster, configs: list, out: Path, processes: str = "one"):
        nodes = {"/sim_visual": True, "/match_recorder": True, "/referee": True}
        parts = ("robot",) if processes == "one" else ("world_model", "nubot_control")
        for config in configs:
            nodes[f"/{config.prefix}/sim_interface"] = False
            for name in config.robot_names():
                nodes |= {f"/{name}/{part}": False for part in parts}
        self.master = master
        self.watch = NodeWatch(master.uri, nodes)
        self.watcher = GameWatcher()
        self.out = out
        self.ended: str | None = None  # why the match was cut short; None while it runs or at full time
        self.events: list[dict] = []
        self._next_poll = 0.0

    def _note(self, text: str, **extra: object) -> None:
        clock = self.watcher.clock
        self.events.append({"sim_time": round(clock, 2), "wall_time": datetime.now().isoformat(timespec="seconds"),
                            "event": text, **extra})
        print(f"  [{_clock(clock)}] {text}", flush=True)

    def cut_short(self, reason: str) -> None:
        if self.ended is None:
            self.ended = reason
            self._note(f"MATCH CUT SHORT: {reason}", cut_short=True)

    def check(self, **launches: Launched) -> bool:
        """Poll the nodes (at most every POLL s); True once the match must end."""
        if time.monotonic() < self._next_poll:
            return self.ended is not None
        self._next_poll = time.monotonic() + self.POLL
        table = process_table()  # one pass over /proc for every launch
        for child in self.master.children:
            child.remember(table)
        events: list[NodeEvent] = self.watch.poll()
        for event in events:
            if event.change != "up":
                self._note(event.describe(), node=event.node, change=event.change, critical=event.critical)
            if event.critical and event.change == "died":
                self.cut_short(event.describe())
        for name, launched in launches.items():
            if not launched.alive():
                self.cut_short(f"the {name}'s launch ended (status {launched.process.returncode})")
        return self.ended is not None

    def finish(self, bag: Path) -> None:
        """After the recorder stopped: recover a bag it could not close, and write RUN_FILE."""
        active = bag.with_name(bag.name + ".active")
        if active.exists() and not bag.exists():
            done = subprocess.run(["rosbag", "reindex", "-q", str(active)], capture_output=True, text=True)
            if done.returncode == 0:
                active.rename(bag)
                active.with_name(f"{bag.name}.orig.active").unlink(missing_ok=True)  # reindex's backup
                self._note(f"the recorder did not close {bag.name}; reindexed what it had written")
            else:
                self._note(f"could not reindex {active.name}: {done.stderr.strip()}")
        outcome = {"ended": "full time" if self.ended is None else "cut short", "reason": self.ended,
                   "sim_time": round(self.watcher.clock, 2), "events": self.events}
        (self.out / RUN_FILE).write_text(strict_json(outcome, indent=2))
        if self.ended is not None:
            print(f"  the match was cut short at sim {_clock(self.watcher.clock)}: {self.ended}", flush=True)


STALL_PATIENCE = 120.0  # [s, wall] a match whose sim time stands still this long is cut short


def _clock(seconds: float) -> str:
    return f"{int(seconds // 60):02d}:{seconds % 60:04.1f}"


def wait_for_simulator(sim: Launched, timeout: float) -> str | None:
    """None once the simulator offers its spawn service; else why not: its launch ended (the end of its log
    says how), or ``timeout`` [s] passed."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        if not sim.alive():
            text = re.sub(r"\x1b\[[0-9;]*m", "", sim.log_text())  # roslaunch's colours
            tail = "\n".join("    " + line for line in text.splitlines()[-12:])
            return f"the simulator's launch ended at start (status {sim.process.returncode}); the end of " \
                   f"{sim.log_path}:\n{tail}"
        try:
            rospy.wait_for_service("/sim_visual/spawn_model", timeout=1.0)
            return None
        except rospy.ROSException:
            continue
    return f"the simulator did not offer /sim_visual/spawn_model within {timeout:.0f} s (its log: {sim.log_path})"


def start_viewer(master: RosMaster, port: int, timeout: float = 20.0) -> Launched:
    """Start the live page (``coach4sim viewer``) and print its address; a match goes on without it."""
    viewer = master.launch("viewer", ["rosrun", "coach4sim", "viewer", f"_port:={port}", "__name:=viewer"])
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline and viewer.alive():
        if rospy.has_param("/viewer/url"):
            print(f"  watch it at {rospy.get_param('/viewer/url')}  (the live page and a coach)", flush=True)
            return viewer
        time.sleep(0.1)
    lines = viewer.log_text().strip().splitlines()
    fatal = [line.split("viewer: ", 1)[-1] for line in lines if "FATAL" in line]  # its reason, not what followed
    why = fatal[-1:] or (lines[-1:] if not viewer.alive() else ["it did not start in time"])
    print(f"  no live page: {why[0] if why else 'the viewer ended'}; the match goes on", flush=True)
    return viewer


def _interrupt(_signum: int, _frame: object) -> None:
    raise KeyboardInterrupt  # a kill ends the match as Ctrl-C does: every child of the master is stopped


def main(argv: list[str] | None = None) -> int:
    signal.signal(signal.SIGTERM, _interrupt)
    signal.signal(signal.SIGINT, _interrupt)  # also when started with it ignored (a script's background job)
    try:
        return play(argv)
    except KeyboardInterrupt:
        print("match interrupted: every node of the match is stopped", file=sys.stderr, flush=True)
        return 130


def play(argv: list[str] | None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--half-seconds", type=float, default=90.0, help="length of a half [s of game time]")
    parser.add_argument("--halves", type=int, default=2)
    parser.add_argument("--real-time-factor", type=float, default=1.0)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--team", action="append", type=Path, help="team YAML (twice); default nubot and rival")
    parser.add_argument("--out", type=Path, default=MATCHES)
    parser.add_argument("--no-report", action="store_true")
    parser.add_argument("--perf-json", type=Path, help="measure real-time factor, control rates, CPU and memory")
    parser.add_argument("--resources-json", type=Path,
                        help="sample every process's RSS and CPU every --resources-period s into this file")
    parser.add_argument("--resources-period", type=float, default=10.0, help="[s, wall]")
    parser.add_argument("--tracker", choices=("mpc", "baseline"), default="",
                        help="the motion layer's tracker of every robot (default: as configured, mpc)")
    parser.add_argument("--processes", choices=("one", "two"), default="one",
                        help="each robot's world model and nubot_control in one node (default) or in two")
    parser.add_argument("--field", default="18x12",
                        help="the world: 18x12 (the chapter's field), 22x14 (the current MSL field) or a YAML file")
    parser.add_argument("--vision", default="",
                        help="robots that see through the simulated omni camera instead of the simulator's percepts "
                             "(omni_vision): all, or names such as nubot1,nubot2; each costs a few ms of CPU a frame")
    parser.add_argument("--policy", default="", help="a trained policy file (make train) that the first team's "
                        "--policy-robots play in open play")
    parser.add_argument("--policy-robots", default="2", help="AgentIDs of the first team playing --policy (default 2)")
    parser.add_argument("--viewer-port", type=int, default=8080,
                        help="the live page's port on 127.0.0.1 (default 8080; 0: any free port; -1: no page)")
    args = parser.parse_args(argv)
    teams = args.team or [TEAMS / "nubot.yaml", TEAMS / "rival.yaml"]
    if len(teams) != 2:
        parser.error("give --team exactly twice")

    try:
        world_path = world_file(args.field)
        world = load_world(world_path)
        vision = RobotSelection.parse(args.vision)
        configs = [load_yaml(TeamConfig, t) for t in teams]
        for config in configs:
            config.check_field(world.field)
        policy_args = []
        if args.policy:
            policy = str(Path(args.policy).expanduser().resolve())
            robots = parse_agent_ids(args.policy_robots)
            replace(configs[0], policy=policy, policy_robots=robots).resolved(teams[0].parent)  # loads, or says why
            policy_args = ["--policy", policy, "--policy-robots", ",".join(map(str, robots))]
    except (OSError, NubotCommonError, ValueError) as exc:
        parser.error(str(exc))
    out = args.out / datetime.now().strftime("match-%Y%m%d-%H%M%S")
    out.mkdir(parents=True, exist_ok=True)
    bag = out / "match.bag"
    print(f"match {configs[0].name} vs {configs[1].name} on the {world.name} field: {args.halves} x "
          f"{args.half_seconds:.0f} s, real_time_factor {args.real_time_factor}, seed {args.seed}"
          f"{f', seeing through their cameras: {vision}' if str(vision) else ''}; folder {out}", flush=True)
    perf: PerfMonitor | None = None
    with RosMaster(out / "logs") as master:
        master.use_in_this_process()

        print(f"  ROS master {master.uri} (ROS_MASTER_URI for rostopic, rosbag or the coach)", flush=True)
        rospy.init_node("match_runner", disable_signals=True)
        run = MatchRun(master, configs, out, args.processes)
        watcher = run.watcher
        sim = master.launch("sim", ["roslaunch", "--skip-log-check", "sim_visual", "match.launch",
                                    f"real_time_factor:={args.real_time_factor}", f"seed:={args.seed}",
                                    f"world:={world_path}", f"vision:={vision}",
                                    "goalies:=" + ",".join(f"{c.prefix}{c.goalie}" for c in configs)])
        failure = wait_for_simulator(sim, timeout=60.0)
        if failure is not None:
            print(f"match not started: {failure}", file=sys.stderr, flush=True)
            rospy.signal_shutdown("the simulator did not start")
            return 1
        if args.viewer_port >= 0:
            start_viewer(master, args.viewer_port)
        # A recorder that dies leaves match.bag.active: MatchRun.finish reindexes it into match.bag. What it
        # loses is the chunk it was filling: 256 KB, about 0.3 s of a 5 vs 5 match.
        recorder = master.launch("recorder", ["rosbag", "record", "-a", "-x", UNRECORDED, "--chunksize=256", "-O",
                                              str(bag), "__name:=match_recorder"])
        team_args = ((["--tracker", args.tracker] if args.tracker else []) + ["--vision", str(vision)]
                     + ["--processes", args.processes])
        for k, (team_file, config) in enumerate(zip(teams, configs)):
            master.launch(f"team_{config.prefix}", [sys.executable, "-m", "nubot_tools.ros.spawner",
                                                    str(team_file), *team_args, *(policy_args if k == 0 else [])])
        names = [n for c in configs for n in c.robot_names()]

        silent = wait_for_robots(names, timeout=180, stop=lambda: run.check(simulator=sim))
        if run.ended is None:
            if silent:
                print(f"  robots without a world model after 180 s: {', '.join(silent)}; playing on", flush=True)
            print(f"  {len(names) - len(silent)} robots ready; kick-off", flush=True)
            teams_yaml = out / "referee_teams.yaml"
            teams_yaml.write_text("teams:\n" + "".join(
                f"  - {{prefix: {c.prefix}, attack: {c.attack}, goalie: {c.goalie}}}\n" for c in configs))
            referee = master.launch("referee", ["roslaunch", "--skip-log-check", "coach4sim", "referee.launch",
                                                f"half_duration:={args.half_seconds}", f"halves:={args.halves}",
                                                f"config:={teams_yaml}"])
            perf = PerfMonitor(names, master.children) if args.perf_json else None
            resources = ResourceLog(lambda: [c.process.pid for c in [master.core, *master.children] if c is not None],
                                    lambda: watcher.clock) if args.resources_json else None
            next_sample = 0.0
            perf_started = False
            wall_start, last_line = time.monotonic(), 0.0
            # a match that advances, however slowly (every robot on its camera), plays to full time
            progress = SimProgress(STALL_PATIENCE)
            while True:
                s = watcher.state
                # the referee ends a half in the update that takes its clock to the half's length, so a
                # stoppage just before the end (ball out at 19.97 s of 20) does not count as full time
                if s is not None and s.half >= args.halves and s.game_time >= args.half_seconds and not s.running:
                    break
                if run.check(simulator=sim, referee=referee):
                    break
                if progress.stalled(watcher.clock):
                    run.cut_short(progress.describe())
                    break
                if resources is not None and time.monotonic() >= next_sample:
                    next_sample = time.monotonic() + args.resources_period
                    resources.sample(time.monotonic())
                if time.monotonic() - last_line >= 5.0:
                    last_line = time.monotonic()
                    print(watcher.line(), flush=True)
                    if perf is not None:
                        if perf_started:
                            perf.sample()
                        elif s is not None:
                            perf.begin(watcher.clock)
                            perf_started = True
                time.sleep(0.1)
            print(watcher.line(), flush=True)
            elapsed = time.monotonic() - wall_start
            print(f"  {'full time' if run.ended is None else 'match over'} after {elapsed:.0f} s wall "
                  f"({watcher.clock / max(elapsed, 1e-6):.2f} x real time); closing the bag", flush=True)
            if resources is not None:
                resources.save(args.resources_json)
            if perf is not None and perf_started:
                perf.stop(watcher.clock)
        recorder.stop(timeout=20)
        rospy.signal_shutdown("match over")
    run.finish(bag)
    if perf is not None and perf.end is not None and bag.exists():
        figures = perf.result(bag)
        args.perf_json.parent.mkdir(parents=True, exist_ok=True)
        args.perf_json.write_text(strict_json(figures, indent=2))
        print(f"  performance: real-time factor {figures['achieved_real_time_factor']}, slowest control "
              f"loop {figures['control_rate_min_hz']} Hz, missed cycles "
              f"{100 * figures['missed_cycle_share']:.1f} %, CPU {figures['cpu_cores_total']} of "
              f"{figures['cpus']} cores, memory {figures['rss_mib_total']} MiB", flush=True)
    status = 0 if run.ended is None else CUT_SHORT_STATUS
    if args.no_report or not bag.exists():
        return status

    return match_report.main([str(bag), "--out", str(out)]) or status


if __name__ == "__main__":
    sys.exit(main())
