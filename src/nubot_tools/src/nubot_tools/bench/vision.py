"""Benchmark the omni vision in one process without ROS: pipeline time, localization, the ball, Fig. 11.

    python scripts/bench_vision.py --out bench/results [--seed 0] [--quick] [--field 18x12] [--cpu N]

Requires: the world (``--field``), omni_vision's ``config/omni_vision.yaml`` and ``config/colors_sim.npz``,
sim_visual's ``Simulator`` (physics at 0.005 s, the robots' camera, odometry and inertial heading), matplotlib.
The vision robot is ``nubot1``, attacking +x (its team frame is the world frame); the others are ``rivalN``. Its
``OmniVision`` gets what the simulator node publishes, by sim time: camera frames at 30 Hz, odometry and the
inertial heading at 50 Hz; robots are commanded at 33 Hz (the control nodes' rate), moving robots by a
feed-forward plus proportional controller on the TRUE pose (the localization is measured, not the control).
Provides, in ``--out``: ``vision.json`` (the machine, the durations, every figure with its target and ``met``)
and the plots ``vision_localization.png`` (the figure of eight's error over time and its traces; Fig. 11:
the estimated trace over the true one along a rectangle, on the field's lines) and ``vision_ball.png`` (the
ball's error and detection rate against its distance); progress lines and a summary on stdout. Scenarios:

1. ``pipeline_time``: ``timings`` of ``OmniVision.process`` per stage while tracking, over the figure of eight's
   frames, on one core (``cv2.setNumThreads(1)``, pinned to ``--cpu``): median and p90 [ms]; target median
   total <= 5 ms. The rendering (``Simulator.camera_frame``) apart, median and p90 [ms].
2. ``standing``: the robot standing at fixed poses, other robots about it, from a global search (no pose given):
   after ``SETTLE`` s, the mean position error [m] (target <= 0.02 m) and heading error [deg].
3. ``figure_eight``: a lemniscate of Gerono (8 x 4 m about the centre spot) at 3 m/s, facing along the path,
   among five robots moving slowly in small circles off the path, starting from the known pose: mean (target
   <= 0.04 m) and p95 (target <= 0.10 m) position error, heading error mean and p95, share of frames localized.
4. ``global_localization``: seeded random poses inside the lines (random heading, robots about): ``reset()``,
   then frames of the standing robot until it is localized within ``CONVERGED_ERROR``; target: within 30
   frames (1 s) for at least 95 %; frames needed; wrong convergences (localized more than ``WRONG_ERROR`` off).
5. ``ball``: the ball at seeded random distances (0.6-9 m) and directions, robots about; balls a robot or a
   mirror strut hides (geometry) are counted apart. Per distance bin: detection rate, error [% of distance]
   median and p95; targets: rate >= 95 % and p95 error <= 5 % up to 6 m. False detections per minute: the
   robot driving among robots with the ball out of view (above the viewpoint, so no camera sees it).
6. ``fig11``: the robot driven along a rectangle at 2 m/s (stopping at the corners, heading fixed): the traces
   (plot) and their error, held to the figure of eight's targets.

The simulated mirror is the one the vision is calibrated for (the simulator's and omni_vision's defaults), except
in ``figure_eight_miscalibrated_mirror``: the figure of eight again, the mirror's scale off by
``MIRROR_SCALE_ERROR`` and its centre by ``MIRROR_CENTRE_ERROR`` (no target: how much a calibration error
costs). Global localization starts with the inertial heading off by up to ``GLOBAL_HEADING_OFFSET``.

Every figure but the times is deterministic for a seed (one ``numpy.random.Generator`` per scenario from
``--seed``; the simulator's sensor noise from the same seed).
"""

from __future__ import annotations

import argparse
import math
import os
import time
from collections.abc import Callable, Sequence
from dataclasses import asdict, dataclass, replace
from pathlib import Path
from typing import Any

import cv2
import matplotlib.pyplot as plt
import numpy as np

from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, rotate, wrap_angle
from nubot_common.json_text import strict_json
from nubot_common.packages import package_path
from nubot_common.params import load_yaml
from nubot_common.world_description import WorldDescription, load_world
from nubot_tools.bench.harness import cpu_pressure, machine, pinned
from nubot_tools.workspace import BENCH_RESULTS
from omni_vision.colors import ColorTable
from omni_vision.pipeline import OmniVision, OmniVisionParams
from sim_visual.params import RobotSpawn, SimConfig
from sim_visual.sensors import SensorParams
from sim_visual.simulator import Simulator
from sim_visual.world import BallState, RobotState

VISION_CONFIG = package_path("omni_vision") / "config"
VIEWER = "nubot1"  # the robot that sees through its camera; attacks +x, so its team frame is the world frame
CAMERA_PERIOD = 1.0 / 30.0  # [s] as the simulator node publishes the camera
ODOMETRY_PERIOD = 1.0 / 50.0  # [s]
INERTIAL_PERIOD = 1.0 / 50.0  # [s]
COMMAND_PERIOD = 1.0 / 33.0  # [s] velocity commands, as the control nodes send them
TIME_EPS = 1e-9  # [s] sensor schedules compare sim times with this slack (sums of periods drift)
POSITION_GAIN = 3.0  # [1/s] the tracking controller's feedback on the true position
HEADING_GAIN = 4.0  # [1/s] ... and on the true heading
EIGHT_SIZE = (8.0, 4.0)  # [m] the figure of eight's extent along x and y, centred on the centre spot
EIGHT_SPEED = 3.0  # [m/s] along the path
EIGHT_ACCELERATION = 3.0  # [m/s^2] from rest up to the speed
EIGHT_CLEARANCE = 1.3  # [m] the other robots' spots keep this far from the path (they circle within 0.3 m)
LINE_SPEED = 2.0  # [m/s] Fig. 11's straight lines
LINE_ACCELERATION = 2.0  # [m/s^2] ... speeding up from and braking to each corner
FALSE_DETECTION_SPEED = 1.5  # [m/s] the robot drives the figure of eight this fast while the ball is out of view
BALL_OUT_OF_VIEW_Z = 10.0  # [m] above the viewpoint: no camera shows the ball
SETTLE = 1.0  # [s] standing: frames before this are not measured (the global search's start)
# The figure of eight again with a simulated mirror that is not exactly the one the vision was calibrated
# for, as on a real robot: its scale (a) off by MIRROR_SCALE_ERROR, its centre by MIRROR_CENTRE_ERROR [px].
MIRROR_SCALE_ERROR = 0.005
MIRROR_CENTRE_ERROR = (0.5, -0.5)
# Global localization starts with the inertial heading off by up to this [rad] (uniform), as before a
# recalibration: the search must still find the right pose and tell it from its mirror image.
GLOBAL_HEADING_OFFSET = math.radians(5.0)
CONVERGED_ERROR = 0.2  # [m] global localization has converged when localized within this
WRONG_ERROR = 0.5  # [m] localized farther off than this is a wrong convergence
STANDING_POSES = ((0.0, 0.0, 0.0), (-6.0, 3.0, math.pi / 2), (4.5, -2.0, -2.4), (7.5, 4.5, math.pi),
                  (-3.0, -4.5, 0.8))  # [m, m, rad] world frame
