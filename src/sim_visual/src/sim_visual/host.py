"""The simulator node's core, without ROS: the simulator hosted for many callers, stepped on one schedule and kept
at pace with the wall clock.

Requires: ``SimNodeParams`` (with the world). Provides:

- ``RobotSensors``: which sensors a robot has: percepts given (OmniVisionInfo, and a goalie's 3-D ball) or, for
  the robots of ``vision``, its omni camera, odometry, IMU and truth, plus a goalie's two RGB-D cameras or any
  other robot's front camera.
- ``SensorSchedule``: what one physics step is due to give (clock, model states, percepts, each camera at its own
  phase of the frame period, odometry, IMU), each ``Periodic`` in sim time. The lockstep engine uses its percept
  and model-state clocks.
- ``Pacer``: holds sim time at ``factor`` times wall time (0: as fast as possible), catching up at most
  ``MAX_LAG`` and never sleeping longer than ``MAX_SLEEP`` at a time, so that a new factor takes effect at once.
- ``SimHost``: the ``Simulator`` behind one lock for the node's threads: robots' commands (refusals and clamps
  counted by a ``RejectionReporter``, a line every few seconds), services (model state, spawn, delete, reset,
  switch ends), dynamic reconfigure, and ``step()`` -> ``Tick``, the step's events and every due output as data.
  The node turns a ``Tick`` into messages, outside the lock.
"""

from __future__ import annotations

import dataclasses
import math
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from nubot_common import NubotCommonError
from nubot_common.commands import KickKind
from nubot_common.kinematics import WheelLayout
from nubot_common.percepts import Ball3dPercept, RobotView
from nubot_common.reconfigure import ReconfigureParam
from nubot_common.rejections import RejectionReporter
from nubot_common.schedule import Periodic
from sim_visual import SimVisualError
from sim_visual.odometry import ImuReading, OdometryReading
from sim_visual.omni_camera import RenderedFrame
from sim_visual.params import (
    NOISE_UPPER_BOUNDS,
    PLUGIN_UPPER_BOUNDS,
    REAL_TIME_FACTOR_MAX,
    NoiseParams,
    PluginParams,
    RobotSpawn,
    SimNodeParams,
)
from sim_visual.rgbd_camera import RgbdFrame
from sim_visual.simulator import BallCaptured, BallKicked, GoalScored, SimEvent, Simulator
from sim_visual.world import BallState, RobotState

CAMERA_PHASES = 4  # the cameras render at this many phases of the frame period, in turn
MAX_LAG = 0.5  # [s, wall] behind schedule before the pacing gives up catching up
MAX_SLEEP = 0.1  # [s, wall] the pacing looks at the real-time factor again at least this often
REJECTION_REPORT_INTERVAL = 5.0  # [s, wall] between two log lines about one robot's refused commands
PLUGIN_NAMES = frozenset(f.name for f in dataclasses.fields(PluginParams))
NOISE_NAMES = frozenset(f.name for f in dataclasses.fields(NoiseParams))
RECONFIGURABLE = PLUGIN_NAMES | NOISE_NAMES | {"real_time_factor"}


@dataclass(frozen=True)
class RobotSensors:
    """The sensors of one simulated robot."""

    camera: bool  # sees through the omni camera (omni_vision makes its percepts), with odometry, IMU and truth
    labels: bool  # its camera also gives each pixel's colour class
    ball3d: bool  # a goalie given percepts: also its 3-D ball (kinect_ball's output)
    rgbd: bool  # a goalie seeing through cameras: its two RGB-D cameras
    front: bool  # any other robot seeing through cameras: its front camera

    @classmethod
    def of(cls, params: SimNodeParams, name: str) -> RobotSensors:
        camera, goalie = name in params.vision_robots, params.is_goalie(name)
        return cls(camera, camera and params.camera_labels, goalie and not camera, goalie and camera,
                   camera and not goalie)


@dataclass(frozen=True)
class Due:
    """What one physics step is due to give."""

    clock: bool = False
    states: bool = False
    percepts: bool = False  # the robots given percepts (not their cameras)
    cameras: tuple[str, ...] = ()  # the robots whose camera frame is due
    odometry: bool = False
    imu: bool = False


