"""Benchmark the lockstep engine: match speed, physics alone, the Gymnasium environment, memory, scaling, recording.

    python scripts/bench_lockstep.py --out bench/results [--quick] [--only lockstep,physics,...] [--cpu N]

Requires: the shipped teams (``nubot_control/config/teams/nubot.yaml`` and ``rival.yaml``), pyode, gymnasium,
matplotlib; no ROS. Provides, in ``--out``: ``lockstep.json`` (the machine, the targets and every part's
figures) and ``lockstep.png`` (simulated seconds per wall second per scenario, log scale, the 50x target
line); a table on stdout. Parts (``--only``, comma-separated; default all):

- ``lockstep``: a 5 vs 5 match with full team software in this process, pinned to one core
  (``--cpu``), per tracker (mpc, baseline): sim seconds per wall second over ``measure`` s of sim time
  after a ``warmup`` [s]; agent cycles per second and the time in ``RobotAgent.step`` per cycle [us], in
  ``Simulator.step`` per physics step [us] (of it in ``PhysicsWorld.step``, the ODE part), in sensing
  and the world models' vision updates and other inputs (3-D ball, teammates, coach); the rest is the engine
  (schedule, relay, referee). What the target leaves the robots: the speed if their software (cycles and
  inputs) cost nothing, and the time an agent cycle may take at the target beside everything else as
  measured (negative: the rest alone is too slow); the plot marks the first on each lockstep bar; how often ODE's
  solver reported "LCP internal error" in the match (``PhysicsWorld.solver_errors``; so does the ``evaluate`` part,
  over its matches). Target: 50x real time.
- ``physics``: a ``Simulator`` with the 10 robots (the match's start poses) and the ball, robots driven
  to places on a ring of radius ``RING`` about a point wandering near the centre spot, with varying
  velocity commands at 33 Hz (so neighbours jostle and push the ball): physics steps per second on one
  core (target 20,000); and pyode alone (``ode.World`` + ``ode.HashSpace``, 10 cylinders, a sphere, the
  ground plane, contact joints from ``space.collide``, the same exact solver) driven alike, for
  comparison (the reference saw 60,000-70,000 steps/s on this machine). Both again with every robot
  heading for the one point (``*_scrum``): contacts cost most of a step.
- ``env``: ``gymnasium.make("NuBot/ScoreAgainstGoalie-v0")`` with random actions: steps per second.
- ``memory``: the peak RSS (``ru_maxrss``) of a fresh process after its imports and after playing one full
  2 x 15 min lockstep 5 vs 5 match and its report (``nubot_match.evaluate.play_match``; target 150 MiB), and
  its RSS every 5 s of wall time while it played (target: flat after the first minute).
- ``evaluate``: ``nubot_match.evaluate.main`` with ``--jobs 1`` and then ``--jobs 2`` on the same
  matches: simulated seconds per wall second each and their ratio (target >= 1.8).
- ``recording``: the lockstep match (mpc) with ``BagRecorder(robots=False)`` and ``robots=True``.

Every figure is wall-clock and falls on a loaded machine: the JSON keeps the load average at the start
and end and, per pinned measurement, the share of the core the process got (``cpu_share``) and the
speed per CPU second, which the load lowers less.
"""

from __future__ import annotations

import argparse
import io
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import threading
import time
from collections.abc import Sequence
from contextlib import redirect_stderr, redirect_stdout
from dataclasses import asdict, dataclass
from pathlib import Path
from typing import Any

import gymnasium
import matplotlib.pyplot as plt
import ode
import psutil

import nubot_match.envs  # noqa: F401 - registers NuBot/ScoreAgainstGoalie-v0
from nubot_common.json_text import strict_json
from nubot_match import evaluate
from nubot_match.bag import BagRecorder
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_match.evaluate import jobs_for, play_match
from nubot_match.record import MatchListener
from nubot_tools.bench.harness import Clock, cpu_pressure, machine, pinned, timed
from nubot_tools.workspace import BENCH_RESULTS, TEAMS
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.simulator import Simulator