DISTANCE_BINS = ((0.0, 2.0), (2.0, 4.0), (4.0, 6.0), (6.0, 9.0))  # [m]
BALL_DISTANCE_RANGE = (0.6, 9.0)  # [m]
TARGET_PIPELINE_MEDIAN_MS = 5.0
TARGET_STANDING_MEAN_M = 0.02
TARGET_MOVING_MEAN_M = 0.04
TARGET_MOVING_P95_M = 0.10
TARGET_GLOBAL_FRAMES = 30  # 1 s at 30 Hz
TARGET_GLOBAL_SHARE = 0.95
TARGET_BALL_RATE = 0.95  # up to TARGET_BALL_RANGE
TARGET_BALL_ERROR_PERCENT = 5.0  # p95 of the error, % of the distance, up to TARGET_BALL_RANGE
TARGET_BALL_RANGE = 6.0  # [m]
STAGES = ("sample", "lines", "ball", "obstacles", "localization", "total")
Velocity = tuple[float, float, float]  # a body-frame velocity command (vx, vy [m/s], w [rad/s])
Command = Callable[[float], Velocity]  # the viewer's command at a sim time [s]


@dataclass(frozen=True)
class Durations:
    """How long each scenario runs."""

    standing_poses: int  # of STANDING_POSES
    standing_seconds: float  # [s of sim time] per pose
    eight_seconds: float  # [s of sim time]
    global_poses: int
    global_max_frames: int  # frames fed to one global search at most
    ball_placements: int  # one frame each
    false_detection_seconds: float  # [s of sim time]
    rectangle: tuple[float, float]  # [m] Fig. 11's rectangle (x, y), centred on the centre spot
    rectangle_laps: int


FULL = Durations(5, 10.0, 60.0, 100, 90, 600, 60.0, (12.0, 8.0), 1)
QUICK = Durations(2, 2.0, 8.0, 8, 45, 60, 4.0, (8.0, 4.0), 1)


@dataclass(frozen=True)
class FrameRecord:
    """One processed camera frame: the truth and what the vision made of it."""

    t: float  # [s] sim time
    truth: Pose2D  # team frame (= world frame)
    estimate: Pose2D
    localized: bool
    timings: dict[str, float]  # [s] per stage
    render: float  # [s] Simulator.camera_frame
    ball: tuple[float, float] | None  # detection, body frame [m]
    ball_truth: tuple[float, float, float]  # centre, body frame [m] (x, y, z)

    @property
    def position_error(self) -> float:
        return math.hypot(self.estimate.x - self.truth.x, self.estimate.y - self.truth.y)

    @property
    def heading_error(self) -> float:
        return abs(wrap_angle(self.estimate.theta - self.truth.theta))


# Where a driven robot should be at one time: its pose and velocity in the world frame.
Reference = RobotState


