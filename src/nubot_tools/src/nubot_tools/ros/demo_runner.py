"""Run the single-robot demo headless for a bounded time and report what happened.

Starts a private roscore on a free port, ``roslaunch sim_visual single_robot.launch demo:=true``,
watches the demo's state, the simulator's goals and model states, prints progress, and
writes ``matches/<stamp>/summary.json`` and ``trajectory.png``. Exit status 0 when the
demo scored, 1 otherwise.
"""

from __future__ import annotations

import argparse
import math
import sys
import threading
import time
from datetime import datetime
from pathlib import Path

import matplotlib.pyplot as plt
import rospy
from rosgraph_msgs.msg import Clock
from std_msgs.msg import String

from nubot_common.json_text import strict_json
from nubot_common.msg import GoalEvent, ModelStates
from nubot_common.processes import RosMaster
from nubot_tools.progress import SimProgress
from nubot_tools.workspace import MATCHES


class DemoWatcher:
    def __init__(self) -> None:
        self.lock = threading.Lock()
        self.clock = 0.0
        self.states: list[tuple[float, str]] = []
        self.goals: list[tuple[float, int]] = []
        self.robot_path: list[tuple[float, float, float]] = []
        self.ball_path: list[tuple[float, float, float]] = []
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10)
        rospy.Subscriber("/nubot1/demo/state", String, self._on_state, queue_size=50)
        rospy.Subscriber("/sim_visual/goal", GoalEvent, self._on_goal, queue_size=10)
        rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=10)

    def _on_clock(self, msg) -> None:
        self.clock = msg.clock.to_sec()

    def _on_state(self, msg) -> None:
        with self.lock:
            if not self.states or self.states[-1][1] != msg.data:
                self.states.append((self.clock, msg.data))
                print(f"  t={self.clock:6.2f} s  state {msg.data}", flush=True)

    def _on_goal(self, msg) -> None:
        with self.lock:
            self.goals.append((msg.header.stamp.to_sec(), msg.side))
        print(f"  t={msg.header.stamp.to_sec():6.2f} s  GOAL (goal at {'+x' if msg.side > 0 else '-x'}, "
              f"last touch {msg.last_touch or 'nobody'})", flush=True)

    def _on_states(self, msg) -> None:
        poses = dict(zip(msg.name, msg.pose))
        if "nubot1" not in poses or "football" not in poses:
            return
        r, b = poses["nubot1"].position, poses["football"].position
        with self.lock:
            if not self.robot_path or self.clock - self.robot_path[-1][0] >= 0.05:
                self.robot_path.append((self.clock, r.x, r.y))
                self.ball_path.append((self.clock, b.x, b.y))

    def distance_covered(self) -> float:
        with self.lock:
            path = list(self.robot_path)
        return sum(math.dist(a[1:], b[1:]) for a, b in zip(path, path[1:]))


def plot(watcher: DemoWatcher, out: Path, field_length: float, field_width: float) -> None:
    fig, ax = plt.subplots(figsize=(9, 6))
    hl, hw = field_length / 2, field_width / 2
    ax.add_patch(plt.Rectangle((-hl, -hw), field_length, field_width, fill=True, color="#2e7d32", alpha=0.3))
    ax.plot([0, 0], [-hw, hw], color="white")
    for side in (-1, 1):
        ax.plot([side * hl, side * hl], [-1.2, 1.2], color="black", linewidth=4)
    if watcher.robot_path:
        ax.plot([p[1] for p in watcher.robot_path], [p[2] for p in watcher.robot_path], label="nubot1", color="blue")
        ax.plot([p[1] for p in watcher.ball_path], [p[2] for p in watcher.ball_path], label="ball", color="orange")
    ax.set_xlim(-hl - 1, hl + 1)
    ax.set_ylim(-hw - 1, hw + 1)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_title("Single-robot demo: trajectories")
    ax.legend(loc="upper left")
    fig.savefig(out, dpi=100, bbox_inches="tight")
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--sim-seconds", type=float, default=60.0, help="stop after this much sim time")
    parser.add_argument("--real-time-factor", type=float, default=1.0, help="0 = as fast as possible")
    parser.add_argument("--shot", choices=["lob", "ground"], default="lob")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out", type=Path, default=MATCHES)
    args = parser.parse_args(argv)

    out = args.out / datetime.now().strftime("demo-%Y%m%d-%H%M%S")
    out.mkdir(parents=True, exist_ok=True)
    print(f"single-robot demo: up to {args.sim_seconds:.0f} s of sim time, logs in {out}", flush=True)
    with RosMaster(out / "logs") as master:
        master.use_in_this_process()

        rospy.init_node("demo_watcher", disable_signals=True)
        watcher = DemoWatcher()
        sim = master.launch("single_robot", ["roslaunch", "sim_visual", "single_robot.launch", "demo:=true",
                                             f"real_time_factor:={args.real_time_factor}", f"seed:={args.seed}",
                                             f"shot:={args.shot}"])
        wall_start, last_report = time.monotonic(), 0.0
        progress = SimProgress(60.0)  # the demo waits for a slow simulation, not for a stopped one
        while watcher.clock < args.sim_seconds and sim.alive():
            if watcher.states and watcher.states[-1][1] == "HOME":
                break
            if time.monotonic() - last_report > 5.0:
                last_report = time.monotonic()
                print(f"  ... sim time {watcher.clock:6.2f} s, distance covered {watcher.distance_covered():5.2f} m",
                      flush=True)
            if progress.stalled(watcher.clock):
                print(f"  giving up: {progress.describe()}", flush=True)
                break
            time.sleep(0.05)
        crashed = not sim.alive()
        rospy.signal_shutdown("demo finished")
    kicks = sum(1 for _, s in watcher.states if s == "KICK_BALL")
    summary = {
        "sim_seconds": round(watcher.clock, 3),
        "wall_seconds": round(time.monotonic() - wall_start, 2),
        "transitions": [{"t": round(t, 3), "state": s} for t, s in watcher.states],
        "kicks": kicks,
        "goals": [{"t": round(t, 3), "goal_side": side} for t, side in watcher.goals],
        "distance_covered_m": round(watcher.distance_covered(), 3),
        "simulator_crashed": crashed,
    }
    (out / "summary.json").write_text(strict_json(summary, indent=2))
    plot(watcher, out / "trajectory.png", 18.0, 12.0)
    print(f"done after {summary['sim_seconds']:.2f} s of sim time ({summary['wall_seconds']:.1f} s wall): "
          f"{kicks} kick(s), {len(watcher.goals)} goal(s), nubot1 covered {summary['distance_covered_m']:.2f} m")
    print(f"summary: {out / 'summary.json'}\ntrajectories: {out / 'trajectory.png'}")
    if crashed:
        print(f"the simulator stopped unexpectedly; see {out / 'logs'}", file=sys.stderr)
    return 0 if watcher.goals and not crashed else 1


if __name__ == "__main__":
    sys.exit(main())