PARTS = ("lockstep", "recording", "physics", "env", "memory", "evaluate")
TRACKERS = ("mpc", "baseline")
HOME, AWAY = TEAMS / "nubot.yaml", TEAMS / "rival.yaml"
TARGET_REAL_TIME_FACTOR = 50.0  # sim seconds per wall second of a lockstep 5 vs 5 match on one core
TARGET_PHYSICS_STEPS = 20_000.0  # physics steps per second of the Simulator with 10 robots, one core
TARGET_EVALUATE_SPEEDUP = 1.8  # throughput of --jobs 2 over --jobs 1
PYODE_REFERENCE = (60_000.0, 70_000.0)  # steps/s the reference measured for pyode alone on this machine
RING = 1.0  # [m] radius of the robots' ring in the physics benchmarks (0: all in one scrum)
COMMAND_PERIOD = 1.0 / 33.0  # [s] velocity commands in the physics benchmarks, as the control nodes send them
@dataclass(frozen=True)
class Durations:
    """How long each part runs."""

    warmup: float  # [s of sim time] played before a lockstep measurement
    measure: float  # [s of sim time] measured
    physics_steps: int  # Simulator steps measured
    pyode_steps: int  # pyode steps measured
    env_steps: int  # environment steps measured
    memory_half: float  # [s] half length of the match played by the memory process
    memory_halves: int
    evaluate_matches: int
    evaluate_half: float  # [s]
    evaluate_halves: int


TARGET_PHYSICS_OVER_ODE = 1.3  # the simulator's step inside a match against the physics world's own step
TARGET_MEMORY_MIB = 150.0  # one full match's process, its report included

FULL = Durations(5.0, 60.0, 30_000, 60_000, 2_000, 900.0, 2, 8, 15.0, 2)  # memory: a full 2 x 15 min
QUICK = Durations(2.0, 10.0, 3_000, 10_000, 200, 5.0, 1, 2, 5.0, 1)


def _r(x: float, digits: int = 2) -> float:
    return round(float(x), digits)


def _us(seconds: float, calls: int) -> float | None:
    return _r(1e6 * seconds / calls, 1) if calls else None


# --- 1 and 6: the lockstep match ---------------------------------------------------------------------------------
def lockstep_case(tracker: str, d: Durations, cpu: int | None, listeners: Sequence[MatchListener] = (),
                  seed: int = 0) -> dict:
    """Play a 5 vs 5 lockstep match for ``d.warmup`` + ``d.measure`` s of sim time and time the measured part."""
    config = match_config(HOME, AWAY, "18x12", tracker, half_seconds=300.0, halves=2, seed=seed)
    match = LockstepMatch(config, listeners)
    match.reset(seed)
    sim = match.sim
    assert sim is not None
    physics = timed(sim, "step")
    sensing = timed(sim, "observe_all")  # every robot's vision frame at once
    cycles = [timed(agent, "step") for agent in match.agents.values()]
    vision = [timed(agent, "on_vision") for agent in match.agents.values()]
    # The robots' other inputs: the 3-D ball, what teammates share and the coach's commands.
    inputs = [timed(agent, method) for agent in match.agents.values()
              for method in ("on_ball3d", "on_teammate", "on_teammate_strategy", "on_coach")]
    clock = Clock()
    with pinned(cpu):
        match.run(until=d.warmup)
        for timer in (physics, sensing, *cycles, *vision, *inputs):
            timer.clear()
        start, ode_start = match.time, sim.world.step_seconds
        with clock.measure():
            match.run(until=d.warmup + d.measure)
        simulated = match.time - start
        ode_seconds = sim.world.step_seconds - ode_start  # ODE's own part of the steps, timed by the compiled world
    match.close()
    agent_calls, agent_seconds = sum(t.calls for t in cycles), sum(t.seconds for t in cycles)
    vision_calls, vision_seconds = sum(t.calls for t in vision), sum(t.seconds for t in vision)
    input_seconds = sum(t.seconds for t in inputs)
    robots = agent_seconds + vision_seconds + input_seconds  # the robots' software, all of it
    engine = clock.wall - physics.seconds - sensing.seconds - robots
    rest = clock.wall - robots  # the simulator, sensing, referee, relay and engine
    return {
        "tracker": tracker, "robots": len(match.agents), "seed": seed, "warmup_sim_seconds": d.warmup,
        "sim_seconds": _r(simulated, 3), "wall_seconds": _r(clock.wall, 3), "cpu_seconds": _r(clock.cpu, 3),
        "cpu_share": _r(clock.cpu_share, 3),
        "sim_seconds_per_wall_second": _r(simulated / clock.wall),
        "sim_seconds_per_cpu_second": _r(simulated / clock.cpu) if clock.cpu > 0 else None,
        "agent_cycles": agent_calls, "agent_cycles_per_second": _r(agent_calls / clock.wall, 1),
        "us_per_agent_cycle": _us(agent_seconds, agent_calls),
        "physics_steps": physics.calls, "physics_steps_per_second": _r(physics.calls / clock.wall, 1),
        "us_per_physics_step": _us(physics.seconds, physics.calls),
        "us_per_physics_step_ode": _us(ode_seconds, physics.calls),
        "physics_step_over_ode_part": _r(physics.seconds / ode_seconds) if ode_seconds > 0 else None,
        "solver_errors": sim.world.solver_errors,  # ODE's "LCP internal error"s in the whole match played
        "target_physics_step_over_ode_part": TARGET_PHYSICS_OVER_ODE,
        # The machine's speed drifts between runs (up to 40 % here); this ratio of two times of one run does not.
        "agent_cycle_in_physics_steps": _r(agent_seconds / agent_calls / (physics.seconds / physics.calls))
        if agent_calls and physics.calls and physics.seconds > 0 else None,
        "us_per_vision_frame_sensing": _us(sensing.seconds, sensing.calls * len(match.agents)),
        "us_per_vision_frame_world_model": _us(vision_seconds, vision_calls),
        "wall_share": {"agents": _r(agent_seconds / clock.wall, 3), "physics": _r(physics.seconds / clock.wall, 3),
                       "sensing": _r(sensing.seconds / clock.wall, 3),
                       "world_model_vision": _r(vision_seconds / clock.wall, 3),
                       "world_model_other_inputs": _r(input_seconds / clock.wall, 3),
                       "engine_referee_relay_listeners": _r(engine / clock.wall, 3)},
        "target_sim_seconds_per_wall_second": TARGET_REAL_TIME_FACTOR,
        # What the target leaves the robots' software (its cycles and all its inputs): the speed if it cost
        # nothing, and the time one agent cycle may take at the target beside the rest as measured (negative: the
        # simulator, sensing, referee and engine alone are slower than the target).
        "sim_seconds_per_wall_second_without_agents": _r(simulated / rest) if rest > 0 else None,
        "us_per_agent_cycle_budget_at_target": _r(1e6 * (simulated / TARGET_REAL_TIME_FACTOR - rest) / agent_calls, 1)
        if agent_calls else None,
    }