# --- the rig: one simulator, one vision --------------------------------------------------------------------------
class VisionRig:
    """A Simulator with the viewer and ``others`` robots and the viewer's OmniVision, fed as the nodes feed it."""

    def __init__(self, world: WorldDescription, params: OmniVisionParams, table: ColorTable, others: int, seed: int,
                 miscalibrated: bool = False):
        f = world.field
        # Spawned in a row on the border; every scenario places them where it wants them.
        spawns = [RobotSpawn(VIEWER, 0.0, 0.0, 0.0, 1)] + [
            RobotSpawn(f"rival{k + 1}", -f.half_length + 1.0 + 0.8 * k, -f.half_width - 0.6, 0.0, -1)
            for k in range(others)]
        self.world = world
        m = params.mirror
        if miscalibrated:
            m = replace(m, a=m.a * (1.0 + MIRROR_SCALE_ERROR), centre_u=m.centre_u + MIRROR_CENTRE_ERROR[0],
                        centre_v=m.centre_v + MIRROR_CENTRE_ERROR[1])
        self.sim = Simulator(SimConfig(world=world, robots=tuple(spawns), ball_start=(0.0, f.half_width - 0.5),
                                       seed=seed, sensors=SensorParams(mirror=m)))
        self.heading_offset = 0.0  # [rad] added to the inertial heading the vision gets
        _ = self.sim.sensors.renderer  # built now (about 0.1 s), not within the first frame's rendering time
        self.vision = OmniVision(world, params, table, 1)
        self.others = [s.name for s in spawns[1:]]
        self.drive: dict[str, Velocity] = {}  # the others' constant body-frame commands
        self._next = {"command": 0.0, "odometry": 0.0, "inertial": 0.0, "camera": 0.0}

    def place(self, name: str, x: float, y: float, theta: float) -> None:
        self.sim.set_model_state(name, RobotState(x, y, theta, 0.0, 0.0, 0.0))

    def place_ball(self, x: float, y: float, z: float | None = None) -> None:
        r = self.world.ball.radius
        self.sim.set_model_state(self.world.ball_name, BallState(x, y, r if z is None else z, 0.0, 0.0, 0.0))

    def viewer_pose(self) -> Pose2D:
        return self.sim.observe_truth(VIEWER).robot.pose

    def run(self, seconds: float | None = None, frames: int | None = None,
            command: Command | None = None,
            stop: Callable[[FrameRecord], bool] | None = None) -> list[FrameRecord]:
        """Step the simulator for ``seconds`` or until ``frames`` frames (or ``stop`` says so); the viewer
        follows ``command(t)`` (a body-frame velocity; standing without one). Return the frames processed."""
        sim, nxt, out = self.sim, self._next, list[FrameRecord]()
        end = sim.time + seconds if seconds is not None else math.inf
        while sim.time < end - TIME_EPS and (frames is None or len(out) < frames):
            if sim.time >= nxt["command"] - TIME_EPS:
                sim.command_velocity(VIEWER, *(command(sim.time) if command else (0.0, 0.0, 0.0)))
                for name in self.others:
                    sim.command_velocity(name, *self.drive.get(name, (0.0, 0.0, 0.0)))
                nxt["command"] += COMMAND_PERIOD
            sim.step()
            now = sim.time
            if now >= nxt["odometry"] - TIME_EPS:
                odo = sim.odometry(VIEWER, ODOMETRY_PERIOD)
                self.vision.odometry(now, odo.vx, odo.vy, odo.w, odo.robot_stuck)
                nxt["odometry"] += ODOMETRY_PERIOD
            if now >= nxt["inertial"] - TIME_EPS:
                yaw = sim.inertial_heading(VIEWER, INERTIAL_PERIOD).yaw + self.heading_offset
                self.vision.inertial(now, wrap_angle(yaw))
                nxt["inertial"] += INERTIAL_PERIOD
            if now >= nxt["camera"] - TIME_EPS:
                out.append(self._frame(now))
                nxt["camera"] += CAMERA_PERIOD
                if stop is not None and stop(out[-1]):
                    break
        return out

    def _frame(self, now: float) -> FrameRecord:
        start = time.perf_counter()
        image = self.sim.camera_frame(VIEWER).image
        render = time.perf_counter() - start
        frame = self.vision.process(now, image)
        truth = self.viewer_pose()
        b = self.sim.world.ball_state()
        bx, by = truth.to_body(b.x, b.y)
        ball = (frame.ball.x, frame.ball.y) if frame.ball is not None else None
        return FrameRecord(now, truth, frame.estimate.pose, frame.estimate.localized, dict(frame.timings), render,
                           ball, (bx, by, b.z))


def tracking_command(rig: VisionRig, reference: Callable[[float], Reference]) -> Command:
    """A controller for ``rig.run``: the reference's velocity plus a pull towards it, from the true pose."""

    def command(t: float) -> Velocity:
        ref, s = reference(t), rig.sim.world.robot_state(VIEWER)
        vx = ref.vx + POSITION_GAIN * (ref.x - s.x)
        vy = ref.vy + POSITION_GAIN * (ref.y - s.y)
        bx, by = rotate(vx, vy, -s.theta)
        return bx, by, ref.w + HEADING_GAIN * wrap_angle(ref.theta - s.theta)

    return command


# --- the paths ------------------------------------------------------------------------------------------------
class FigureEight:
    """A lemniscate of Gerono, x = a sin s, y = b sin 2s (extent 2a x 2b [m]), driven facing along it at
    ``speed`` [m/s] after speeding up at ``acceleration`` [m/s^2] from rest at the centre spot."""

    def __init__(self, size: tuple[float, float], speed: float, acceleration: float):
        self.a, self.b = size[0] / 2.0, size[1] / 2.0
        self.speed, self.acceleration = speed, acceleration
        self._s = np.linspace(0.0, 2.0 * math.pi, 8193)
        dx, dy = self._tangent(self._s)
        step = np.hypot(dx, dy)
        self._length = np.concatenate([[0.0], np.cumsum(0.5 * (step[1:] + step[:-1]) * np.diff(self._s))])

    def _tangent(self, s: np.ndarray | float) -> tuple[Any, Any]:
        return self.a * np.cos(s), 2.0 * self.b * np.cos(2.0 * s)

    def points(self, count: int = 2000) -> np.ndarray:
        s = np.linspace(0.0, 2.0 * math.pi, count)
        return np.column_stack([self.a * np.sin(s), self.b * np.sin(2.0 * s)])

    def __call__(self, t: float) -> Reference:
        ramp = self.speed / self.acceleration
        if t < ramp:
            along, speed = 0.5 * self.acceleration * t * t, self.acceleration * t
        else:
            along, speed = 0.5 * self.speed * ramp + self.speed * (t - ramp), self.speed
        s = float(np.interp(along % self._length[-1], self._length, self._s))
        dx, dy = self._tangent(s)
        ddx, ddy = -self.a * math.sin(s), -4.0 * self.b * math.sin(2.0 * s)
        norm = math.hypot(dx, dy)
        curvature = (dx * ddy - dy * ddx) / norm**3
        return Reference(self.a * math.sin(s), self.b * math.sin(2.0 * s), math.atan2(dy, dx),
                         speed * dx / norm, speed * dy / norm, speed * curvature)


