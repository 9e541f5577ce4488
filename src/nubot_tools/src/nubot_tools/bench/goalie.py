"""Benchmark the goalie against seeded shots in one process without ROS: how many lobs and ground shots it saves.

    python scripts/bench_goalie.py --out bench/results [--seed 0] [--shots 200] [--quick] [--label after]
                                   [--perception truth|vision]

Requires: the world (``--field``), sim_visual's ``Simulator`` (ODE, the percepts a match without cameras gives:
omni vision and, for the goalie, ``observe_ball3d``; with ``--perception vision`` the goalie's 3-D ball comes
instead from its two simulated RGB-D cameras through kinect_ball's core, with kinect_ball's ``config/kinect_ball.yaml``
and the goalie's own noisy self-localization), nubot_control's ``RobotAgent`` with the default parameters (the
goalie's whole software: world model, roles, ``keep_goal``, motion layer), matplotlib.
Each shot: the goalie ``nubot1`` (attacking +x, so its team frame is the world frame) starts on its goal line
and plays (STARTROBOT) while the ball lies still for ``SETTLE`` s at a seeded spot 4-9 m from the centre of its goal
(any angle up to 60 deg off the goal's axis), so it takes its place; then the ball is shot at a seeded point of the
goal mouth (at most 0.2 m inside a post): half the shots (alternately) a lob as the simulator's Shoot makes it
(``rules.lob_velocity``: its top crosses the line below the bar), the others a ground shot at 6-10 m/s. Percepts
at 30 Hz, control at 33 Hz, physics at the simulator's step, as in a match. A shot is conceded when the simulator
scores it within ``WATCH`` s, saved otherwise (every shot is aimed inside the goal mouth: without a goalie each
one would score, ``--no-goalie`` checks that).

Provides, in ``--out``: ``goalie_<label>.json`` (the machine, save rates by kind with 95 % Wilson intervals, and
by distance) and ``goalie_<label>.png`` (save rate by kind and distance band). Deterministic for a seed.
"""

from __future__ import annotations

import argparse
import math
import time
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

from kinect_ball.pipeline import KinectBall, KinectBallParams
from nubot_common.clouds import Cloud
from nubot_common.geometry import Pose2D
from nubot_common.json_text import strict_json
from nubot_common.match_mode import MatchMode
from nubot_common.naming import parse_robot_name
from nubot_common.packages import package_path
from nubot_common.params import load_yaml
from nubot_common.percepts import Ball3dPercept
from nubot_common.world_description import WorldDescription, load_world
from nubot_control.agent import RobotAgent
from nubot_control.params import ControlParams
from nubot_match.statistics import share_interval
from nubot_tools.bench.harness import machine
from nubot_tools.workspace import BENCH_RESULTS
from sim_visual.params import PluginParams, RobotSpawn, SimConfig
from sim_visual.rules import lob_velocity
from sim_visual.simulator import GoalScored, Simulator
from sim_visual.world import BallState

GOALIE = "nubot1"
KINECT_CONFIG = package_path("kinect_ball") / "config" / "kinect_ball.yaml"
SETTLE = 1.5  # the ball lies still this long before the shot [s]
WATCH = 3.0  # a shot not scored this long after it was struck is saved [s]
DISTANCES = (4.0, 9.0)  # from the goal's centre [m]
MAX_ANGLE = math.radians(60.0)  # off the goal's axis
GROUND_SPEEDS = (6.0, 10.0)  # [m/s]
POST_MARGIN = 0.2  # aim at most this far inside a post [m]
VISION_PERIOD, CONTROL_PERIOD = 1.0 / 30.0, 1.0 / 33.0  # [s]
LOB_LIFT = 0.01  # a lobbed ball starts this far above the carpet, as the simulator's Shoot lifts it [m]


@dataclass(frozen=True)
class Shot:
    index: int
    kind: str  # "lob" or "ground"
    distance: float  # from the goal's centre [m]
    x: float  # where the ball lies [m]
    y: float
    aim_y: float  # the point of the goal line aimed at [m]
    speed: float  # the ball's initial speed [m/s]
    saved: bool
    goal_at: float | None  # time after the shot the goal was scored [s]