def bench_lockstep(d: Durations, cpu: int | None) -> dict:
    return {tracker: lockstep_case(tracker, d, cpu) for tracker in TRACKERS}


def bench_recording(d: Durations, cpu: int | None, unrecorded: dict | None) -> dict:
    out: dict[str, Any] = {"tracker": "mpc"}
    with tempfile.TemporaryDirectory(prefix="bench_lockstep_bag_") as folder:
        for robots in (False, True):
            bag = Path(folder) / f"robots_{robots}.bag"
            case = lockstep_case("mpc", d, cpu, [BagRecorder(bag, robots=robots)])
            size = bag.stat().st_size / 2**20
            case.update({"bag_robots_topics": robots, "bag_mib": _r(size, 2),
                         "bag_mib_per_sim_minute": _r(60.0 * size / (d.warmup + d.measure), 2)})
            if unrecorded:
                case["relative_to_unrecorded"] = _r(case["sim_seconds_per_wall_second"]
                                                    / unrecorded["sim_seconds_per_wall_second"], 3)
            out["robots" if robots else "no_robots"] = case
    return out


# --- 2: physics alone ------------------------------------------------------------------------------------------
def start_poses() -> list[tuple[str, float, float, float, int]]:
    """The match's start poses in the world frame: (name, x [m], y [m], heading [rad], attack)."""
    config = match_config(HOME, AWAY)
    return [(name, x, y, yaw, t.config.attack) for t in config.teams for name, x, y, yaw in t.config.world_poses()]


def meeting_point(i: int, count: int, t: float, ring: float) -> tuple[float, float]:
    """Where robot ``i`` of ``count`` heads at sim time ``t`` [s]: its place on a ring of radius ``ring`` [m]
    about a point wandering near the centre spot, so that neighbours jostle and push the ball (which starts
    there); with ``ring`` 0 all of them head for that point (a scrum)."""
    a = 2 * math.pi * i / count
    return 1.5 * math.cos(0.2 * t) + ring * math.cos(a), math.sin(0.3 * t) + ring * math.sin(a)