class Polyline:
    """Straight lines through ``corners`` (world frame [m]), closed, ``laps`` times, heading fixed at
    ``heading``; each line from rest to rest at ``speed`` [m/s] with ``acceleration`` [m/s^2]."""

    def __init__(self, corners: Sequence[tuple[float, float]], laps: int, speed: float, acceleration: float,
                 heading: float = 0.0):
        ring = list(corners) * laps + [corners[0]]
        self.legs = list(zip(ring[:-1], ring[1:]))
        self.speed, self.acceleration, self.heading = speed, acceleration, heading
        ramp = speed / acceleration
        # A leg too short to reach the speed is a triangle: up to sqrt(a L) and down again.
        self.times = [2.0 * math.sqrt(length / acceleration) if length <= speed * ramp
                      else 2.0 * ramp + (length - speed * ramp) / speed
                      for length in (math.dist(a, b) for a, b in self.legs)]

    @property
    def duration(self) -> float:
        return sum(self.times)

    def points(self, step: float = 0.05) -> np.ndarray:
        """Points along the lines, ``step`` [m] apart or closer."""
        return np.vstack([np.linspace(a, b, max(2, math.ceil(math.dist(a, b) / step))) for a, b in self.legs])

    def __call__(self, t: float) -> Reference:
        k = 0
        while k < len(self.legs) - 1 and t > self.times[k]:
            t, k = t - self.times[k], k + 1
        (a, b), leg = self.legs[k], self.times[k]
        t = min(max(t, 0.0), leg)  # at rest at the start before it, at the end after the last leg
        length, peak = math.dist(a, b), min(self.speed, self.acceleration * leg / 2.0)
        ramp = peak / self.acceleration
        if t < ramp:
            along, speed = 0.5 * self.acceleration * t * t, self.acceleration * t
        elif t < leg - ramp:
            along, speed = 0.5 * peak * ramp + peak * (t - ramp), peak
        else:
            left = leg - t
            along, speed = length - 0.5 * self.acceleration * left * left, self.acceleration * left
        ux, uy = (b[0] - a[0]) / length, (b[1] - a[1]) / length
        return Reference(a[0] + along * ux, a[1] + along * uy, self.heading, speed * ux, speed * uy, 0.0)


# --- placing robots -------------------------------------------------------------------------------------------
def free_spots(rng: np.random.Generator, count: int, field: FieldGeometry, taken: Sequence[tuple[float, float]],
               clearance: float, margin: float = 0.4,
               allowed: Callable[[float, float], bool] | None = None) -> list[tuple[float, float]]:
    """``count`` random points inside the lines (less ``margin`` [m]), ``clearance`` [m] from ``taken`` and
    each other, where ``allowed`` says so."""
    spots: list[tuple[float, float]] = []
    for _ in range(10_000):
        if len(spots) == count:
            return spots
        x = float(rng.uniform(-field.half_length + margin, field.half_length - margin))
        y = float(rng.uniform(-field.half_width + margin, field.half_width - margin))
        if all(math.dist((x, y), p) >= clearance for p in (*taken, *spots)) and (allowed is None or allowed(x, y)):
            spots.append((x, y))
    raise RuntimeError(f"found only {len(spots)} of {count} free spots {clearance} m apart")


def scatter_others(rig: VisionRig, rng: np.random.Generator, taken: Sequence[tuple[float, float]],
                   clearance: float = 1.0, allowed: Callable[[float, float], bool] | None = None) -> None:
    """Put every other robot on a free spot, random heading, at rest."""
    spots = free_spots(rng, len(rig.others), rig.world.field, taken, clearance, allowed=allowed)
    for name, (x, y) in zip(rig.others, spots):
        rig.place(name, x, y, float(rng.uniform(-math.pi, math.pi)))


def circle_slowly(rig: VisionRig, rng: np.random.Generator) -> None:
    """Every other robot drives a small circle (radius 0.2-0.3 m, 0.2-0.4 m/s) round its spot."""
    for name in rig.others:
        speed, radius = float(rng.uniform(0.2, 0.4)), float(rng.uniform(0.2, 0.3))
        rig.drive[name] = (speed, 0.0, float(rng.choice([-1.0, 1.0])) * speed / radius)


# --- statistics -----------------------------------------------------------------------------------------------
def _r(x: float | None, digits: int = 4) -> float | None:
    return None if x is None or not math.isfinite(x) else round(float(x), digits)


def summary(values: Sequence[float], scale: float = 1.0, digits: int = 4) -> dict[str, Any]:
    """count, mean, median, p90, p95 and max of ``values`` times ``scale`` (None when there are none)."""
    v = np.asarray(values, dtype=float) * scale
    if v.size == 0:
        return {"count": 0, "mean": None, "median": None, "p90": None, "p95": None, "max": None}
    return {"count": int(v.size), "mean": _r(v.mean(), digits), "median": _r(np.median(v), digits),
            "p90": _r(np.percentile(v, 90), digits), "p95": _r(np.percentile(v, 95), digits),
            "max": _r(v.max(), digits)}


def localization_figures(frames: Sequence[FrameRecord]) -> dict[str, Any]:
    """Errors over the localized frames (position [m], heading [deg]) and the share localized."""
    tracked = [f for f in frames if f.localized]
    return {"frames": len(frames), "localized_share": _r(len(tracked) / len(frames), 4) if frames else None,
            "position_error_m": summary([f.position_error for f in tracked]),
            "heading_error_deg": summary([f.heading_error for f in tracked], math.degrees(1.0), 3)}


def moving_targets(figures: dict[str, Any]) -> dict[str, Any]:
    error = figures["position_error_m"]
    figures.update({"target_position_error_mean_m": TARGET_MOVING_MEAN_M,
                    "target_position_error_p95_m": TARGET_MOVING_P95_M,
                    "met": error["count"] > 0 and error["mean"] <= TARGET_MOVING_MEAN_M
                    and error["p95"] <= TARGET_MOVING_P95_M})
    return figures


# --- 1 and 3: the figure of eight, the pipeline's time -----------------------------------------------------------
def away_from(points: np.ndarray, clearance: float) -> Callable[[float, float], bool]:
    """Whether a point [m] lies at least ``clearance`` [m] from every one of ``points`` (N x 2)."""
    return lambda x, y: bool(np.min(np.hypot(points[:, 0] - x, points[:, 1] - y)) >= clearance)


def start_drive(rig: VisionRig, rng: np.random.Generator, path: Callable[[float], Reference],
                off_path: Callable[[float, float], bool], ball: bool = True) -> Command:
    """Put the viewer at rest at the path's start, its pose known (as at kick-off), the ball (with ``ball``) and
    the others where ``off_path`` allows; return the controller that drives the path from now."""
    start = path(0.0)
    rig.place(VIEWER, start.x, start.y, start.theta)
    taken = free_spots(rng, 1, rig.world.field, [], 0.0, allowed=off_path) if ball else []
    if taken:
        rig.place_ball(*taken[0])
    scatter_others(rig, rng, taken, allowed=off_path)
    rig.vision.reset(rig.viewer_pose())
    begin = rig.sim.time
    return tracking_command(rig, lambda t: path(t - begin))