def seeded_shots(n: int, seed: int, world: WorldDescription) -> list[dict[str, float | str]]:
    """``n`` shots at the goal at -x, from one generator: alternately a lob and a ground shot."""
    rng = np.random.default_rng(seed)
    f = world.field
    out: list[dict[str, float | str]] = []
    for i in range(n):
        d = rng.uniform(*DISTANCES)
        a = rng.uniform(-MAX_ANGLE, MAX_ANGLE)
        x, y = -f.half_length + d * math.cos(a), d * math.sin(a)
        y = max(-f.half_width + 0.5, min(f.half_width - 0.5, y))
        aim_y = rng.uniform(-f.goal_width / 2 + POST_MARGIN, f.goal_width / 2 - POST_MARGIN)
        speed = rng.uniform(*GROUND_SPEEDS)
        out.append({"kind": "lob" if i % 2 == 0 else "ground", "distance": float(math.hypot(x + f.half_length, y)),
                    "x": float(x), "y": float(y), "aim_y": float(aim_y), "speed": float(speed)})
    return out


def ball_launch(shot: dict[str, Any], world: WorldDescription, plugin: PluginParams,
                gravity: float) -> BallState:
    """The ball as it leaves the shooter's foot: along the line to the aimed point."""
    f, r = world.field, world.ball.radius
    x, y = float(shot["x"]), float(shot["y"])
    heading = math.atan2(float(shot["aim_y"]) - y, -f.half_length - x)
    if shot["kind"] == "lob":
        vx, vy, vz = lob_velocity(Pose2D(x, y, heading), x, y, -1, f, r, gravity, plugin)
        return BallState(x, y, r + LOB_LIFT, vx, vy, vz)
    speed = float(shot["speed"])
    vx, vy = speed * math.cos(heading), speed * math.sin(heading)
    return BallState(x, y, r, vx, vy, 0.0, -vy / r, vx / r, 0.0)


def rgbd_ball(sim: Simulator, core: KinectBall, pose: Pose2D) -> Ball3dPercept | None:
    """The goalie's 3-D ball from its two simulated RGB-D cameras through kinect_ball's core."""
    clouds = {f.camera: Cloud(f.points.reshape(-1, 3), f.rgb.reshape(-1, 3), (f.points.shape[0], f.points.shape[1]))
              for f in sim.rgbd_frames(GOALIE)}
    return core.process(sim.time, pose, clouds).percept


def play_shot(index: int, shot: dict[str, Any], world: WorldDescription, seed: int, goalie: bool = True,
              vision: bool = False) -> Shot:
    f = world.field
    spawns = (RobotSpawn(GOALIE, -f.half_length + 0.4, 0.0, 0.0, 1),) if goalie else ()
    sim = Simulator(SimConfig(world=world, robots=spawns, ball_start=(float(shot["x"]), float(shot["y"])),
                              seed=seed * 100_003 + index))
    agent = RobotAgent(parse_robot_name(GOALIE), world, control=ControlParams()) if goalie else None
    if agent is not None:
        agent.on_coach(0.0, MatchMode.STARTROBOT)
    launch = ball_launch(shot, world, sim.plugin_params, sim.config.physics.gravity)
    core = KinectBall(load_yaml(KinectBallParams, KINECT_CONFIG), world.ball.radius) if vision else None
    next_vision = next_control = 0.0
    struck_at: float | None = None
    goal_at: float | None = None
    while sim.time < SETTLE + WATCH:
        t = sim.time
        if struck_at is None and t >= SETTLE:
            sim.set_model_state(sim.config.ball_name, launch)
            struck_at = t
        if agent is not None and t >= next_vision:
            view = sim.observe(GOALIE)
            agent.on_vision(view)
            agent.on_ball3d(sim.observe_ball3d(GOALIE) if core is None else rgbd_ball(sim, core, view.robot.pose))
            next_vision += VISION_PERIOD
        if agent is not None and t >= next_control:
            sim.execute(GOALIE, agent.step(t).command)
            next_control += CONTROL_PERIOD
        events = sim.step()
        if struck_at is not None and any(isinstance(e, GoalScored) and e.side == -1 for e in events):
            goal_at = sim.time - struck_at
            break
    return Shot(index, str(shot["kind"]), float(shot["distance"]), float(shot["x"]), float(shot["y"]),
                float(shot["aim_y"]), math.sqrt(launch.vx ** 2 + launch.vy ** 2 + launch.vz ** 2), goal_at is None,
                goal_at)