def chase_command(i: int, t: float, x: float, y: float, theta: float,
                  goal: tuple[float, float]) -> tuple[float, float, float]:
    """A body-frame velocity (vx, vy [m/s], w [rad/s]) towards ``goal``, its speed and turn varying in time."""
    dx, dy = goal[0] - x, goal[1] - y
    norm = math.hypot(dx, dy) or 1.0
    speed = 1.5 + 1.0 * math.sin(0.7 * t + i)
    wx, wy = speed * dx / norm + 0.5 * math.cos(0.4 * t + 2 * i), speed * dy / norm
    c, s = math.cos(theta), math.sin(theta)
    return c * wx + s * wy, -s * wx + c * wy, 1.0 * math.sin(0.3 * t + i)


def robot_contacts(positions: Sequence[tuple[float, float]], distance: float) -> int:
    """How many robot pairs have their centres closer than ``distance`` [m]."""
    return sum(1 for i, a in enumerate(positions) for b in positions[i + 1:]
               if math.hypot(a[0] - b[0], a[1] - b[1]) < distance)


def bench_simulator(steps: int, cpu: int | None, ring: float) -> dict:
    spawns = tuple(RobotSpawn(name, x, y, yaw, attack) for name, x, y, yaw, attack in start_poses())
    sim = Simulator(SimConfig(robots=spawns, ball_start=(0.0, 0.0)))
    names = list(sim.plugins)
    contact = 2 * sim.config.robot.radius + 0.03
    next_command, samples, touching, pairs, stepping = 0.0, 0, 0, 0, 0.0
    clock, warmup = Clock(), 200
    with pinned(cpu), clock.measure():
        for k in range(warmup + steps):
            if sim.time + 1e-9 >= next_command:
                for i, name in enumerate(names):
                    s = sim.world.robot_state(name)
                    goal = meeting_point(i, len(names), sim.time, ring)
                    sim.command_velocity(name, *chase_command(i, sim.time, s.x, s.y, s.theta, goal))
                next_command += COMMAND_PERIOD
            if k >= warmup and k % 20 == 0:
                n = robot_contacts([(s.x, s.y) for s in map(sim.world.robot_state, names)], contact)
                samples, touching, pairs = samples + 1, touching + (n > 0), pairs + n
            start = time.perf_counter()
            sim.step()
            if k >= warmup:
                stepping += time.perf_counter() - start
    dt = sim.config.physics.step_size
    return {"robots": len(names), "ring_m": ring, "steps": steps, "step_size_s": dt,
            "wall_seconds_in_step": _r(stepping, 3),
            "cpu_share": _r(clock.cpu_share, 3), "steps_per_second": _r(steps / stepping, 1),
            "us_per_step": _r(1e6 * stepping / steps, 1),
            "sim_seconds_per_wall_second": _r(steps * dt / stepping),
            "samples_with_robot_contact_share": _r(touching / samples, 3) if samples else None,
            "robot_pairs_in_contact_mean": _r(pairs / samples, 3) if samples else None,
            "target_steps_per_second": TARGET_PHYSICS_STEPS}


