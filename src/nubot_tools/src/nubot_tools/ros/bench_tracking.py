"""Benchmark the motion layer: the Fig. 13 experiment in the simulator, and its cost per control cycle.

1. In the simulator over ROS (``path_tracking.launch``): nubot1 drives p0 -> p1 -> p2 -> p3 around two
   standing robots, with the MPC tracker and with the baseline, at 3.25 m/s and at 4 m/s. From the
   simulator's ground truth (``/sim_visual/model_states``) and the node's ``TrackingInfo``: the RMS
   and maximum position error (MPC: against its reference point of each instant; both trackers: the
   distance to the MPC run's reference path), the peak speed, the time to reach p3 and the least
   gap between hulls.
   Plots, per speed: reference vs real trajectory, speed, error (PNG).
2. In-process, pinned to one core: the wall time of one control cycle (replanning + MPC) with
   10 obstacles, and of the baseline's.
Writes ``<out>/tracking.json`` and ``<out>/tracking_{path,speed,error}_<speed>.png``.
"""

from __future__ import annotations

import argparse
import math
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import rospy

from nubot_common.geometry import Pose2D, rotate
from nubot_common.json_text import strict_json
from nubot_common.msg import ModelStates, TrackingInfo
from nubot_common.processes import RosMaster, wait_until
from nubot_common.world_description import WorldDescription
from nubot_control.motion import MotionController
from nubot_control.params import MotionParams
from nubot_tools.workspace import BENCH_RESULTS

P0 = (-6.0, -3.0)
WAYPOINTS = ((-2.0, 2.0), (2.0, -2.0), (6.0, 2.0))
OBSTACLES = ((-4.0, 0.0), (0.0, 0.0))
ROBOT_RADIUS = 0.26


# --- 2: cost per cycle ---------------------------------------------------------------------------
def cycle_cost(tracker: str, cycles: int, seed: int = 0) -> dict:
    """Drive a kinematic robot to ever new random goals among 10 robots that wander; time each cycle."""
    rng = np.random.default_rng(seed)
    dt = 1.0 / 33.0
    motion = MotionController(MotionParams(tracker=tracker, max_speed=3.25), WorldDescription(), dt)
    obstacles = rng.uniform((-7.0, -5.0), (7.0, 5.0), size=(10, 2))
    drift = rng.normal(0.0, 0.5, size=(10, 2))
    pose, goal, times = Pose2D(-7.0, 0.0, 0.0), (7.0, 0.0), []
    for k in range(cycles):
        if k == 0 or math.hypot(goal[0] - pose.x, goal[1] - pose.y) < 0.3:  # always on the move
            gx, gy = rng.uniform((-7.0, -5.0), (7.0, 5.0))
            goal = (float(gx), float(gy))
        obstacles = np.clip(obstacles + drift * dt, (-8.0, -5.5), (8.0, 5.5))
        bx, by, w = motion.follow(pose, [goal], 0.0, [tuple(o) for o in obstacles], dt)
        times.append(motion.compute_time)
        vx, vy = rotate(bx, by, pose.theta)
        pose = Pose2D(pose.x + vx * dt, pose.y + vy * dt, pose.theta + w * dt)
    ms = np.array(times) * 1e3
    return {"cycles": cycles, "obstacles": 10, "median_ms": round(float(np.median(ms)), 3),
            "p95_ms": round(float(np.percentile(ms, 95)), 3), "max_ms": round(float(ms.max()), 3)}


# --- 1: the Fig. 13 experiment -----------------------------------------------------------------------
class Recorder:
    def __init__(self):
        self.lock = threading.Lock()
        self.truth: list[tuple[float, float, float, float, float]] = []  # t, x, y, vx, vy
        self.obstacles: dict[str, tuple[float, float]] = {}
        self.tracking: list[tuple[float, float, float, float, bool, float]] = []  # t, rx, ry, err, finished, cpu
        self.subs = [rospy.Subscriber("/sim_visual/model_states", ModelStates, self._states, queue_size=20),
                     rospy.Subscriber("/nubot1/nubotcontrol/tracking", TrackingInfo, self._tracking, queue_size=50)]

    def _states(self, msg) -> None:
        t = rospy.get_time()
        with self.lock:
            for name, pose, twist in zip(msg.name, msg.pose, msg.twist):
                if name == "nubot1":
                    self.truth.append((t, pose.position.x, pose.position.y, twist.linear.x, twist.linear.y))
                elif name.startswith("rival"):
                    self.obstacles[name] = (pose.position.x, pose.position.y)

    def _tracking(self, msg) -> None:
        with self.lock:
            self.tracking.append((msg.header.stamp.to_sec(), msg.reference.x, msg.reference.y, msg.error,
                                  msg.finished, msg.compute_time))

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