def summarise(shots: list[Shot]) -> dict[str, Any]:
    out: dict[str, Any] = {}
    bands = ((4.0, 5.5), (5.5, 7.0), (7.0, 9.01))
    for kind in ("lob", "ground"):
        mine = [s for s in shots if s.kind == kind]
        saved = sum(s.saved for s in mine)
        share = share_interval(saved, len(mine))
        by_band = {}
        for lo, hi in bands:
            band = [s for s in mine if lo <= s.distance < hi]
            by_band[f"{lo:g}-{min(hi, 9.0):g} m"] = {"shots": len(band), "saved": sum(s.saved for s in band)}
        out[kind] = {"shots": len(mine), "saved": saved, "save_rate": saved / len(mine) if mine else 0.0,
                     "ci95": [share.low, share.high], "by_distance": by_band}
    return out


def plot(summary: dict[str, Any], label: str, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6.4, 3.6))
    width = 0.38
    for k, kind in enumerate(("lob", "ground")):
        bands = summary[kind]["by_distance"]
        names = list(bands)
        rates = [b["saved"] / b["shots"] if b["shots"] else 0.0 for b in bands.values()]
        xs = np.arange(len(names)) + (k - 0.5) * width
        ax.bar(xs, rates, width, label=f"{kind}: {summary[kind]['save_rate']:.0%} of {summary[kind]['shots']}")
        ax.set_xticks(np.arange(len(names)), names)
    ax.axhline(0.6, color="grey", linestyle="--", linewidth=1, label="target for lobs: 60 %")
    ax.set_ylim(0, 1)
    ax.set_ylabel("saved")
    ax.set_xlabel("distance of the shot from the goal's centre")
    ax.set_title(f"Goalie against seeded shots ({label})")
    ax.legend(loc="upper right", fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--shots", type=int, default=200)
    parser.add_argument("--quick", action="store_true", help="20 shots")
    parser.add_argument("--field", default="18x12", help="18x12, 22x14 or a world YAML")
    parser.add_argument("--label", default="goalie", help="names the output files goalie_<label>.{json,png}")
    parser.add_argument("--no-goalie", action="store_true", help="the same shots at an empty goal")
    parser.add_argument("--perception", choices=("truth", "vision"), default="truth",
                        help="the goalie's 3-D ball: the simulator's percept, or its RGB-D cameras and kinect_ball")
    args = parser.parse_args(argv)
    if args.shots < 1:
        parser.error(f"--shots must be at least 1, got {args.shots}")
    n = 20 if args.quick else args.shots
    world = load_world(args.field)
    shots = seeded_shots(n, args.seed, world)
    start = time.perf_counter()
    played: list[Shot] = []
    for i, shot in enumerate(shots):
        played.append(play_shot(i, shot, world, args.seed, goalie=not args.no_goalie,
                                vision=args.perception == "vision"))
        if (i + 1) % 20 == 0 or i + 1 == n:
            lobs = [s for s in played if s.kind == "lob"]
            print(f"  {i + 1}/{n} shots, {sum(s.saved for s in lobs)}/{len(lobs)} lobs and "
                  f"{sum(s.saved for s in played) - sum(s.saved for s in lobs)}/{len(played) - len(lobs)} ground "
                  f"shots saved, {time.perf_counter() - start:.0f} s", flush=True)
    summary = summarise(played)
    results = {"label": args.label, "seed": args.seed, "field": world.name, "goalie": not args.no_goalie,
               "perception": args.perception,
               "machine": machine(None), "wall_seconds": round(time.perf_counter() - start, 1), "figures": summary,
               "target": {"lob_save_rate": 0.6, "met": summary["lob"]["save_rate"] >= 0.6},
               "shots": [asdict(s) for s in played]}
    args.out.mkdir(parents=True, exist_ok=True)
    name = f"goalie_{args.label}"
    (args.out / f"{name}.json").write_text(strict_json(results, indent=2))
    plot(summary, args.label, args.out / f"{name}.png")
    for kind in ("lob", "ground"):
        s = summary[kind]
        print(f"{kind}: {s['saved']}/{s['shots']} saved ({s['save_rate']:.0%}, 95 % CI "
              f"{s['ci95'][0]:.0%}-{s['ci95'][1]:.0%})")
    print(f"figures: {args.out / (name + '.json')}, {args.out / (name + '.png')}")
    return 0