def bench_pyode(steps: int, cpu: int | None, ring: float) -> dict:
    """pyode alone, robots gliding above the ground (no gravity, no robot-ground contact) and kept upright in
    their plane (``Plane2DJoint``) as ``PhysicsWorld`` keeps them."""
    world = ode.World()
    world.setGravity((0.0, 0.0, -9.81))
    world.setERP(0.2)
    world.setCFM(1e-5)
    space, joints = ode.HashSpace(), ode.JointGroup()
    ground = ode.GeomPlane(space, (0.0, 0.0, 1.0), 0.0)
    radius, height, ball_radius = 0.26, 0.75, 0.11
    robots, geoms = [], []  # pyode destroys a geom or joint nobody refers to: the space does not hold it
    for _name, x, y, _yaw, _attack in start_poses():
        body, mass = ode.Body(world), ode.Mass()
        mass.setCylinderTotal(31.0, 3, radius, height)
        body.setMass(mass)
        body.setGravityMode(False)
        geom = ode.GeomCylinder(space, radius, height)
        geom.setBody(body)
        body.setPosition((x, y, height / 2 + 0.01))
        plane = ode.Plane2DJoint(world)  # in C what PhysicsWorld.drive_robot does in Python: no tilt, no lift
        plane.attach(body, ode.environment)
        robots.append(body)
        geoms.append((geom, plane))
    ball, mass = ode.Body(world), ode.Mass()
    mass.setSphereTotal(0.45, ball_radius)
    ball.setMass(mass)
    ball_geom = ode.GeomSphere(space, ball_radius)
    ball_geom.setBody(ball)
    ball.setPosition((0.0, 0.0, ball_radius))
    contacts = [0]

    def near(_args: object, a: ode.GeomObject, b: ode.GeomObject) -> None:
        if ground in (a, b) and ball_geom not in (a, b):
            return  # as PhysicsWorld: robots glide above the carpet
        for contact in ode.collide(a, b):
            contact.setMu(0.5)
            ode.ContactJoint(world, joints, contact).attach(a.getBody(), b.getBody())
            contacts[0] += 1

    dt, clock, t = 0.005, Clock(), 0.0
    commands = [(0.0, 0.0, 0.0)] * len(robots)

    def advance(count: int) -> None:
        nonlocal commands, t
        for k in range(count):
            if k % 7 == 0:  # 33 Hz commands at a 5 ms step
                where = [body.getPosition() for body in robots]
                commands = [chase_command(i, t, p[0], p[1], 0.0, meeting_point(i, len(robots), t, ring))
                            for i, p in enumerate(where)]
            for body, (vx, vy, w) in zip(robots, commands):
                body.setLinearVel((vx, vy, 0.0))
                body.setAngularVel((0.0, 0.0, w))
            space.collide(None, near)
            world.step(dt)
            joints.empty()
            t += dt

    with pinned(cpu):
        advance(500)
        contacts[0] = 0
        with clock.measure():
            advance(steps)
    return {"bodies": len(robots) + 1, "ring_m": ring, "steps": steps,
            "wall_seconds": _r(clock.wall, 3),
            "cpu_share": _r(clock.cpu_share, 3), "steps_per_second": _r(steps / clock.wall, 1),
            "steps_per_cpu_second": _r(steps / clock.cpu, 1) if clock.cpu > 0 else None,
            "contacts_per_step": _r(contacts[0] / steps, 2),
            "reference_steps_per_second": list(PYODE_REFERENCE)}


# --- 3: the environment ----------------------------------------------------------------------------------------
def bench_env(steps: int, cpu: int | None) -> dict:
    made = time.perf_counter()
    env = gymnasium.make("NuBot/ScoreAgainstGoalie-v0")
    made = time.perf_counter() - made
    env.action_space.seed(0)
    clock, episodes, simulated = Clock(), 1, 0.0
    with pinned(cpu):
        _obs, info = env.reset(seed=0)
        last = float(info.get("time", 0.0))
        with clock.measure():
            for _ in range(steps):
                _obs, _reward, terminated, truncated, info = env.step(env.action_space.sample())
                simulated += float(info.get("time", last)) - last
                last = float(info.get("time", last))
                if terminated or truncated:
                    _obs, info = env.reset()
                    last = float(info.get("time", 0.0))
                    episodes += 1
    env.close()
    return {"id": "NuBot/ScoreAgainstGoalie-v0", "steps": steps, "episodes": episodes,
            "make_seconds": _r(made, 3), "wall_seconds": _r(clock.wall, 3), "cpu_share": _r(clock.cpu_share, 3),
            "steps_per_second": _r(steps / clock.wall, 1),
            "sim_seconds_per_wall_second": _r(simulated / clock.wall) if simulated > 0 else None,
            "note": "resets included in the time"}


# --- 4: memory ------------------------------------------------------------------------------------------------
def _rss_mib() -> float:
    return psutil.Process().memory_info().rss / 2**20


