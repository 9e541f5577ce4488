"""Benchmark kinect_ball in one process without ROS: time per frame pair, touchdown prediction of seeded lobs.

    python scripts/bench_kinect_ball.py --out bench/results [--seed 0] [--lobs 200] [--quick] [--cpu N]

Requires: the world (``--field``), kinect_ball's ``config/kinect_ball.yaml``, sim_visual's ``Simulator`` (ODE at
0.005 s, the goalie's two simulated RGB-D cameras), sensor_msgs (the clouds go through real PointCloud2 messages,
as between the simulator node and kinect_ball), matplotlib; pyransac3d optionally (the sphere fit comparison).
Each lob: the goalie ``nubot1`` (attacking +x, so its team frame is the world frame) stands 0.4-0.8 m in front
of its goal line facing the field; ``rival1`` holds the ball 4-9 m from that goal line (seeded), turns to a seeded
point of the goal mouth and lob-shoots through the ``Shoot`` interface (``ShootPos`` 1, the simulator's
``lob_velocity``). Every 1/30 s of sim time both clouds are rendered, packed into PointCloud2, read back and
processed by ``KinectBall`` with the goalie's true pose. The true touchdown is where the simulated ball comes down
to z = radius: ``ball_flight.landing`` of its last free-flight state (ODE's, before its first contact; in free flight
ODE changes only vz, by gravity per step); a lob that meets a robot, a post or a net earlier than 0.3 s before its
touchdown is counted apart (disturbed), not measured. ODE's integration drifts from the exact parabola by about
g * step * t / 2 (``integration_drift_m``: the kick's exact touchdown against the simulated one).

Provides, in ``--out``: ``kinect_ball.json`` (the machine, the figures with their targets and ``met``) and
``kinect_ball.png`` (touchdown error against time to touchdown: median and p90 over the lobs; time per frame).
Figures:

1. ``frame_time_ms``: per frame pair (both cameras), reading both PointCloud2 and ``KinectBall.process``, pinned
   to one core: median and p95; target median <= 10 ms. The rendering (simulator side) apart.
2. ``touchdown_error_at_0_3s_m``: the error of the touchdown prediction the goalie holds 0.3 s before the ball lands
   (the latest one made by then), over the undisturbed lobs: median, p90, p95, max; target median <= 0.10 m; the
   share of lobs with a prediction by then and how long before touchdown that prediction was made.
3. ``sphere_fit``: the vectorised numpy RANSAC against pyransac3d's ``Sphere`` (4-point, free radius) on the same
   ball point sets taken from the frames, with the same inlier band: time per fit and centre error. Open3D 0.16
   (Debian) offers RANSAC for planes only, so it is not compared.

Every figure but the times is deterministic for a seed.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from dataclasses import dataclass, field
from importlib.metadata import version
from pathlib import Path
from typing import Any

import genpy
import matplotlib.pyplot as plt
import numpy as np
from sensor_msgs.msg import PointCloud2, PointField

from kinect_ball.detection import fit_sphere
from kinect_ball.pipeline import KinectBall, KinectBallParams
from nubot_common.ball_flight import landing
from nubot_common.clouds import cloud_from_msg, cloud_msg
from nubot_common.geometry import Pose2D
from nubot_common.json_text import strict_json
from nubot_common.packages import package_path
from nubot_common.params import load_yaml
from nubot_common.world_description import load_world
from nubot_tools.bench.harness import machine, pinned
from nubot_tools.workspace import BENCH_RESULTS
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.rgbd_camera import BALL
from sim_visual.simulator import Simulator
from sim_visual.world import BallState

CONFIG = package_path("kinect_ball") / "config" / "kinect_ball.yaml"
GOALIE, SHOOTER = "nubot1", "rival1"
FRAME_PERIOD = 1.0 / 30.0  # [s] as the simulator node publishes the clouds
TIME_EPS = 1e-9
LEAD = 0.3  # [s] before touchdown: the figure's moment
TARGET_FRAME_MEDIAN_MS = 10.0
TARGET_ERROR_M = 0.10
DISTANCES = (4.0, 9.0)  # [m] the shooter's ball from the goal line
TAUS = np.round(np.arange(0.0, 1.21, 1.0 / 30.0), 4)  # [s] times to touchdown of the error curve
DEVIATION = 0.01  # [m] the ball this far off its kick's parabola has touched something


@dataclass
class LobRecord:
    distance: float  # [m]
    truth: tuple[float, float, float]  # touchdown x, y [m] and sim time [s]
    disturbed_at: float  # sim time the ball met something other than the ground (inf: never)
    analytic: tuple[float, float, float]  # the kick's drag-free touchdown (x, y, time), against ODE's integration
    predictions: list[tuple[float, float, float]] = field(default_factory=list)  # (frame time, x, y)
    sightings: list[float] = field(default_factory=list)  # frame times with the ball seen
    frame_ms: list[float] = field(default_factory=list)
    render_ms: list[float] = field(default_factory=list)
    ball_sets: list[tuple[np.ndarray, np.ndarray, float]] = field(default_factory=list)  # points, centre, dist


def _r(x: float | None, digits: int = 4) -> float | None:
    return None if x is None or not math.isfinite(x) else round(float(x), digits)


def summary(values: list[float], scale: float = 1.0, digits: int = 4) -> dict[str, Any]:
    if not values:
        return {"count": 0, "median": None, "p90": None, "p95": None, "max": None}
    a = np.asarray(values) * scale
    return {"count": len(a), "median": _r(float(np.median(a)), digits), "p90": _r(float(np.percentile(a, 90)), digits),
            "p95": _r(float(np.percentile(a, 95)), digits), "max": _r(float(a.max()), digits)}


def camera_frame_centre(centre_world: np.ndarray, goalie: Pose2D, mount: Any) -> np.ndarray:
    c, s = math.cos(goalie.theta), math.sin(goalie.theta)
    dx, dy = centre_world[0] - goalie.x, centre_world[1] - goalie.y
    body = np.array([c * dx + s * dy, -s * dx + c * dy, centre_world[2]])
    return mount.rotation().T @ (body - mount.offset)


def fly_lob(k: int, seed: int, world: Any, params: KinectBallParams, keep_sets: bool) -> LobRecord:
    """One seeded lob at the goalie; its frames through kinect_ball."""
    rng = np.random.default_rng([seed, k])
    f = world.field
    goalie = Pose2D(-f.half_length + rng.uniform(0.4, 0.8), rng.uniform(-0.4, 0.4), 0.0)
    distance = rng.uniform(*DISTANCES)
    target_y = rng.uniform(-0.8, 0.8) * (f.goal_width / 2.0 - world.ball.radius)
    ball_y = float(np.clip(target_y + rng.uniform(-2.5, 2.5), -f.half_width + 1.0, f.half_width - 1.0))
    ball_x = -f.half_length + distance
    heading = math.atan2(target_y - ball_y, -f.half_length - ball_x)
    hold = 0.43  # the plugin's hold distance: the shooter stands behind the ball
    shooter = (ball_x - hold * math.cos(heading), ball_y - hold * math.sin(heading))
    config = SimConfig(world=world, robots=(RobotSpawn(GOALIE, goalie.x, goalie.y, goalie.theta, 1),
                                            RobotSpawn(SHOOTER, shooter[0], shooter[1], heading, -1)),
                       ball_start=(ball_x, ball_y), seed=seed * 1000 + k)
    sim = Simulator(config)
    sim.set_model_state(world.ball_name, BallState(ball_x, ball_y, world.ball.radius, 0.0, 0.0, 0.0))
    if not sim.ball_handle(SHOOTER, 1):
        raise RuntimeError(f"lob {k}: the shooter does not hold the ball")
    done, kick = sim.shoot(SHOOTER, 0.0, 1)
    if not done or kick is None:
        raise RuntimeError(f"lob {k}: the lob was not kicked")
    gravity, dt = config.physics.gravity, config.physics.step_size
    analytic = landing(*kick.position, *kick.velocity, world.ball.radius, gravity)
    record = LobRecord(distance, (math.nan, math.nan, math.nan), math.inf,
                       analytic=(analytic.x, analytic.y, kick.time + analytic.t))
    core = KinectBall(params, world.ball.radius)
    next_frame = sim.time
    free = sim.world.ball_state()  # the last state of the free flight
    free_time, contact = sim.time, math.inf
    while sim.time < min(contact + 0.05, kick.time + 4.0):
        sim.step()
        b = sim.world.ball_state()
        if math.isinf(contact):
            # In free flight ODE changes only vz, by gravity * step: anything else is a contact.
            if max(abs(b.vx - free.vx), abs(b.vy - free.vy), abs(b.vz - free.vz - gravity * dt)) > 1e-6:
                contact = sim.time
            else:
                free, free_time = b, sim.time
        if sim.time < next_frame - TIME_EPS:
            continue
        next_frame += FRAME_PERIOD
        t0 = time.perf_counter()
        frames = sim.rgbd_frames(GOALIE)
        t1 = time.perf_counter()
        stamp = genpy.Time.from_sec(sim.time)
        msgs = [cloud_msg(fr.points, fr.rgb, PointCloud2, PointField, stamp, fr.camera) for fr in frames]
        t2 = time.perf_counter()
        clouds = {fr.camera: cloud_from_msg(m) for fr, m in zip(frames, msgs)}
        result = core.process(sim.time, goalie, clouds)
        t3 = time.perf_counter()
        record.render_ms.append((t1 - t0) * 1e3)
        record.frame_ms.append((t3 - t2) * 1e3)
        if result.percept is not None:
            record.sightings.append(sim.time)
        if result.touchdown is not None:
            record.predictions.append((sim.time, result.touchdown.x, result.touchdown.y))
        if keep_sets and math.isinf(contact):
            for fr in frames:
                on_ball = (fr.labels == BALL) & np.isfinite(fr.points[..., 0])
                if on_ball.sum() >= 4:
                    mount = params.mounts.by_name(fr.camera)
                    centre = camera_frame_centre(np.array([b.x, b.y, b.z]), goalie, mount)
                    record.ball_sets.append((fr.points[on_ball].astype(float), centre, float(np.linalg.norm(centre))))
    down = landing(free.x, free.y, free.z, free.vx, free.vy, free.vz, world.ball.radius, gravity)
    record.truth = (down.x, down.y, free_time + down.t)
    if free.z > world.ball.radius + 0.03:  # it met a robot, a post or a net, not the ground
        record.disturbed_at = contact
    return record


def prediction_at(record: LobRecord, tau: float) -> tuple[float, float, float] | None:
    """The latest prediction made at least ``tau`` s before touchdown."""
    cutoff = record.truth[2] - tau + TIME_EPS
    made = [p for p in record.predictions if p[0] <= cutoff]
    return made[-1] if made else None


def error_curves(records: list[LobRecord]) -> dict[str, Any]:
    clean = [r for r in records if r.disturbed_at >= r.truth[2] - LEAD]
    curve = []
    for tau in TAUS:
        errors = []
        for r in clean:
            p = prediction_at(r, float(tau))
            if p is not None:
                errors.append(math.hypot(p[1] - r.truth[0], p[2] - r.truth[1]))
        curve.append({"tau_s": float(tau), "share_predicted": _r(len(errors) / max(len(clean), 1), 3),
                      **summary(errors)})
    drift = [math.hypot(r.analytic[0] - r.truth[0], r.analytic[1] - r.truth[1]) for r in clean]
    made = [(r, prediction_at(r, LEAD)) for r in clean]
    ahead = [r.truth[2] - p[0] for r, p in made if p is not None]  # the ball leaves the views overhead
    return {"lobs": len(records), "undisturbed": len(clean), "integration_drift_m": summary(drift),
            "prediction_made_before_touchdown_s": summary(ahead, 1.0, 3), "curve": curve}


def sphere_fit_comparison(records: list[LobRecord], params: KinectBallParams, radius: float,
                          limit: int) -> dict[str, Any]:
    sets = [s for r in records for s in r.ball_sets][:limit]
    rng = np.random.default_rng(0)
    det = params.detection
    ours_t, ours_e = [], []
    for points, centre, dist in sets:
        t0 = time.perf_counter()
        fit = fit_sphere(points, radius, det.inlier_band(dist), det.iterations, det.refine_steps, rng)
        ours_t.append(time.perf_counter() - t0)
        ours_e.append(float(np.linalg.norm(fit.centre - centre)) if fit is not None else math.inf)
    out: dict[str, Any] = {
        "point_sets": len(sets), "points_per_set": summary([len(s[0]) for s in sets], 1.0, 1),
        "numpy_ransac": {"iterations": det.iterations, "time_ms": summary(ours_t, 1e3, 3),
                         "centre_error_m": summary(ours_e)}}
    try:
        import pyransac3d
    except ImportError:
        out["pyransac3d"] = "not installed (pip install pyransac3d to compare)"
        return out

    for iterations in (det.iterations, 1000):
        times, errors = [], []
        for points, centre, dist in sets:
            t0 = time.perf_counter()
            found, _radius, _inliers = pyransac3d.Sphere().fit(points, thresh=det.inlier_band(dist),
                                                               maxIteration=iterations)
            times.append(time.perf_counter() - t0)
            errors.append(float(np.linalg.norm(np.asarray(found) - centre)) if len(found) == 3 else math.inf)
        out[f"pyransac3d_{iterations}"] = {"version": version("pyransac3d"), "iterations": iterations,
                                           "time_ms": summary(times, 1e3, 3), "centre_error_m": summary(errors)}
    return out


def plot(results: dict[str, Any], records: list[LobRecord], path: Path) -> None:
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(12, 4.5))
    curve = results["touchdown"]["curve"]
    tau = [c["tau_s"] for c in curve]
    for key, style in (("median", "-"), ("p90", "--")):
        ax.plot(tau, [np.nan if c[key] is None else c[key] * 100 for c in curve], style, label=key)
    ax.axhline(TARGET_ERROR_M * 100, color="grey", lw=0.8)
    ax.axvline(LEAD, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("time to touchdown [s]")
    ax.set_ylabel("touchdown prediction error [cm]")
    ax.set_title(f"{results['touchdown']['undisturbed']} undisturbed lobs from 4-9 m")
    ax.invert_xaxis()
    ax.set_ylim(0, 60)
    ax.legend(loc="upper center")
    share = ax.twinx()
    share.plot(tau, [c["share_predicted"] for c in curve], color="tab:green", lw=0.8)
    share.set_ylabel("share of lobs with a prediction", color="tab:green")
    share.set_ylim(0, 1.05)
    frame = [ms for r in records for ms in r.frame_ms]
    render = [ms for r in records for ms in r.render_ms]
    bx.hist([frame, render], bins=40, label=["kinect_ball (both clouds)", "rendering (simulator)"])
    bx.axvline(TARGET_FRAME_MEDIAN_MS, color="grey", lw=0.8)
    bx.set_xlabel("time per frame pair [ms]")
    bx.legend()
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


def run(args: argparse.Namespace) -> tuple[dict[str, Any], list[LobRecord]]:
    world = load_world(args.field)
    params = load_yaml(KinectBallParams, CONFIG)
    cpu = None if args.cpu < 0 else args.cpu
    lobs = 20 if args.quick else args.lobs
    records: list[LobRecord] = []
    start = time.monotonic()
    with pinned(cpu):
        for k in range(lobs):
            records.append(fly_lob(k, args.seed, world, params, keep_sets=k < 40))
            if (k + 1) % 20 == 0:
                print(f"  {k + 1}/{lobs} lobs, {time.monotonic() - start:.0f} s", flush=True)
        fits = sphere_fit_comparison(records, params, world.ball.radius, 300)
    frame = summary([ms for r in records for ms in r.frame_ms], 1.0, 3)
    touchdown = error_curves(records)
    at_lead = next(c for c in touchdown["curve"] if abs(c["tau_s"] - LEAD) < 1e-6)
    results = {
        "machine": machine(cpu), "seed": args.seed, "field": world.name, "lobs": lobs,
        "camera": {"resolution": "128 x 106", "mounts": "nubot_common.kinect_mount.GOALIE_MOUNTS"},
        "frame_time_ms": {**frame, "target_median_ms": TARGET_FRAME_MEDIAN_MS,
                          "met": frame["median"] is not None and frame["median"] <= TARGET_FRAME_MEDIAN_MS},
        "render_time_ms": summary([ms for r in records for ms in r.render_ms], 1.0, 3),
        "touchdown_error_at_0_3s_m": {**{k: at_lead[k] for k in ("count", "median", "p90", "p95", "max")},
                                      "share_predicted": at_lead["share_predicted"],
                                      "made_before_touchdown_s": touchdown["prediction_made_before_touchdown_s"],
                                      "undisturbed_lobs": touchdown["undisturbed"],
                                      "target_median_m": TARGET_ERROR_M,
                                      "met": at_lead["median"] is not None and at_lead["median"] <= TARGET_ERROR_M},
        "touchdown": touchdown,
        "sphere_fit": fits,
        "wall_seconds": _r(time.monotonic() - start, 1),
    }
    return results, records


def report(results: dict[str, Any]) -> str:
    f, e, s = results["frame_time_ms"], results["touchdown_error_at_0_3s_m"], results["sphere_fit"]
    lines = [f"kinect_ball per frame pair: median {f['median']} ms, p95 {f['p95']} ms "
             f"(target median <= {f['target_median_ms']:g} ms: {'met' if f['met'] else 'NOT met'}); "
             f"rendering median {results['render_time_ms']['median']} ms",
             f"touchdown error 0.3 s before landing over {e['undisturbed_lobs']} undisturbed of {results['lobs']} "
             f"lobs ({e['share_predicted']:.0%} predicted): median {e['median']} m, p90 {e['p90']} m, "
             f"p95 {e['p95']} m, max {e['max']} m (target median <= {e['target_median_m']:g} m: "
             f"{'met' if e['met'] else 'NOT met'}); that prediction made a median "
             f"{e['made_before_touchdown_s']['median']} s before touchdown (the ball then leaves the views overhead)",
             f"sphere fit on {s['point_sets']} ball point sets: numpy RANSAC {s['numpy_ransac']['time_ms']['median']} "
             f"ms, centre error median {s['numpy_ransac']['centre_error_m']['median']} m"]
    for key in ("pyransac3d_48", "pyransac3d_1000"):
        if isinstance(s.get(key), dict):
            lines.append(f"  pyransac3d ({s[key]['iterations']} iterations): {s[key]['time_ms']['median']} ms, "
                         f"centre error median {s[key]['centre_error_m']['median']} m, "
                         f"p95 {s[key]['centre_error_m']['p95']} m")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--lobs", type=int, default=200)
    parser.add_argument("--quick", action="store_true", help="20 lobs")
    parser.add_argument("--field", default="18x12", help="18x12, 22x14 or a world YAML")
    parser.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                        help="the core the measurements are pinned to (-1: no pinning)")
    args = parser.parse_args(argv)
    if args.seed < 0 or args.lobs < 1:
        parser.error("--seed must not be negative and --lobs must be positive")
    args.out.mkdir(parents=True, exist_ok=True)
    results, records = run(args)
    (args.out / "kinect_ball.json").write_text(strict_json(results, indent=2))
    plot(results, records, args.out / "kinect_ball.png")
    print(report(results))
    print(f"figures: {args.out / 'kinect_ball.json'}, {args.out / 'kinect_ball.png'}")
    return 0