class SensorSchedule:
    """The outputs' due times in sim time. Cameras are not synchronised: each renders at its own phase of the frame
    period, which spreads the rendering and the vision nodes' work over the period instead of piling it up."""

    def __init__(self, params: SimNodeParams, start: float = 0.0):
        self.frame_period = 1.0 / params.vision_rate
        self.odometry_period, self.imu_period = 1.0 / params.odometry_rate, 1.0 / params.imu_rate
        self.vision = Periodic(self.frame_period, start)
        self.states = Periodic(1.0 / params.model_states_rate, start)
        self.clock = Periodic(1.0 / params.clock_rate, start)
        self.odometry = Periodic(self.odometry_period, start)
        self.imu = Periodic(self.imu_period, start)
        self._cameras: dict[str, Periodic] = {}
        self._added = 0  # cameras ever added: the next one's phase
        self._states_time = -math.inf  # one model-states message per sim time

    def add_camera(self, name: str, now: float) -> None:
        phase = self._added % CAMERA_PHASES
        self._cameras[name] = Periodic(self.frame_period, now + self.frame_period * phase / CAMERA_PHASES)
        self._added += 1

    def remove_camera(self, name: str) -> None:
        self._cameras.pop(name, None)

    def tick(self, now: float) -> Due:
        """What is due at sim time ``now`` [s] (each due time fires once)."""
        states = now > self._states_time and self.states.due(now)
        if states:
            self._states_time = now
        return Due(self.clock.due(now), states, self.vision.due(now),
                   tuple(name for name, frames in self._cameras.items() if frames.due(now)),
                   self.odometry.due(now), self.imu.due(now))


class Pacer:
    """Sim time at ``factor`` times wall time (0: as fast as possible)."""

    def __init__(self, factor: float, sim_time: float, clock: Callable[[], float] = time.monotonic,
                 sleep: Callable[[float], None] = time.sleep):
        self.factor = factor
        self._clock, self._sleep = clock, sleep
        self._anchor = (clock(), sim_time, factor)  # wall time, sim time, factor

    def hold(self, sim_time: float) -> None:
        """Sim time stands (paused): pace from here on."""
        self._anchor = (self._clock(), sim_time, self.factor)

    def wait(self, sim_time: float, stopped: Callable[[], bool] = lambda: False) -> None:
        """Sleep until the wall clock reaches ``sim_time`` [s] at the factor; a new factor takes effect at once."""
        wall, start, factor = self._anchor
        rate = self.factor
        if rate != factor:
            self._anchor = wall, start, factor = self._clock(), sim_time, rate
        if rate <= 0.0:
            return
        delay = wall + (sim_time - start) / rate - self._clock()
        while delay > 0.0 and self.factor == rate and not stopped():
            self._sleep(min(delay, MAX_SLEEP))
            delay = wall + (sim_time - start) / rate - self._clock()
        if delay < -MAX_LAG:  # too far behind: give the lost time up instead of racing to catch up
            self._anchor = self._clock(), sim_time, rate


@dataclass
class RobotOutputs:
    """One robot's due outputs of one step (None or empty: not due or not its sensor)."""

    percepts: RobotView | None = None  # given percepts (OmniVisionInfo)
    ball3d: Ball3dPercept | None = None  # with them, a goalie's 3-D ball (None inside: no ball seen)
    has_ball3d: bool = False
    camera: RenderedFrame | None = None  # the omni camera's frame
    truth: RobotView | None = None  # with it, the noise-free percepts
    front: np.ndarray | None = None  # the front camera's image (rendered only for a listener)
    rgbd: tuple[RgbdFrame, ...] = ()  # the two RGB-D cameras' clouds (rendered only for a listener)
    odometry: OdometryReading | None = None
    holding: bool | None = None  # the ball handler holds the ball (with the odometry)
    drive: tuple[np.ndarray, bool] | None = None  # a wheel-driven robot's wheels' ground speeds, ball in handler
    inertial: ImuReading | None = None


@dataclass
class Tick:
    """One physics step: its events and due outputs."""

    time: float
    events: list[SimEvent]
    clock: bool
    states: list[tuple[str, RobotState | BallState]] | None
    robots: dict[str, RobotOutputs] = field(default_factory=dict)  # only the robots with something due
    refusals: list[str] = field(default_factory=list)  # throttled lines about refused commands, to log

    def robot(self, name: str) -> RobotOutputs:
        outputs = self.robots.get(name)
        if outputs is None:
            outputs = self.robots[name] = RobotOutputs()
        return outputs


Listening = Callable[[str, str], bool]  # (robot, "front" or "rgbd"): whether anyone takes that sensor's output