def match_process_figures(half_seconds: float, halves: int) -> None:
    """In a fresh process: print as JSON the peak RSS after the imports and after playing one match (and its report),
    and the RSS every 5 s of wall time while it played, to show whether it grows with the match."""
    imports_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    samples: list[tuple[float, float]] = []
    done = threading.Event()
    start = time.perf_counter()

    def sample() -> None:
        while not done.wait(5.0):
            samples.append((time.perf_counter() - start, _rss_mib()))

    sampler = threading.Thread(target=sample, daemon=True)
    sampler.start()
    result = play_match(jobs_for(str(HOME), str(AWAY), 1, half_seconds, halves)[0])
    done.set()
    sampler.join()
    peak_kib = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
    playing = [(t, m) for t, m in samples if t <= result.wall_seconds]  # the match itself, before its report
    after_minute = [m for t, m in playing if t >= 60.0]
    print(json.dumps({"rss_mib_after_imports": _r(imports_kib / 1024, 1), "rss_mib_peak": _r(peak_kib / 1024, 1),
                      "rss_mib_playing_after_first_minute": [_r(min(after_minute), 1), _r(max(after_minute), 1)]
                      if after_minute else None,
                      "rss_mib_samples": [[_r(t, 0), _r(m, 1)] for t, m in samples],
                      "sim_seconds": result.sim_seconds, "wall_seconds": result.wall_seconds}))


def bench_memory(d: Durations, cpu: int | None) -> dict:
    code = (f"from nubot_tools.bench.lockstep import match_process_figures; "
            f"match_process_figures({d.memory_half!r}, {d.memory_halves!r})")
    with pinned(cpu):  # the child inherits the affinity
        done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=False)
    if done.returncode != 0:
        raise RuntimeError(f"the match process failed ({done.returncode}):\n{done.stderr[-3000:]}")
    figures = json.loads(done.stdout.strip().splitlines()[-1])
    return {"match": f"{d.memory_halves} x {d.memory_half:g} s, 5 vs 5, as make evaluate plays it", **figures,
            "rss_mib_match": _r(figures["rss_mib_peak"] - figures["rss_mib_after_imports"], 1)}


# --- 5: make evaluate scaling ------------------------------------------------------------------------------------
def bench_evaluate(d: Durations) -> dict:
    runs: dict[str, Any] = {}
    with tempfile.TemporaryDirectory(prefix="bench_lockstep_eval_") as folder:
        for jobs in (1, 2):
            out = Path(folder) / f"jobs{jobs}"
            log = io.StringIO()  # its table, verdict and progress bar: not this benchmark's output
            start = time.perf_counter()
            with redirect_stdout(log), redirect_stderr(log):
                status = evaluate.main(["--matches", str(d.evaluate_matches), "--half-seconds",
                                        str(d.evaluate_half), "--halves", str(d.evaluate_halves), "--jobs", str(jobs),
                                        "--out", str(out)])
            wall = time.perf_counter() - start
            if status != 0:
                print(f"[bench] evaluate --jobs {jobs} ended with status {status}:\n{log.getvalue()[-3000:]}",
                      file=sys.stderr, flush=True)
            data = json.loads((out / "results.json").read_text())
            sim = sum(m["sim_seconds"] for m in data["matches"])
            runs[f"jobs{jobs}"] = {"jobs": jobs, "status": status, "matches": data["finished"],
                                   "sim_seconds": _r(sim, 1), "wall_seconds": _r(wall, 2),
                                   "sim_seconds_per_wall_second": _r(sim / wall),
                                   "reported_sim_seconds_per_wall_second":
                                       data["throughput"]["sim_seconds_per_wall_second"],
                                   "match_wall_seconds_mean": _r(sum(m["wall_seconds"] for m in data["matches"])
                                                                 / max(len(data["matches"]), 1)),
                                   "rss_mib_max": data["throughput"]["rss_mib_max"],
                                   "solver_errors": data["solver_errors"]}
    one, two = runs["jobs1"]["sim_seconds_per_wall_second"], runs["jobs2"]["sim_seconds_per_wall_second"]
    return {"matches": d.evaluate_matches, "match": f"{d.evaluate_halves} x {d.evaluate_half:g} s", **runs,
            "speedup_jobs2_over_jobs1": _r(two / one, 3) if one > 0 else None,
            "target_speedup": TARGET_EVALUATE_SPEEDUP,
            "note": "wall time includes forking the workers and the analysis of each match; a match_wall_seconds_mean "
                    "higher with --jobs 2 than with --jobs 1 means the workers did not get a core each (load)"}