def bench_figure_eight(rig: VisionRig, rng: np.random.Generator, seconds: float,
                       progress: Callable[[str], None]) -> list[FrameRecord]:
    """Drive the figure of eight for ``seconds`` among the others circling slowly; return the frames."""
    path = FigureEight(EIGHT_SIZE, EIGHT_SPEED, EIGHT_ACCELERATION)
    command = start_drive(rig, rng, path, away_from(path.points(), EIGHT_CLEARANCE))
    circle_slowly(rig, rng)
    frames: list[FrameRecord] = []
    for done in range(10, math.ceil(seconds) + 10, 10):  # in 10 s pieces, for the progress lines
        frames += rig.run(min(seconds, done) - (done - 10), command=command)
        progress(f"figure of eight {min(seconds, done):g}/{seconds:g} s")
    rig.drive.clear()
    return frames


def pipeline_figures(frames: Sequence[FrameRecord]) -> dict[str, Any]:
    tracked = [f for f in frames if f.localized]
    stages = {stage: summary([f.timings[stage] for f in tracked], 1e3, 3) for stage in STAGES}
    total = stages["total"]
    return {"frames_tracking": len(tracked), "stages_ms": stages, "total_ms": total,
            "render_ms": summary([f.render for f in frames], 1e3, 3),
            "cv2_threads": cv2.getNumThreads(), "target_total_median_ms": TARGET_PIPELINE_MEDIAN_MS,
            "met": total["median"] is not None and total["median"] <= TARGET_PIPELINE_MEDIAN_MS}


# --- 2: standing still ---------------------------------------------------------------------------------------------
def rig_positions(rig: VisionRig) -> list[tuple[float, float]]:
    """Where the other robots stand (world frame [m])."""
    return [(s.x, s.y) for s in (rig.sim.world.robot_state(n) for n in rig.others)]


def bench_standing(rig: VisionRig, rng: np.random.Generator, d: Durations, progress: Callable[[str], None]) -> dict:
    per_pose, measured = [], []
    for k, (x, y, theta) in enumerate(STANDING_POSES[:d.standing_poses]):
        progress(f"standing {k + 1}/{d.standing_poses} at ({x:g}, {y:g}, {math.degrees(theta):.0f} deg)")
        rig.place(VIEWER, x, y, theta)
        scatter_others(rig, rng, [(x, y)])
        rig.place_ball(*free_spots(rng, 1, rig.world.field, [(x, y), *rig_positions(rig)], 0.6)[0])
        rig.vision.reset()
        begin = rig.sim.time
        frames = rig.run(d.standing_seconds)
        first = next((f.t - begin for f in frames if f.localized), None)
        settled = [f for f in frames if f.t - begin >= SETTLE]
        measured += settled
        per_pose.append({"pose": [x, y, _r(theta)], "first_localized_s": _r(first, 3),
                         **localization_figures(settled)})
    figures = localization_figures(measured)
    error = figures["position_error_m"]
    return {"settle_seconds": SETTLE, "seconds_per_pose": d.standing_seconds, **figures, "poses": per_pose,
            "target_position_error_mean_m": TARGET_STANDING_MEAN_M,
            "met": error["count"] > 0 and error["mean"] <= TARGET_STANDING_MEAN_M}


# --- 4: global localization ----------------------------------------------------------------------------------------
def bench_global(rig: VisionRig, rng: np.random.Generator, d: Durations, progress: Callable[[str], None]) -> dict:
    field = rig.world.field
    needed: list[int | None] = []
    wrong, cases = 0, []
    for k in range(d.global_poses):
        (x, y), = free_spots(rng, 1, field, [], 0.0, margin=0.3)
        theta = float(rng.uniform(-math.pi, math.pi))
        rig.place(VIEWER, x, y, theta)
        scatter_others(rig, rng, [(x, y)])
        rig.place_ball(*free_spots(rng, 1, field, [(x, y), *rig_positions(rig)], 0.6)[0])
        rig.heading_offset = float(rng.uniform(-GLOBAL_HEADING_OFFSET, GLOBAL_HEADING_OFFSET))
        rig.vision.reset()
        frames = rig.run(frames=d.global_max_frames,
                         stop=lambda f: f.localized and f.position_error < CONVERGED_ERROR)
        done = frames[-1].localized and frames[-1].position_error < CONVERGED_ERROR
        off = [f.position_error for f in frames if f.localized and f.position_error > WRONG_ERROR]
        wrong += bool(off)
        needed.append(len(frames) if done else None)
        cases.append({"pose": [_r(x, 3), _r(y, 3), _r(theta, 3)], "frames": len(frames) if done else None,
                      "wrong_max_error_m": _r(max(off), 3) if off else None})
        if (k + 1) % 10 == 0 or k + 1 == d.global_poses:
            progress(f"global localization {k + 1}/{d.global_poses}")
    converged = [n for n in needed if n is not None]
    within = sum(1 for n in converged if n <= TARGET_GLOBAL_FRAMES)
    edges = sorted({e for e in (1, 2, 3, 5, 10, 20, 30, 60) if e < d.global_max_frames} | {d.global_max_frames})
    histogram = {f"<={e}": sum(1 for n in converged if n <= e) for e in edges}
    share = within / d.global_poses
    return {"poses": d.global_poses, "max_frames": d.global_max_frames, "converged_error_m": CONVERGED_ERROR,
            "converged": len(converged), "converged_within_1s": within, "converged_within_1s_share": _r(share),
            "not_converged": d.global_poses - len(converged), "frames_needed": summary(converged, digits=1),
            "frames_needed_cumulative": histogram, "wrong_error_m": WRONG_ERROR, "wrong_convergences": wrong,
            "cases": cases, "target_frames": TARGET_GLOBAL_FRAMES, "target_share": TARGET_GLOBAL_SHARE,
            "met": share >= TARGET_GLOBAL_SHARE}


# --- 5: the ball --------------------------------------------------------------------------------------------------
def _overlap(a: float, half_a: float, b: float, half_b: float) -> bool:
    return abs(wrap_angle(a - b)) < half_a + half_b


