"""Benchmark front_vision in one process without ROS: time per frame and the ball's position error.

    python scripts/bench_front_vision.py --out bench/results [--seed 0] [--balls 500] [--cpu N]

Requires: sim_visual's ``FrontCameraRenderer`` (the simulated front camera with its default, true camera and its
noise), front_vision's shipped calibration (``config/front_camera_sim.yaml``, made by ``rosrun front_vision
calibrate --simulate``) and omni_vision's colour table (``config/colors_sim.npz``), matplotlib.
Scenario: ``--balls`` seeded placements of the ball on the ground at 0.6 - 4.5 m from the robot's centre, within
+-40 deg of its front, the robot at a random pose inside the lines, sometimes (one in three) another robot 0.8 -
1.5 m beyond the ball. Each frame goes through ``FrontVision.process`` (the calibrated camera, not the true one)
on one core (``cv2.setNumThreads(1)``, pinned to ``--cpu``).
Provides, in ``--out``: ``front_vision.json`` (the machine, per-frame time median and p95 [ms] (target median <=
3 ms), the rendering's time, per distance bin: balls wholly in view, detection rate, error median, p95 and max
[cm]; within 1.5 m the error's p95 and max (target max <= 2 cm) and ``met``) and ``front_vision.png`` (error
against distance; time per frame); a summary on stdout. Every figure but the times is deterministic for a seed.
"""

from __future__ import annotations

import argparse
import math
import os
import time
from pathlib import Path
from typing import Any

import cv2
import matplotlib.pyplot as plt
import numpy as np

from front_vision.pipeline import FrontVision
from nubot_common.camera_model import PinholeCamera, load_camera
from nubot_common.json_text import strict_json
from nubot_common.packages import package_path
from nubot_common.world_description import WorldDescription
from nubot_tools.bench.harness import cpu_pressure, machine, pinned
from nubot_tools.workspace import BENCH_RESULTS
from omni_vision.colors import ColorTable
from sim_visual.camera_params import OmniCameraParams
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.world import BallState, RobotState

CAMERA_FILE = package_path("front_vision") / "config" / "front_camera_sim.yaml"
TABLE_FILE = package_path("omni_vision") / "config" / "colors_sim.npz"
BINS = (0.6, 1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5)  # [m] from the robot's centre
NEAR = 1.5  # [m] the error target holds within this distance
TARGET_MEDIAN_MS = 3.0
TARGET_ERROR_CM = 2.0
MAX_BEARING = math.radians(40.0)
_RIM_POINTS = 32


def wholly_in_view(camera: PinholeCamera, centre: np.ndarray, radius: float) -> bool:
    """Whether the whole ball (centre [m], body frame) lies inside the image (the true camera's tangent cone)."""
    rel = centre - camera.origin
    dist = float(np.linalg.norm(rel))
    axis = rel / dist
    side = np.cross(axis, [0.0, 0.0, 1.0])
    side /= np.linalg.norm(side)
    up = np.cross(side, axis)
    psi = np.linspace(0.0, 2.0 * math.pi, _RIM_POINTS, endpoint=False)
    s = radius / dist
    rim = camera.origin + math.sqrt(1.0 - s * s) * axis + s * (np.outer(np.cos(psi), side) + np.outer(np.sin(psi), up))
    uv, ahead = camera.project(rim)
    margin = 1.5
    return bool(ahead.all() and (uv[:, 0] >= margin).all() and (uv[:, 0] <= camera.width - 1 - margin).all()
                and (uv[:, 1] >= margin).all() and (uv[:, 1] <= camera.height - 1 - margin).all())