# --- the machine, the plot, the table -----------------------------------------------------------------------------
def scenarios(results: dict) -> list[tuple[str, float]]:
    """(label, sim seconds per wall second) of every measured scenario, for the plot and the table."""
    rows: list[tuple[str, float]] = []
    for tracker, case in results.get("lockstep", {}).items():
        rows.append((f"lockstep 5v5\n{tracker}", case["sim_seconds_per_wall_second"]))
    recording = results.get("recording", {})
    for key, label in (("no_robots", "bag, no robot\ntopics (mpc)"), ("robots", "bag, robot\ntopics (mpc)")):
        if key in recording:
            rows.append((label, recording[key]["sim_seconds_per_wall_second"]))
    for key in ("jobs1", "jobs2"):
        if key in results.get("evaluate", {}):
            rows.append((f"evaluate\n--jobs {key[-1]}", results["evaluate"][key]["sim_seconds_per_wall_second"]))
    env = results.get("env", {}).get("sim_seconds_per_wall_second")
    if env:
        rows.append(("gym env\n1 learner", env))
    physics = results.get("physics", {}).get("simulator")
    if physics:
        rows.append(("physics alone\n10 robots", physics["sim_seconds_per_wall_second"]))
    return rows


def plot(results: dict, path: Path) -> None:
    rows = scenarios(results)
    fig, ax = plt.subplots(figsize=(max(6.0, 1.3 * len(rows) + 2), 4.5))
    colours = ["tab:green" if v >= TARGET_REAL_TIME_FACTOR else "tab:blue" for _, v in rows]
    bars = ax.bar([label for label, _ in rows], [v for _, v in rows], color=colours)
    for bar, (_, value) in zip(bars, rows):
        ax.annotate(f"{value:.1f}x", (bar.get_x() + bar.get_width() / 2, value), ha="center", va="bottom",
                    fontsize=8)
    ax.axhline(TARGET_REAL_TIME_FACTOR, color="tab:red", ls="--", label=f"target {TARGET_REAL_TIME_FACTOR:.0f}x")
    ceilings = [(bar, case["sim_seconds_per_wall_second_without_agents"])
                for bar, case in zip(bars, results.get("lockstep", {}).values())]  # the lockstep bars come first
    for i, (bar, ceiling) in enumerate(c for c in ceilings if c[1]):
        ax.hlines(ceiling, bar.get_x(), bar.get_x() + bar.get_width(), colors="black", linestyles=":",
                  label="lockstep if the robots' software cost nothing" if i == 0 else None)
        ax.annotate(f"{ceiling:.0f}x", (bar.get_x() + bar.get_width(), ceiling), ha="left", va="center", fontsize=7)
    ax.set_yscale("log")
    values = [v for _, v in rows if v > 0] + [c for _, c in ceilings if c] or [1.0]
    ax.set_ylim(0.5 * min(*values, 1.0), 2.0 * max(*values, TARGET_REAL_TIME_FACTOR))
    ax.set_ylabel("simulated seconds per wall second")
    load = results["machine"]["load_average_start"][0]
    ax.set_title(f"Lockstep engine ({results['machine']['cpus']} CPUs, load {load:.1f} at start)")
    ax.tick_params(axis="x", labelsize=8)
    ax.legend(loc="upper left")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def table(results: dict) -> str:
    lines = [f"{'scenario':<34}{'sim s / wall s':>16}"]
    lines += [f"{label.replace(chr(10), ' '):<34}{value:>16.2f}" for label, value in scenarios(results)]
    for tracker, case in results.get("lockstep", {}).items():
        lines.append(f"lockstep {tracker}: {case['agent_cycles_per_second']:.0f} agent cycles/s, "
                     f"{case['us_per_agent_cycle']} us/agent cycle, {case['us_per_physics_step']} us/physics step "
                     f"(an agent cycle costs {case['agent_cycle_in_physics_steps']} physics steps), "
                     f"cpu share {case['cpu_share']}")
        lines.append(f"  a physics step is {case['physics_step_over_ode_part']} x its ODE part "
                     f"({case['us_per_physics_step_ode']} us; target {TARGET_PHYSICS_OVER_ODE}); ODE's solver reported "
                     f"'LCP internal error' {case['solver_errors']} times")
        lines.append(f"  with robots that cost nothing {case['sim_seconds_per_wall_second_without_agents']}x; at "
                     f"{TARGET_REAL_TIME_FACTOR:.0f}x the rest leaves {case['us_per_agent_cycle_budget_at_target']} "
                     f"us per agent cycle")
    physics = results.get("physics", {})
    if physics:
        lines.append(f"physics: Simulator {physics['simulator']['steps_per_second']:.0f} steps/s (target "
                     f"{TARGET_PHYSICS_STEPS:.0f}), pyode alone {physics['pyode']['steps_per_second']:.0f} "
                     f"steps/s; in a scrum {physics['simulator_scrum']['steps_per_second']:.0f} and "
                     f"{physics['pyode_scrum']['steps_per_second']:.0f}")
    if "env" in results:
        lines.append(f"env: {results['env']['steps_per_second']:.0f} steps/s")
    if "memory" in results:
        memory = results["memory"]
        lines.append(f"memory: peak RSS {memory['rss_mib_peak']} MiB per match process (target "
                     f"{TARGET_MEMORY_MIB:.0f}); while playing, after the first minute: "
                     f"{memory['rss_mib_playing_after_first_minute']} MiB")
    if "evaluate" in results:
        evaluate = results["evaluate"]
        lines.append(f"evaluate: --jobs 2 / --jobs 1 = {evaluate['speedup_jobs2_over_jobs1']} "
                     f"(target {TARGET_EVALUATE_SPEEDUP}); 'LCP internal error' in its matches: "
                     f"{evaluate['jobs1']['solver_errors']} and {evaluate['jobs2']['solver_errors']}")
    return "\n".join(lines)