class SimHost:
    """The simulator behind one lock, for the node's callback threads and its stepping loop."""

    def __init__(self, params: SimNodeParams, clock: Callable[[], float] = time.monotonic):
        self.params = params
        self.sim = Simulator(params.sim)
        self.lock = threading.Lock()
        self.paused = False
        self.pacer = Pacer(params.real_time_factor, self.sim.time)
        self.schedule = SensorSchedule(params, self.sim.time)
        self.rejections = RejectionReporter(REJECTION_REPORT_INTERVAL)
        self.sensors: dict[str, RobotSensors] = {}
        self.wheels: dict[str, WheelLayout] = {}  # the layout of a robot's last wheel speeds: it has wheels
        self._wheel_keys: dict[str, tuple[tuple[float, ...], float]] = {}
        self._clock = clock
        for name in self.sim.plugins:
            self._add(name)

    def _add(self, name: str) -> RobotSensors:
        sensors = self.sensors[name] = RobotSensors.of(self.params, name)
        if sensors.camera:
            self.schedule.add_camera(name, self.sim.time)
        return sensors

    # --- robots' commands (any thread) ---------------------------------------------------------------
    def command_velocity(self, name: str, vx: float, vy: float, w: float) -> str | None:
        """Drive robot ``name`` (body frame); return a line to log about a refusal or clamp, or None."""
        with self.lock:
            if name not in self.sim.plugins:
                return None  # deleted while the command was on its way
            try:
                _, clamped = self.sim.command_velocity(name, vx, vy, w)
            except SimVisualError as exc:
                return self._refused(name, "velocity command rejected", str(exc))
            if not clamped:
                return None
            return self._refused(name, "velocity command clamped to the robot's limits", f"({vx}, {vy}, {w})")

    def command_wheels(self, name: str, angles: tuple[float, ...], distance: float,
                       speeds: tuple[float, ...]) -> str | None:
        """Drive robot ``name`` by its wheels' rim speeds for wheels at ``angles`` [rad] and ``distance`` [m]."""
        with self.lock:
            if name not in self.sim.plugins:
                return None
            try:
                key = (tuple(angles), distance)
                if self._wheel_keys.get(name) != key:  # a new layout (made once: it checks itself)
                    self.wheels[name] = WheelLayout(tuple(math.degrees(a) for a in angles), distance)
                    self._wheel_keys[name] = key
                layout = self.wheels[name]
                _, clamped = self.sim.command_wheels(name, layout, np.asarray(speeds, dtype=float))
            except (NubotCommonError, SimVisualError) as exc:
                return self._refused(name, "wheel speeds rejected", str(exc))
            if not clamped:
                return None
            return self._refused(name, "wheel speeds clamped to the robot's limits", f"{list(speeds)}")

    def _refused(self, name: str, kind: str, detail: str) -> str | None:
        return self.rejections.count(name, kind, detail, self._clock())

    def refused(self, source: str, kind: str, detail: str) -> str | None:
        """Count a refused request of ``source`` (a robot's Shoot, a service call); the line to log now, or None
        while the reports of that source and kind are held back (a line every few seconds with the count)."""
        with self.lock:
            return self._refused(source, kind, detail)

    def ball_handle(self, name: str, enable: int) -> bool:
        """Switch robot ``name``'s ball handler; whether it holds the ball. Raises ``SimVisualError``."""
        with self.lock:
            return self.sim.ball_handle(name, enable)

    def shoot(self, name: str, strength: float, shoot_pos: int) -> tuple[bool, BallKicked | None]:
        """Robot ``name`` kicks; whether it kicked and the kick. Raises ``SimVisualError``."""
        with self.lock:
            return self.sim.shoot(name, strength, shoot_pos)

    # --- services ----------------------------------------------------------------------------------------
    def set_model_state(self, name: str, state: RobotState | BallState) -> None:
        with self.lock:
            self.sim.set_model_state(name, state)

    def spawn(self, spawn: RobotSpawn) -> RobotSensors:
        with self.lock:
            self.sim.spawn_robot(spawn)
            return self._add(spawn.name)

    def delete(self, name: str) -> None:
        with self.lock:
            self.sim.delete_robot(name)
            del self.sensors[name]
            self.wheels.pop(name, None)
            self._wheel_keys.pop(name, None)
            self.schedule.remove_camera(name)

    def reset(self) -> None:
        with self.lock:
            self.sim.reset()

    def switch_ends(self) -> str:
        """Every robot attacks the other goal; which goal each now attacks."""
        with self.lock:
            self.sim.switch_ends()
            return ", ".join(f"{n} {'+x' if p.spawn.attack > 0 else '-x'}" for n, p in self.sim.plugins.items())

    def pause(self, paused: bool) -> None:
        self.paused = paused

    # --- dynamic reconfigure -------------------------------------------------------------------------------
    def reconfigure_params(self) -> list[ReconfigureParam]:
        specs = [ReconfigureParam("real_time_factor", "double", self.pacer.factor, 0.0, REAL_TIME_FACTOR_MAX,
                                  "sim seconds per wall second; 0 as fast as possible")]
        for group, bounds in ((self.sim.plugin_params, PLUGIN_UPPER_BOUNDS), (self.sim.noise, NOISE_UPPER_BOUNDS)):
            for f in dataclasses.fields(group):
                specs.append(ReconfigureParam(f.name, "double", float(getattr(group, f.name)), 0.0, bounds[f.name],
                                              f"{type(group).__name__}.{f.name}"))
        return specs

    def reconfigure(self, config: Mapping[str, float]) -> dict[str, float]:
        """Apply a new configuration; the one in force. Raises ``ValueError`` (nothing changed) for a bad one."""
        plugin = dataclasses.replace(self.sim.plugin_params, **{k: config[k] for k in PLUGIN_NAMES})
        noise = dataclasses.replace(self.sim.noise, **{k: config[k] for k in NOISE_NAMES})
        factor = float(config["real_time_factor"])
        if not 0.0 <= factor <= REAL_TIME_FACTOR_MAX:
            raise ValueError(f"real_time_factor must lie in [0, {REAL_TIME_FACTOR_MAX:g}], got {factor}")
        with self.lock:
            self.sim.update_params(plugin, noise)
        self.pacer.factor = factor
        return self.configuration()

    def configuration(self) -> dict[str, float]:
        return {**dataclasses.asdict(self.sim.plugin_params), **dataclasses.asdict(self.sim.noise),
                "real_time_factor": self.pacer.factor}

    # --- stepping ---------------------------------------------------------------------------------------
    def step(self, listening: Listening = lambda _robot, _sensor: False) -> Tick:
        """One physics step and its due outputs (the sensors' noise drawn in one fixed order)."""
        sim, sensors = self.sim, self.sensors
        with self.lock:
            events = sim.step()
            now = sim.time
            due = self.schedule.tick(now)
            tick = Tick(now, events, due.clock, sim.model_states() if due.states else None)
            if due.percepts:
                for name, has in sensors.items():
                    if not has.camera:
                        robot = tick.robot(name)
                        robot.percepts = sim.observe(name)
                        if has.ball3d:
                            robot.has_ball3d, robot.ball3d = True, sim.observe_ball3d(name)
            for name in due.cameras:
                has, robot = sensors[name], tick.robot(name)
                robot.camera, robot.truth = sim.camera_frame(name, labels=has.labels), sim.observe_truth(name)
                if has.front and listening(name, "front"):
                    robot.front = sim.front_camera_frame(name)
                if has.rgbd and listening(name, "rgbd"):  # 5 ms a pair: only for a listener
                    robot.rgbd = sim.rgbd_frames(name)
            if due.odometry:
                for name, has in sensors.items():
                    if has.camera:
                        robot = tick.robot(name)
                        robot.odometry = sim.odometry(name, self.schedule.odometry_period)
                        robot.holding = sim.holder == name
                    if name in self.wheels:
                        tick.robot(name).drive = sim.wheel_ground_speeds(name, self.wheels[name]), sim.holder == name
            if due.imu:
                for name, has in sensors.items():
                    if has.camera:
                        tick.robot(name).inertial = sim.inertial_heading(name, self.schedule.imu_period)
            tick.refusals = self.rejections.due(self._clock())
        return tick

    def idle(self) -> list[str]:
        """While paused: pace from the standing sim time; lines about refused commands, to log."""
        self.pacer.hold(self.sim.time)
        with self.lock:
            return self.rejections.due(self._clock())


def event_line(event: SimEvent) -> str | None:
    """The log line of a simulator event, or None for one not logged."""
    if isinstance(event, GoalScored):
        side = "+x" if event.side > 0 else "-x"
        return f"sim_visual: GOAL in the goal at {side} at t={event.time:.2f} s (last touch " \
               f"{event.last_touch or 'nobody'})"
    if isinstance(event, BallCaptured):
        return f"sim_visual: {event.robot} holds the ball"
    return None


def kick_line(event: BallKicked) -> str:
    kind = "lob shot" if event.kind is KickKind.LOB else "ground pass"
    vx, vy, vz = event.velocity
    return f"{event.robot}: {kind}, ball velocity ({vx:.2f}, {vy:.2f}, {vz:.2f}) m/s"