def run(args: argparse.Namespace) -> tuple[dict[str, Any], list[float]]:
    """The figures, and every frame's processing time [ms] (for the plot)."""
    world = WorldDescription()
    params = FrontCameraParams()
    renderer = FrontCameraRenderer(world, params, OmniCameraParams())
    vision = FrontVision(load_camera(CAMERA_FILE), ColorTable.load(TABLE_FILE))
    radius, field = world.ball.radius, world.field
    rng = np.random.default_rng(args.seed)
    noise = np.random.default_rng(np.random.SeedSequence([args.seed, 1]))
    rows: list[dict[str, Any]] = []
    process_ms: list[float] = []
    render_ms: list[float] = []
    cpu = None if args.cpu < 0 else args.cpu
    with pinned(cpu):
        vision.process(0.0, renderer.render(RobotState(0, 0, 0, 0, 0, 0), BallState(1, 0, radius, 0, 0, 0), [], 0.0,
                                            noise))  # warm-up: caches, first allocations
        for k in range(args.balls):
            me = RobotState(rng.uniform(-field.half_length + 3.5, field.half_length - 3.5),
                            rng.uniform(-field.half_width + 3.5, field.half_width - 3.5),
                            rng.uniform(-math.pi, math.pi), 0.0, 0.0, 0.0)
            d, bearing = rng.uniform(BINS[0], BINS[-1]), rng.uniform(-MAX_BEARING, MAX_BEARING)
            bx, by = d * math.cos(bearing), d * math.sin(bearing)
            c, s = math.cos(me.theta), math.sin(me.theta)
            ball = BallState(me.x + c * bx - s * by, me.y + s * bx + c * by, radius, 0.0, 0.0, 0.0)
            others = []
            if rng.uniform() < 1.0 / 3.0:
                beyond = d + rng.uniform(0.8, 1.5)
                side = bearing + rng.uniform(-0.3, 0.3)
                ox, oy = beyond * math.cos(side), beyond * math.sin(side)
                others.append(RobotState(me.x + c * ox - s * oy, me.y + s * ox + c * oy, 0.0, 0.0, 0.0, 0.0))
            start = time.perf_counter()
            image = renderer.render(me, ball, others, 0.1 * k, noise)
            middle = time.perf_counter()
            result = vision.process(0.1 * k, image)
            end = time.perf_counter()
            render_ms.append(1000.0 * (middle - start))
            process_ms.append(1000.0 * (end - middle))
            seen = result.percept is not None
            error = math.hypot(result.percept.x - bx, result.percept.y - by) if result.percept is not None else None
            rows.append({"distance": d, "bearing_deg": math.degrees(bearing), "robot_behind": bool(others),
                         "in_view": wholly_in_view(params.camera, np.array([bx, by, radius]), radius),
                         "seen": seen, "sighting": result.sighting.sighting.value,
                         "error_cm": None if error is None else 100.0 * error})
    return summarise(args, rows, process_ms, render_ms, cpu), process_ms


def _stats(values: list[float]) -> dict[str, float | None]:
    if not values:
        return {"median": None, "p95": None, "max": None}
    return {"median": round(float(np.median(values)), 3), "p95": round(float(np.percentile(values, 95)), 3),
            "max": round(float(np.max(values)), 3)}


def summarise(args: argparse.Namespace, rows: list[dict[str, Any]], process_ms: list[float],
              render_ms: list[float], cpu: int | None) -> dict[str, Any]:
    bins = []
    for low, high in zip(BINS[:-1], BINS[1:]):
        inside = [r for r in rows if low <= r["distance"] < high]
        in_view = [r for r in inside if r["in_view"]]
        errors = [r["error_cm"] for r in inside if r["error_cm"] is not None]
        bins.append({"from_m": low, "to_m": high, "balls": len(inside), "wholly_in_view": len(in_view),
                     "detection_rate_in_view": round(sum(r["seen"] for r in in_view) / len(in_view), 3)
                     if in_view else None,
                     "reported_when_not_wholly_in_view": sum(r["seen"] for r in inside if not r["in_view"]),
                     "error_cm": _stats(errors)})
    near = [r["error_cm"] for r in rows if r["distance"] < NEAR and r["error_cm"] is not None]
    near_in_view = [r for r in rows if r["distance"] < NEAR and r["in_view"]]
    times: dict[str, Any] = dict(_stats(process_ms))
    near_stats: dict[str, Any] = dict(_stats(near))
    results: dict[str, Any] = {
        "machine": machine(cpu), "seed": args.seed, "balls": args.balls,
        "camera": {"simulated": str(FrontCameraParams().camera), "calibrated_file": str(CAMERA_FILE.name)},
        "process_time_ms": {**times, "target_median": TARGET_MEDIAN_MS,
                            "met": times["median"] is not None and times["median"] <= TARGET_MEDIAN_MS},
        "render_time_ms": _stats(render_ms),
        "error_within_1_5_m_cm": {**near_stats, "samples": len(near), "target_max": TARGET_ERROR_CM,
                                  "detection_rate_in_view": round(sum(r["seen"] for r in near_in_view)
                                                                  / max(len(near_in_view), 1), 3),
                                  "met": near_stats["max"] is not None and near_stats["max"] <= TARGET_ERROR_CM},
        "bins": bins,
        "samples": rows,
    }
    results["machine"]["load_average_end"] = [round(x, 2) for x in os.getloadavg()]
    results["machine"]["cpu_pressure_some_avg60_percent_end"] = cpu_pressure()
    return results