def drive(master: RosMaster, tracker: str, speed: float, timeout: float) -> dict:
    recorder = Recorder()
    process = master.launch(f"tracking_{tracker}_{speed}", [
        "roslaunch", "nubot_control", "path_tracking.launch", f"tracker:={tracker}", f"max_speed:={speed}"])
    try:
        wait_until(lambda: any(r[4] for r in recorder.tracking) or not process.alive(), timeout,
                   f"{tracker} at {speed} m/s to reach p3", poll=0.1)
        time.sleep(0.5)
    finally:
        recorder.close()
        process.stop()
        time.sleep(0.5)
    with recorder.lock:
        return {"truth": np.array(recorder.truth), "tracking": recorder.tracking,
                "obstacles": dict(recorder.obstacles)}


def path_distance(points: np.ndarray, path: np.ndarray) -> np.ndarray:
    """Distance from each point to the polyline ``path``."""
    a, b = path[:-1], path[1:]
    ab = b - a
    length2 = np.maximum((ab ** 2).sum(axis=1), 1e-12)
    ap = points[:, None, :] - a[None, :, :]
    t = np.clip((ap * ab[None]).sum(axis=2) / length2[None], 0.0, 1.0)
    closest = a[None] + t[..., None] * ab[None]
    return np.linalg.norm(points[:, None, :] - closest, axis=2).min(axis=1)


def reference_of(run: dict) -> np.ndarray:
    """The MPC run's reference: the points it was to be at, cycle after cycle, as a polyline (N, 2)."""
    points = np.array([(r[1], r[2]) for r in run["tracking"] if r[5] > 0.0 or r[3] > 0.0])
    keep = np.concatenate(([True], np.linalg.norm(np.diff(points, axis=0), axis=1) > 1e-6))
    return points[keep]


def analyse(run: dict, path: np.ndarray, tracker: str) -> dict:
    """Errors against ``path`` (the MPC's reference) for both trackers; against the reference point of each
    instant for the MPC only (the baseline has no timed reference: it heads for the next waypoint)."""
    truth, tracking = run["truth"], run["tracking"]
    moving = [r for r in tracking if r[3] > 0.0 or r[5] > 0.0]  # cycles after the start delay
    start = moving[0][0]
    done = next((r[0] for r in tracking if r[4]), math.nan)
    in_run = truth[(truth[:, 0] >= start) & (truth[:, 0] <= (done if math.isfinite(done) else truth[-1, 0]))]
    t_track = np.array([r[0] for r in moving if not r[4]])
    ref = np.array([(r[1], r[2]) for r in moving if not r[4]])
    true_at = np.column_stack([np.interp(t_track, truth[:, 0], truth[:, k]) for k in (1, 2)])
    error = np.linalg.norm(true_at - ref, axis=1)
    off_path = path_distance(in_run[:, 1:3], path)
    speed = np.linalg.norm(in_run[:, 3:5], axis=1)
    obstacles = np.array(list(run["obstacles"].values()))
    gaps = np.linalg.norm(in_run[:, None, 1:3] - obstacles[None], axis=2).min() - 2 * ROBOT_RADIUS
    cpu = np.array([r[5] for r in moving]) * 1e3
    timed = tracker == "mpc"
    return {
        "reached_p3": bool(math.isfinite(done)),
        "time_to_p3_s": round(done - start, 3) if math.isfinite(done) else None,
        "final_error_m": round(float(np.hypot(truth[-1, 1] - WAYPOINTS[-1][0], truth[-1, 2] - WAYPOINTS[-1][1])), 4),
        "rms_error_m": round(float(np.sqrt(np.mean(error ** 2))), 4) if timed else None,
        "max_error_m": round(float(error.max()), 4) if timed else None,
        "rms_path_error_m": round(float(np.sqrt(np.mean(off_path ** 2))), 4),
        "max_path_error_m": round(float(off_path.max()), 4),
        "peak_speed_mps": round(float(speed.max()), 3), "least_hull_gap_m": round(float(gaps), 3),
        "cycle_median_ms": round(float(np.median(cpu)), 3),
        "series": {"t": (in_run[:, 0] - start).round(3).tolist(), "x": in_run[:, 1].round(4).tolist(),
                   "y": in_run[:, 2].round(4).tolist(), "speed": speed.round(4).tolist(),
                   "path_error": off_path.round(4).tolist(), "t_ref": (t_track - start).round(3).tolist(),
                   "ref_x": ref[:, 0].round(4).tolist(), "ref_y": ref[:, 1].round(4).tolist(),
                   "error": error.round(4).tolist()},
    }