def ball_hidden(rig: VisionRig, ball: tuple[float, float, float]) -> str | None:
    """What hides the ball (body frame centre ``ball``) wholly or partly from the viewer: "robot" (nearer
    and as tall as the viewpoint: it blacks out its wedge to the rim), "strut" (the mirror holder), or None."""
    me, r = rig.viewer_pose(), rig.world.ball.radius
    distance = math.hypot(ball[0], ball[1])
    bearing, half = math.atan2(ball[1], ball[0]), math.asin(min(1.0, r / distance))
    radius = rig.world.robot.radius
    for x, y in rig_positions(rig):
        bx, by = me.to_body(x, y)
        d = math.hypot(bx, by)
        if d - radius < distance and _overlap(bearing, half, math.atan2(by, bx), math.asin(min(1.0, radius / d))):
            return "robot"
    camera, mirror = rig.sim.config.sensors.camera, rig.vision.mirror
    if camera.strut_width > 0.0:
        near_px = float(mirror.radius(max(distance - r, mirror.min_distance)))
        strut_half = math.asin(min(1.0, camera.strut_width / 2.0 / near_px))
        if any(_overlap(bearing, half, math.radians(a), strut_half) for a in camera.strut_angles_deg):
            return "strut"
    return None


def bench_ball(rig: VisionRig, rng: np.random.Generator, d: Durations, progress: Callable[[str], None]) -> dict:
    field, arena = rig.world.field, rig.world.field.border - 0.2
    rows: list[dict[str, Any]] = []
    for k in range(d.ball_placements):
        want = float(rng.uniform(*BALL_DISTANCE_RANGE))
        while True:
            (x, y), = free_spots(rng, 1, field, [], 0.0)
            theta, direction = (float(a) for a in rng.uniform(-math.pi, math.pi, 2))
            bx, by = x + want * math.cos(direction), y + want * math.sin(direction)
            if field.is_inside(bx, by, arena):
                break
        rig.place(VIEWER, x, y, theta)
        rig.place_ball(bx, by)
        spots = free_spots(rng, len(rig.others), field, [(x, y), (bx, by)], 0.8, margin=0.3)
        for name, (ox, oy) in zip(rig.others, spots):
            rig.place(name, ox, oy, float(rng.uniform(-math.pi, math.pi)))
        rig.vision.reset(rig.viewer_pose())
        frame = rig.run(frames=1)[0]
        distance = math.hypot(frame.ball_truth[0], frame.ball_truth[1])
        error = math.dist(frame.ball, frame.ball_truth[:2]) if frame.ball is not None else None
        rows.append({"distance": distance, "hidden": ball_hidden(rig, frame.ball_truth), "error": error})
        if (k + 1) % 100 == 0 or k + 1 == d.ball_placements:
            progress(f"ball {k + 1}/{d.ball_placements}")
    return ball_figures(rows)


def ball_figures(rows: Sequence[dict[str, Any]]) -> dict[str, Any]:
    """Per distance bin and up to TARGET_BALL_RANGE: detection rate (visible balls) and error in % of distance."""

    def figures(part: Sequence[dict[str, Any]]) -> dict[str, Any]:
        visible = [r for r in part if r["hidden"] is None]
        seen = [r for r in visible if r["error"] is not None]
        percent = [100.0 * r["error"] / r["distance"] for r in seen]
        hidden_seen = sum(1 for r in part if r["hidden"] is not None and r["error"] is not None)
        return {"placements": len(part), "visible": len(visible), "detected": len(seen),
                "detection_rate": _r(len(seen) / len(visible)) if visible else None,
                "hidden_by_robot": sum(1 for r in part if r["hidden"] == "robot"),
                "behind_strut": sum(1 for r in part if r["hidden"] == "strut"),
                "hidden_but_detected": hidden_seen,
                "error_percent": summary(percent, digits=2),
                "error_m": summary([r["error"] for r in seen], digits=4)}

    bins = {f"{lo:g}-{hi:g}m": figures([r for r in rows if lo <= r["distance"] < hi]) for lo, hi in DISTANCE_BINS}
    near = figures([r for r in rows if r["distance"] < TARGET_BALL_RANGE])
    rate, p95 = near["detection_rate"], near["error_percent"]["p95"]
    return {"bins": bins, f"up_to_{TARGET_BALL_RANGE:g}m": near, "all": figures(rows),
            "target_detection_rate": TARGET_BALL_RATE, "target_error_percent_p95": TARGET_BALL_ERROR_PERCENT,
            "target_range_m": TARGET_BALL_RANGE,
            "met": rate is not None and rate >= TARGET_BALL_RATE and p95 is not None
            and p95 <= TARGET_BALL_ERROR_PERCENT,
            "samples": [[_r(r["distance"], 3), r["hidden"], _r(r["error"], 4)] for r in rows]}


def bench_false_detections(rig: VisionRig, rng: np.random.Generator, seconds: float) -> dict:
    """Frames with a ball detected while no ball is in view (high above): the robot drives the figure of eight
    at FALSE_DETECTION_SPEED among the others circling slowly."""
    path = FigureEight(EIGHT_SIZE, FALSE_DETECTION_SPEED, EIGHT_ACCELERATION)
    follow = start_drive(rig, rng, path, away_from(path.points(), EIGHT_CLEARANCE), ball=False)
    circle_slowly(rig, rng)

    def command(t: float) -> Velocity:
        rig.place_ball(0.0, 0.0, BALL_OUT_OF_VIEW_Z)  # held up there (it falls a few mm between commands)
        return follow(t)

    frames = rig.run(seconds, command=command)
    rig.drive.clear()
    detections = sum(1 for f in frames if f.ball is not None)
    minutes = len(frames) * CAMERA_PERIOD / 60.0
    return {"frames": len(frames), "ball_height_m": BALL_OUT_OF_VIEW_Z, "speed_m_s": FALSE_DETECTION_SPEED,
            "false_detections": detections, "per_minute": _r(detections / minutes, 2) if minutes else None}


