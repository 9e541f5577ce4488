"""Benchmark of the real robot's hardware side (make bench): ``bench/results/hwcontrol.{json,png}``.

1. In-process (deterministic): a robot of the simulator driven by nubot_hwcontrol's controller through the
   simulated drive along a figure eight; the encoder odometry's drift per 10 m against the simulator's truth,
   for the regular and the goalie layout, over ``--seeds`` seeds.
2. Over ROS, in a network namespace (root): nubot_hwcontrol alone on wall time (its loop period, p50/p99, from
   nubotdriver/status); ``real_robot.launch backend:=sim`` driven along the same figure for ``--seconds`` (the
   loop on sim time, the odometry's drift as a user of /nubotdriver/odoinfo sees it, the CPU of every node);
   then the whole robot scoring alone.
The team link's own figures (latency, delivery under loss) are bench_team_link's.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import tempfile
from pathlib import Path

from nubot_comm import netns
from nubot_common.json_text import strict_json
from nubot_hwcontrol.controller import HardwareController, HwControlParams
from nubot_hwcontrol.sim_drive import SimulatedDrive
from nubot_hwcontrol.sim_world import SimulatorWorld
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator


def figure_command(t: float) -> tuple[float, float, float]:
    """The figure of eight both the in-process drift and the real robot's run drive: 2 m/s, turning left then right
    every 5 s [m/s, m/s, rad/s]."""
    return 2.0, 0.0, 1.2 * (1.0 if math.sin(2.0 * math.pi * t / 10.0) >= 0.0 else -1.0)


def in_process_drift(goalie: bool, seed: int, seconds: float = 60.0) -> dict:
    sim = Simulator(SimConfig(robots=(RobotSpawn("nubot1", -1.0, 0.0, 0.0),), ball_start=(3.0, 4.0), seed=seed))
    params = HwControlParams()
    ctl = HardwareController(params, SimulatedDrive(SimulatorWorld(sim, "nubot1"), params.layout(goalie), seed=seed),
                             goalie)
    next_cycle, travelled, last = 0.0, 0.0, None
    while sim.time < seconds:
        if sim.time >= next_cycle - 1e-9:
            ctl.command_velocity(sim.time, *figure_command(sim.time))
            ctl.cycle(sim.time)
            next_cycle += 1.0 / params.rate
            s = sim.world.robot_state("nubot1")
            if last is not None:
                travelled += math.dist(last, (s.x, s.y))
            last = (s.x, s.y)
        sim.step()
    s, odo = sim.world.robot_state("nubot1"), ctl.odometry.estimate
    error = math.hypot(odo.x - (s.x + 1.0), odo.y - s.y)
    return {"goalie": goalie, "seed": seed, "travelled": travelled, "position_error": error,
            "drift_per_10m": error / travelled * 10.0, "heading_error": math.remainder(odo.theta - s.theta, math.tau)}


def in_namespace(scenario: str, seconds: float) -> dict:
    with tempfile.TemporaryDirectory(prefix="bench_hw_") as folder, netns.NetNamespace(f"bench{scenario}") as ns:
        out = Path(folder) / f"{scenario}.json"
        subprocess.run(ns.command(sys.executable, "-m", "nubot_tools.ros.real_robot_run", "--scenario", scenario,
                                  "--seconds", str(seconds), "--out", str(out)), check=True, timeout=seconds * 4 + 120,
                       stdin=subprocess.DEVNULL)
        return json.loads(out.read_text())


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", type=Path, default=Path("bench/results"))
    ap.add_argument("--seeds", type=int, default=5)
    ap.add_argument("--seconds", type=float, default=60.0)
    args = ap.parse_args()

    report: dict = {"in_process": [in_process_drift(g, s) for g in (False, True) for s in range(args.seeds)]}
    for layout in ("regular", "goalie"):
        runs = [r for r in report["in_process"] if r["goalie"] == (layout == "goalie")]
        drifts = sorted(r["drift_per_10m"] for r in runs)
        print(f"in-process odometry drift ({layout}, figure eight 60 s, {len(runs)} seeds): "
              f"median {100 * drifts[len(drifts) // 2]:.1f} cm per 10 m, worst {100 * drifts[-1]:.1f}")
    why = netns.unavailable()
    if why is None:
        wall = in_namespace("loop", 30.0)
        figure = in_namespace("figure", args.seconds)
        score = in_namespace("score", 60.0)
        report["ros_loop"], report["ros_figure"], report["ros_score"] = wall, figure, score
        print(f"nubot_hwcontrol alone, wall time, 30 s: loop period p50 {1000 * wall['loop_period_p50']:.1f} ms, "
              f"worst p99 of 1 s windows {1000 * wall['loop_period_p99']:.1f} ms (overruns {wall['loop_overruns']}), "
              f"CPU {wall['cpu_cores']['/nubot_hwcontrol']:.2f} cores")
        print(f"real_robot.launch backend:=sim, figure eight {figure['sim_seconds']:.0f} s: loop period (sim time, "
              f"/clock at 100 Hz) p50 {1000 * figure['loop_period_p50']:.1f} ms, worst p99 "
              f"{1000 * figure['loop_period_p99']:.1f} ms "
              f"(overruns {figure['loop_overruns']}), odometry drift {100 * figure['drift_per_10m']:.1f} cm per 10 m "
              f"over {figure['travelled']:.0f} m")
        print("CPU per node [cores]: " + ", ".join(f"{k} {v:.2f}" for k, v in sorted(figure["cpu_cores"].items())))
        goal = score["goals"][0]["time"] if score.get("goals") else None
        print(f"1 vs 0: {'goal after %.1f s of play' % goal if goal is not None else 'no goal in 60 s'}")
    else:
        print(f"skipping the ROS part: {why}")
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "hwcontrol.json").write_text(strict_json(report, indent=1))
    print(f"wrote {args.out / 'hwcontrol.json'}")
    return 0