def parse_parts(text: str) -> list[str]:
    parts = [p.strip() for p in text.split(",") if p.strip()]
    unknown = sorted(set(parts) - set(PARTS))
    if unknown or not parts:
        raise argparse.ArgumentTypeError(f"parts are {', '.join(PARTS)}; got {text!r}")
    return parts


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--quick", action="store_true", help="a short smoke run (10 s of sim time per match)")
    parser.add_argument("--only", type=parse_parts, default=list(PARTS), help=f"comma-separated: {','.join(PARTS)}")
    parser.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                        help="the core one-core measurements are pinned to (-1: no pinning)")
    args = parser.parse_args(argv)
    cpu = None if args.cpu < 0 else args.cpu
    d = QUICK if args.quick else FULL
    args.out.mkdir(parents=True, exist_ok=True)
    results: dict[str, Any] = {"machine": machine(cpu), "quick": args.quick, "parts": args.only,
                               "durations": asdict(d), "teams": [str(HOME), str(AWAY)],
                               "targets": {"lockstep_sim_seconds_per_wall_second": TARGET_REAL_TIME_FACTOR,
                                           "physics_steps_per_second": TARGET_PHYSICS_STEPS,
                                           "evaluate_speedup_jobs2_over_jobs1": TARGET_EVALUATE_SPEEDUP,
                                           "pyode_reference_steps_per_second": list(PYODE_REFERENCE)}}
    started = time.perf_counter()
    for part in (p for p in PARTS if p in args.only):
        print(f"[bench] lockstep: {part} ...", flush=True)
        if part == "lockstep":
            results["lockstep"] = bench_lockstep(d, cpu)
        elif part == "recording":
            results["recording"] = bench_recording(d, cpu, results.get("lockstep", {}).get("mpc"))
        elif part == "physics":
            results["physics"] = {"simulator": bench_simulator(d.physics_steps, cpu, RING),
                                  "pyode": bench_pyode(d.pyode_steps, cpu, RING),
                                  "simulator_scrum": bench_simulator(d.physics_steps, cpu, 0.0),
                                  "pyode_scrum": bench_pyode(d.pyode_steps, cpu, 0.0)}
        elif part == "env":
            results["env"] = bench_env(d.env_steps, cpu)
        elif part == "memory":
            results["memory"] = bench_memory(d, cpu)
        elif part == "evaluate":
            results["evaluate"] = bench_evaluate(d)
    results["machine"]["load_average_end"] = [_r(x) for x in os.getloadavg()]
    results["machine"]["cpu_pressure_some_avg60_percent_end"] = cpu_pressure()
    results["wall_seconds_total"] = _r(time.perf_counter() - started, 1)
    (args.out / "lockstep.json").write_text(strict_json(results, indent=2))
    plot(results, args.out / "lockstep.png")
    print(table(results))
    print(f"figures: {args.out / 'lockstep.json'}, {args.out / 'lockstep.png'}")
    return 0