# --- 6: Fig. 11 -------------------------------------------------------------------------------------------------
def bench_fig11(rig: VisionRig, rng: np.random.Generator, d: Durations) -> tuple[list[FrameRecord], dict]:
    """Drive a rectangle along straight lines among robots standing off it; return the frames and figures."""
    hx, hy = d.rectangle[0] / 2.0, d.rectangle[1] / 2.0
    path = Polyline([(-hx, -hy), (hx, -hy), (hx, hy), (-hx, hy)], d.rectangle_laps, LINE_SPEED, LINE_ACCELERATION)
    frames = rig.run(path.duration + 0.5, command=start_drive(rig, rng, path, away_from(path.points(), 1.0)))
    figures = moving_targets(localization_figures(frames))
    return frames, {"rectangle_m": list(d.rectangle), "laps": d.rectangle_laps, "speed_m_s": LINE_SPEED,
                    "heading_rad": path.heading, "seconds": _r(path.duration, 2), **figures,
                    "note": "held to the figure of eight's targets"}


# --- the plots, the summary, main ------------------------------------------------------------------------------
def draw_traces(ax: Any, frames: Sequence[FrameRecord], field: FieldGeometry, title: str) -> None:
    """The field's white markings (thin grey), the true trace and the estimated one (localized frames) on ``ax``."""
    for (x0, y0), (x1, y1) in field.line_segments():
        ax.plot([x0, x1], [y0, y1], color="0.6", lw=0.8, zorder=0)
    for arc in field.arcs():
        a = np.linspace(arc.start, arc.end, 60)
        ax.plot(arc.x + arc.radius * np.cos(a), arc.y + arc.radius * np.sin(a), color="0.6", lw=0.8, zorder=0)
    ax.plot([f.truth.x for f in frames], [f.truth.y for f in frames], color="tab:blue", lw=1.5, label="true")
    tracked = [f for f in frames if f.localized]
    ax.plot([f.estimate.x for f in tracked], [f.estimate.y for f in tracked], color="tab:red", lw=0.8, ls="--",
            label="estimated")
    mean = float(np.mean([f.position_error for f in tracked])) if tracked else math.nan
    ax.set(aspect="equal", xlim=(-field.half_length - 0.5, field.half_length + 0.5), xlabel="x [m]",
           ylim=(-field.half_width - 0.5, field.half_width + 0.5), ylabel="y [m]")
    ax.set_title(f"{title} (mean error {100.0 * mean:.1f} cm)", fontsize=9)
    ax.legend(loc="upper right", fontsize=7)