def plot(results: dict, speed: float, path: np.ndarray, out: Path) -> list[Path]:
    colours = {"mpc": "tab:blue", "baseline": "tab:orange"}
    files = []
    fig, ax = plt.subplots(figsize=(8, 5.5))
    ax.plot(path[:, 0], path[:, 1], "k--", lw=1.2, label="reference (mpc run)")
    for tracker, r in results.items():
        s = r["series"]
        ax.plot(s["x"], s["y"], color=colours[tracker], lw=1.5, label=f"{tracker}: real trajectory")
    for x, y in OBSTACLES:
        ax.add_patch(plt.Circle((x, y), ROBOT_RADIUS, color="tab:red", alpha=0.6))
    for name, (x, y) in zip(("p0", "p1", "p2", "p3"), (P0, *WAYPOINTS)):
        ax.plot(x, y, "ko", ms=4)
        ax.annotate(name, (x, y), textcoords="offset points", xytext=(5, 5))
    ax.set_aspect("equal")
    files.append(_save(fig, ax, ("x [m]", "y [m]"), f"reference vs real trajectory, at most {speed} m/s",
                       out / f"tracking_path_{speed}.png", "lower right"))

    fig, ax = plt.subplots(figsize=(8, 3.5))
    for tracker, r in results.items():
        ax.plot(r["series"]["t"], r["series"]["speed"], color=colours[tracker], label=tracker)
    ax.axhline(speed, color="k", ls=":", label=f"limit {speed} m/s")
    files.append(_save(fig, ax, ("time [s]", "speed [m/s]"), "speed", out / f"tracking_speed_{speed}.png"))

    fig, ax = plt.subplots(figsize=(8, 3.5))
    for tracker, r in results.items():
        s = r["series"]
        ax.plot(s["t"], np.array(s["path_error"]) * 100, color=colours[tracker], label=f"{tracker}: distance to path")
        if tracker == "mpc":
            ax.plot(s["t_ref"], np.array(s["error"]) * 100, color=colours[tracker], ls="--", lw=1,
                    label="mpc: distance to the reference point")
    files.append(_save(fig, ax, ("time [s]", "error [cm]"), "tracking error", out / f"tracking_error_{speed}.png"))
    return files


def _save(fig, ax, labels: tuple[str, str], title: str, path: Path, legend: str = "best") -> Path:
    ax.set_xlabel(labels[0])
    ax.set_ylabel(labels[1])
    ax.set_title(title)
    ax.legend(loc=legend, fontsize=8)
    fig.savefig(path, dpi=120, bbox_inches="tight")
    plt.close(fig)
    return path


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--speeds", type=float, nargs="+", default=[3.25, 4.0])
    parser.add_argument("--cycles", type=int, default=1500, help="cycles timed in-process")
    parser.add_argument("--timeout", type=float, default=60.0, help="wall time allowed per run [s]")
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    result: dict = {"scenario": {"p0": P0, "waypoints": WAYPOINTS, "obstacles": OBSTACLES}}

    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, {min(os.sched_getaffinity(0))})
    for tracker in ("mpc", "baseline"):
        print(f"[bench] one control cycle with 10 obstacles, {tracker}, {args.cycles} cycles on one core", flush=True)
        result[f"cycle_cost_{tracker}"] = cost = cycle_cost(tracker, args.cycles)
        print(f"        median {cost['median_ms']} ms, p95 {cost['p95_ms']} ms, max {cost['max_ms']} ms", flush=True)
    if hasattr(os, "sched_setaffinity"):
        os.sched_setaffinity(0, set(range(os.cpu_count() or 1)))

    with RosMaster(args.out / "logs") as master:
        master.use_in_this_process()
        subprocess.run(["rosparam", "set", "/use_sim_time", "true"], check=True, env=master.env)
        rospy.init_node("bench_tracking", disable_signals=True)  # on the simulator's clock, as the stamps are
        for speed in args.speeds:
            runs, path = {}, None
            for tracker in ("mpc", "baseline"):
                print(f"[bench] Fig. 13 scenario, {tracker}, at most {speed} m/s", flush=True)
                run = drive(master, tracker, speed, args.timeout)
                path = reference_of(run) if path is None else path
                runs[tracker] = analyse(run, path, tracker)
                r = runs[tracker]
                print(f"        reached p3 {r['reached_p3']} in {r['time_to_p3_s']} s; error RMS {r['rms_error_m']} m, "
                      f"max {r['max_error_m']} m; path error RMS {r['rms_path_error_m']} m, max "
                      f"{r['max_path_error_m']} m; peak {r['peak_speed_mps']} m/s; least gap "
                      f"{r['least_hull_gap_m']} m", flush=True)
            files = plot(runs, speed, path, args.out)
            print(f"        plots: {', '.join(str(f) for f in files)}", flush=True)
            for r in runs.values():
                r.pop("series")
            result[f"fig13_{speed}"] = runs
        rospy.signal_shutdown("done")
    (args.out / "tracking.json").write_text(strict_json(result, indent=2))
    print(f"figures: {args.out / 'tracking.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
