"""Benchmark the simulator: steps per second (1 and 10 robots) and achieved real-time factor.

Measures, on this machine:
  core:  the pure simulator in-process (no ROS), robots driven in circles, ball rolling;
  ros:   the sim_visual node headless over a private roscore, ``real_time_factor`` 0
         (as fast as possible) and 1.0, with every robot's OmniVisionInfo published at
         30 Hz and commands arriving at 33 Hz; CPU share of the simulator process.
Writes ``<out>/sim.json`` and prints a table.
"""

from __future__ import annotations

import argparse
import math
import os
import platform
import sys
import threading
import time
from pathlib import Path

import psutil
import rospy
import yaml
from rosgraph_msgs.msg import Clock

from nubot_common.json_text import strict_json
from nubot_common.msg import VelCmd
from nubot_common.processes import RosMaster
from nubot_tools.workspace import BENCH_RESULTS
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator
from sim_visual.world import BallState


def spawns(count: int) -> list[RobotSpawn]:
    """``count`` robots spread over the field, half of them in a second team."""
    robots = []
    for i in range(count):
        team, k = ("nubot", 1 + i // 2) if i % 2 == 0 else ("rival", 1 + i // 2)
        x = (-1 if team == "nubot" else 1) * (1.5 + 1.5 * (k - 1))
        robots.append(RobotSpawn(f"{team}{k}", x, (k - 3) * 1.8, 0.0, 1 if team == "nubot" else -1))
    return robots


def circle_command(i: int, t: float) -> tuple[float, float, float]:
    return 2.0, 0.0, 1.0 + 0.1 * i * math.sin(0.3 * t)


def bench_core(count: int, sim_seconds: float) -> dict:
    sim = Simulator(SimConfig(robots=tuple(spawns(count)), ball_start=(0.0, 0.0)))

    sim.world.set_ball_state(BallState(0.0, 0.0, 0.11, 3.0, 1.0, 0.0))
    next_cmd, next_vision = 0.0, 0.0
    start = time.perf_counter()
    while sim.time < sim_seconds:
        if sim.time >= next_cmd:
            for i, name in enumerate(sim.plugins):
                sim.command_velocity(name, *circle_command(i, sim.time))
            next_cmd += 1 / 33
        if sim.time >= next_vision:
            for name in sim.plugins:
                sim.observe(name)
            next_vision += 1 / 30
        sim.step()
    wall = time.perf_counter() - start
    return {"robots": count, "sim_seconds": sim_seconds, "wall_seconds": round(wall, 3),
            "steps_per_second": round(sim.steps / wall, 1), "real_time_factor": round(sim.time / wall, 2)}


class ClockWatch:
    def __init__(self) -> None:
        self.clock = 0.0
        rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=1)

    def _on_clock(self, msg) -> None:
        self.clock = msg.clock.to_sec()


def drive(robots: list[RobotSpawn], stop: threading.Event) -> None:
    """Publish body-velocity commands to every robot at 33 Hz (wall time), as control nodes would."""
    pubs = [rospy.Publisher(f"/{r.name}/nubotcontrol/velcmd", VelCmd, queue_size=1) for r in robots]
    t0 = time.monotonic()
    while not stop.is_set():
        t = time.monotonic() - t0
        for i, pub in enumerate(pubs):
            pub.publish(VelCmd(*circle_command(i, t)))
        time.sleep(1 / 33)
    for pub in pubs:
        pub.unregister()


def sim_process(launch) -> psutil.Process | None:
    for child in psutil.Process(launch.process.pid).children(recursive=True):
        if any("sim_visual_node" in part for part in child.cmdline()):
            return child
    return None


def bench_ros(master: RosMaster, out: Path, count: int, rtf: float, window: float) -> dict:
    robots = spawns(count)
    config = out / f"bench_{count}.yaml"
    config.write_text(yaml.safe_dump({"sim": {
        "robots": [{"name": r.name, "x": r.x, "y": r.y, "theta": r.theta, "attack": r.attack} for r in robots],
        "plugin": {"command_timeout": 0.0}}}))
    launch = master.launch(f"sim_{count}_{rtf}", ["roslaunch", "sim_visual", "single_robot.launch", "demo:=false",
                                                  f"real_time_factor:={rtf}", f"config:={config}"])
    watch = ClockWatch()
    stop = threading.Event()
    driver = threading.Thread(target=drive, args=(robots, stop), daemon=True)
    try:
        deadline = time.monotonic() + 60
        while watch.clock < 0.5 and time.monotonic() < deadline:
            time.sleep(0.05)
        if watch.clock < 0.5:
            raise RuntimeError(f"simulator did not start:\n{launch.log_text()[-3000:]}")
        driver.start()
        time.sleep(1.0)
        proc = sim_process(launch)
        cpu0 = proc.cpu_times() if proc else None
        sim0, wall0 = watch.clock, time.monotonic()
        time.sleep(window)
        sim1, wall1 = watch.clock, time.monotonic()
        cpu1 = proc.cpu_times() if proc else None
        memory = proc.memory_info().rss / 2**20 if proc else None
    finally:
        stop.set()
        launch.stop()
        time.sleep(0.5)
    step = SimConfig().physics.step_size
    achieved = (sim1 - sim0) / (wall1 - wall0)
    cpu = ((cpu1.user + cpu1.system) - (cpu0.user + cpu0.system)) / (wall1 - wall0) if proc else None
    return {"robots": count, "requested_real_time_factor": rtf, "wall_seconds": round(wall1 - wall0, 2),
            "steps_per_second": round(achieved / step, 1), "achieved_real_time_factor": round(achieved, 3),
            "sim_process_cpu_share": round(cpu, 3) if cpu is not None else None,
            "sim_process_rss_mib": round(memory, 1) if memory is not None else None}


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--window", type=float, default=8.0, help="wall seconds measured per ROS case")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    results: dict = {"machine": {"cpus": os.cpu_count(), "python": platform.python_version(),
                                 "platform": platform.platform()}, "core": [], "ros": []}
    for count in (1, 10):
        print(f"[bench] core simulator, {count} robot(s) ...", flush=True)
        results["core"].append(bench_core(count, 20.0))
    with RosMaster(args.out / "logs") as master:
        master.use_in_this_process()

        rospy.init_node("bench_sim", disable_signals=True)
        for count, rtf in ((1, 0.0), (10, 0.0), (1, 1.0), (10, 1.0)):
            print(f"[bench] sim_visual node, {count} robot(s), real_time_factor {rtf} ...", flush=True)
            results["ros"].append(bench_ros(master, args.out, count, rtf, args.window))
        rospy.signal_shutdown("bench done")
    (args.out / "sim.json").write_text(strict_json(results, indent=2))
    print(f"{'case':<34}{'steps/s':>10}{'RTF':>8}{'CPU':>7}")
    for r in results["core"]:
        print(f"{'core, %d robot(s)' % r['robots']:<34}{r['steps_per_second']:>10.0f}{r['real_time_factor']:>8.2f}")
    for r in results["ros"]:
        case = f"ROS node, {r['robots']} robot(s), rtf {r['requested_real_time_factor']}"
        print(f"{case:<34}{r['steps_per_second']:>10.0f}{r['achieved_real_time_factor']:>8.2f}"
              f"{r['sim_process_cpu_share']:>7.2f}")
    print(f"figures: {args.out / 'sim.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