def plot_localization(eight: Sequence[FrameRecord], fig11: Sequence[FrameRecord], field: FieldGeometry,
                      path: Path) -> None:
    fig = plt.figure(figsize=(12, 8))
    ax = fig.add_subplot(2, 1, 1)
    times = [f.t - eight[0].t for f in eight]
    ax.plot(times, [100.0 * f.position_error if f.localized else math.nan for f in eight], color="tab:blue",
            lw=0.8, label="position error [cm]")
    ax.axhline(100.0 * TARGET_MOVING_MEAN_M, color="tab:green", ls="--", lw=0.8, label="target mean")
    ax.axhline(100.0 * TARGET_MOVING_P95_M, color="tab:red", ls="--", lw=0.8, label="target p95")
    lost = [t for t, f in zip(times, eight) if not f.localized]
    if lost:
        ax.plot(lost, [0.0] * len(lost), "k|", ms=8, label="not localized")
    ax.set(xlabel="time [s]", ylabel="position error [cm]")
    ax.set_title(f"Figure of eight at {EIGHT_SPEED:g} m/s among robots: localization error", fontsize=10)
    ax.legend(loc="upper left", fontsize=7)
    twin = ax.twinx()
    twin.plot(times, [math.degrees(f.heading_error) if f.localized else math.nan for f in eight], color="tab:orange",
              lw=0.6, alpha=0.7)
    twin.set_ylabel("heading error [deg]", color="tab:orange")
    draw_traces(fig.add_subplot(2, 2, 3), eight, field, "Figure of eight")
    draw_traces(fig.add_subplot(2, 2, 4), fig11, field, f"Fig. 11: straight lines at {LINE_SPEED:g} m/s")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def plot_ball(ball: dict[str, Any], path: Path) -> None:
    fig, (ax, rate) = plt.subplots(1, 2, figsize=(12, 4.5))
    for hidden, colour, label in ((None, "tab:blue", "visible"), ("robot", "tab:gray", "partly hidden by a robot"),
                                  ("strut", "tab:purple", "behind a strut")):
        part = [(d, 100.0 * e / d) for d, h, e in ball["samples"] if h == hidden and e is not None]
        if part:
            ax.scatter(*zip(*part), s=8, color=colour, label=label)
    ax.axhline(TARGET_BALL_ERROR_PERCENT, color="tab:red", ls="--", lw=0.8, label="target (p95 up to 6 m)")
    ax.set(xlabel="ball distance [m]", ylabel="position error [% of distance]", yscale="log")
    ax.set_title("Ball position error against distance", fontsize=10)
    ax.legend(fontsize=7)
    names = list(ball["bins"])
    values = [100.0 * (ball["bins"][n]["detection_rate"] or 0.0) for n in names]
    for bar, value in zip(rate.bar(names, values, color="tab:blue"), values):
        rate.annotate(f"{value:.1f} %", (bar.get_x() + bar.get_width() / 2, value), ha="center", va="bottom",
                      fontsize=8)
    rate.axhline(100.0 * TARGET_BALL_RATE, color="tab:red", ls="--", lw=0.8, label="target (up to 6 m)")
    rate.set(ylim=(0.0, 105.0), xlabel="ball distance", ylabel="detection rate of visible balls [%]")
    rate.set_title("Ball detection rate", fontsize=10)
    rate.legend(loc="lower left", fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def report(results: dict[str, Any]) -> str:
    """The figures against their targets, one line each."""

    def verdict(part: dict[str, Any]) -> str:
        return "met" if part["met"] else "NOT met"

    p, s, e, g, b, f = (results[k] for k in ("pipeline_time", "standing", "figure_eight", "global_localization",
                                             "ball", "fig11"))
    near = b[f"up_to_{TARGET_BALL_RANGE:g}m"]
    m = results["figure_eight_miscalibrated_mirror"]
    lines = [
        f"pipeline: median {p['total_ms']['median']} ms, p90 {p['total_ms']['p90']} ms (target median <= "
        f"{TARGET_PIPELINE_MEDIAN_MS:g} ms: {verdict(p)}); rendering median {p['render_ms']['median']} ms",
        f"standing: mean error {s['position_error_m']['mean']} m, heading {s['heading_error_deg']['mean']} deg, "
        f"localized {s['localized_share']} (target <= {TARGET_STANDING_MEAN_M} m: {verdict(s)})",
        f"figure of eight: mean {e['position_error_m']['mean']} m, p95 {e['position_error_m']['p95']} m, heading "
        f"mean {e['heading_error_deg']['mean']} deg p95 {e['heading_error_deg']['p95']} deg, localized "
        f"{e['localized_share']} ({verdict(e)})",
        f"figure of eight, mirror {100 * MIRROR_SCALE_ERROR:g} % and {MIRROR_CENTRE_ERROR[0]:g} px off its "
        f"calibration: mean {m['position_error_m']['mean']} m, p95 {m['position_error_m']['p95']} m (no target)",
        f"global localization: {g['converged_within_1s']}/{g['poses']} within 1 s, median "
        f"{g['frames_needed']['median']} frames, {g['wrong_convergences']} wrong ({verdict(g)})",
        f"ball up to {TARGET_BALL_RANGE:g} m: rate {near['detection_rate']}, error p95 "
        f"{near['error_percent']['p95']} % ({verdict(b)}); false detections "
        f"{b['false_detections']['per_minute']} per minute",
        f"Fig. 11: mean {f['position_error_m']['mean']} m, p95 {f['position_error_m']['p95']} m ({verdict(f)})",
    ]
    return "\n".join(lines)


def run(args: argparse.Namespace) -> dict[str, Any]:
    """Every scenario, in order, each in a simulator of its own; returns the results and draws the plots."""
    d = QUICK if args.quick else FULL
    world = load_world(args.field)
    params = load_yaml(OmniVisionParams, VISION_CONFIG / "omni_vision.yaml")
    table = ColorTable.load(VISION_CONFIG / "colors_sim.npz")
    cpu = None if args.cpu < 0 else args.cpu
    results: dict[str, Any] = {
        "machine": machine(cpu), "quick": args.quick, "seed": args.seed, "field": args.field,
        "durations": asdict(d),
        "targets": {"pipeline_total_median_ms": TARGET_PIPELINE_MEDIAN_MS,
                    "standing_position_error_mean_m": TARGET_STANDING_MEAN_M,
                    "moving_position_error_mean_m": TARGET_MOVING_MEAN_M,
                    "moving_position_error_p95_m": TARGET_MOVING_P95_M, "global_frames": TARGET_GLOBAL_FRAMES,
                    "global_share": TARGET_GLOBAL_SHARE, "ball_detection_rate": TARGET_BALL_RATE,
                    "ball_error_percent_p95": TARGET_BALL_ERROR_PERCENT, "ball_range_m": TARGET_BALL_RANGE}}

    def progress(line: str) -> None:
        print(f"[bench] vision: {line}", flush=True)

    def rig(others: int, scenario: int, miscalibrated: bool = False) -> tuple[VisionRig, np.random.Generator]:
        return (VisionRig(world, params, table, others, args.seed, miscalibrated),
                np.random.default_rng(np.random.SeedSequence([args.seed, scenario])))

    started = time.perf_counter()
    threads = cv2.getNumThreads()
    cv2.setNumThreads(1)
    try:
        with pinned(cpu):
            eight = bench_figure_eight(*rig(5, 3), d.eight_seconds, progress)
            results["pipeline_time"] = pipeline_figures(eight)
            results["figure_eight"] = {"size_m": list(EIGHT_SIZE), "speed_m_s": EIGHT_SPEED,
                                       "seconds": d.eight_seconds, **moving_targets(localization_figures(eight))}
            off = bench_figure_eight(*rig(5, 3, miscalibrated=True), d.eight_seconds, progress)
            results["figure_eight_miscalibrated_mirror"] = {
                "mirror_scale_error": MIRROR_SCALE_ERROR, "mirror_centre_error_px": list(MIRROR_CENTRE_ERROR),
                **localization_figures(off)}
            results["standing"] = bench_standing(*rig(5, 2), d, progress)
            results["global_localization"] = bench_global(*rig(3, 4), d, progress)
            results["ball"] = bench_ball(*rig(5, 5), d, progress)
            progress(f"false detections, {d.false_detection_seconds:g} s of sim time without a ball in view")
            results["ball"]["false_detections"] = bench_false_detections(*rig(5, 6), d.false_detection_seconds)
            progress(f"Fig. 11: a {d.rectangle[0]:g} x {d.rectangle[1]:g} m rectangle at {LINE_SPEED:g} m/s")
            fig11, results["fig11"] = bench_fig11(*rig(5, 7), d)
    finally:
        cv2.setNumThreads(threads)
    results["machine"]["load_average_end"] = [_r(x, 2) for x in os.getloadavg()]
    results["machine"]["cpu_pressure_some_avg60_percent_end"] = cpu_pressure()
    results["wall_seconds_total"] = _r(time.perf_counter() - started, 1)
    plot_localization(eight, fig11, world.field, args.out / "vision_localization.png")
    plot_ball(results["ball"], args.out / "vision_ball.png")
    return results


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--quick", action="store_true", help="short versions of every scenario (about 10 s)")
    parser.add_argument("--field", default="18x12", help="18x12, 22x14 or a world YAML")
    parser.add_argument("--cpu", type=int, default=max(os.sched_getaffinity(0)),
                        help="the core the measurements are pinned to (-1: no pinning)")
    args = parser.parse_args(argv)
    if args.seed < 0:
        parser.error(f"--seed must not be negative, got {args.seed}")
    args.out.mkdir(parents=True, exist_ok=True)
    results = run(args)
    (args.out / "vision.json").write_text(strict_json(results, indent=2))
    print(report(results))
    print(f"figures: {args.out / 'vision.json'}, {args.out / 'vision_localization.png'}, "
          f"{args.out / 'vision_ball.png'}")
    return 0