def plot(results: dict[str, Any], process_ms: list[float], path: Path) -> None:
    rows = results["samples"]
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.2))
    seen = [r for r in rows if r["error_cm"] is not None]
    ax.scatter([r["distance"] for r in seen], [r["error_cm"] for r in seen], s=8, alpha=0.7, label="ball seen")
    missed = [r for r in rows if r["in_view"] and r["error_cm"] is None]
    ax.scatter([r["distance"] for r in missed], [0.0] * len(missed), marker="x", color="tab:red", s=14,
               label="wholly in view, not reported")
    ax.axhline(TARGET_ERROR_CM, color="k", lw=0.8, ls="--", label=f"target {TARGET_ERROR_CM:g} cm within {NEAR} m")
    ax.axvline(NEAR, color="grey", lw=0.8, ls=":")
    ax.set_xlabel("ball distance from the robot's centre [m]")
    ax.set_ylabel("position error [cm]")
    ax.set_title("front_vision: ball position error (calibrated camera)")
    ax.legend(fontsize=8)
    t = results["process_time_ms"]
    bx.hist(process_ms, bins=40, color="tab:green")
    bx.axvline(t["median"], color="k", lw=1.0, label=f"median {t['median']:.2f} ms")
    bx.axvline(t["p95"], color="k", lw=1.0, ls="--", label=f"p95 {t['p95']:.2f} ms")
    bx.set_xlabel("FrontVision.process per frame [ms] (one core)")
    bx.set_ylabel("frames")
    bx.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def report(results: dict[str, Any]) -> str:
    t, r, e = results["process_time_ms"], results["render_time_ms"], results["error_within_1_5_m_cm"]
    lines = [f"front_vision per frame: median {t['median']:.2f} ms, p95 {t['p95']:.2f} ms "
             f"(target median <= {TARGET_MEDIAN_MS:g} ms: {'met' if t['met'] else 'NOT met'}); "
             f"rendering median {r['median']:.2f} ms",
             f"ball error within {NEAR} m ({e['samples']} seen, detection {100 * e['detection_rate_in_view']:.1f} % of "
             f"balls wholly in view): median {e['median']:.2f} cm, p95 {e['p95']:.2f} cm, max {e['max']:.2f} cm "
             f"(target max <= {TARGET_ERROR_CM:g} cm: {'met' if e['met'] else 'NOT met'})",
             "by distance [m]: in view / detected / error median, p95, max [cm]"]
    for b in results["bins"]:
        err = b["error_cm"]
        rate = "-" if b["detection_rate_in_view"] is None else f"{100 * b['detection_rate_in_view']:.0f} %"
        figures = "-" if err["median"] is None else f"{err['median']:.2f}, {err['p95']:.2f}, {err['max']:.2f}"
        lines.append(f"  {b['from_m']:.1f}-{b['to_m']:.1f}: {b['wholly_in_view']:3d} / {rate:>5s} / {figures}")
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--balls", type=int, default=500, help="seeded ball placements (default 500)")
    parser.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                        help="the core the measurements are pinned to (-1: no pinning)")
    args = parser.parse_args(argv)
    if args.seed < 0 or args.balls < 1:
        parser.error("--seed must not be negative and --balls at least 1")
    args.out.mkdir(parents=True, exist_ok=True)
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    try:
        results, process_ms = run(args)
    finally:
        cv2.setNumThreads(threads)
    (args.out / "front_vision.json").write_text(strict_json(results, indent=2))
    plot(results, process_ms, args.out / "front_vision.png")
    print(report(results))
    print(f"figures: {args.out / 'front_vision.json'}, {args.out / 'front_vision.png'}")
    return 0
