"""A simulated drive behind ``HardwareBackend``: what the motors, the encoders, the carpet and the ball handler
do, around a world that moves the robot by its wheels' speeds.

Requires a ``DriveWorld``: the simulator in this process (``sim_world.SimulatorWorld``) or over ROS (the
hardware node's link to ``sim_visual``). Per cycle (``read``), over the time since the last one:
- motors: each follows its set-point as a first-order lag (``motor_time_constant``);
- carpet: a wheel can turn at most ``slip_limit`` faster or slower than the ground under it moves (the drive
  is at its current limit beyond): this bounds the acceleration, and a blocked robot's wheels nearly stop;
  of what the wheel turns beyond the ground, ``slip_share`` slips (the encoders count it, the robot does not
  move by it), the rest moves the robot;
- encoders: the motor shaft's counts, integers, 32-bit wrapping;
- arms: with the ball in the handler the ball sits deeper or less deep as the arm wheels roll it in and the
  robot's motion pushes or pulls it (``push_forward``, ``push_backward``); each arm follows the ball as a
  damped spring, read by a 10-bit potentiometer with noise; without a ball the arms rest at ``arm_rest``;
- kicker: the solenoid's pulse gives the ball ``v_max (1 - exp(-(p - p0) / tau))`` with a few % of spread,
  less for a lob (the lever takes some of the energy).
Every random draw comes from the generator seeded by ``seed``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from typing import Protocol

import numpy as np

from nubot_common.kinematics import WheelLayout
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import HardwareBackend, HardwareState


class DriveWorld(Protocol):
    """The world the simulated drive acts on."""

    def drive(self, layout: WheelLayout, rim_speeds: np.ndarray) -> None:
        """Move the robot as wheels turning over the ground at these rim speeds [m/s] would."""

    def ground_speeds(self, layout: WheelLayout) -> np.ndarray:
        """The rim speed the robot's actual motion gives each wheel [m/s]."""

    def ball_in_handler(self) -> bool:
        """The ball is held between the arms."""

    def set_dribbling(self, on: bool) -> None:
        """The arm wheels run (the simulator's handler captures a ball in reach) or stop."""

    def kick(self, speed: float, lob: bool) -> bool:
        """Kick the held ball at ``speed`` [m/s] (flat) or as a lob; whether a ball was kicked."""


@dataclass(frozen=True)
class SimDriveParams:
    motor_time_constant: float = 0.04  # [s]
    slip_limit: float = 0.1  # [m/s]
    slip_share: float = 0.2
    counts_per_revolution: int = 2000  # as the real encoders (OdometryParams)
    arm_rest: float = 0.05
    arm_entry: float = 0.35  # where a ball that just came in holds the arms
    arm_gain: float = 1.0  # ball depth per wheel rim speed [1/m]
    push_forward: float = 0.55  # ball depth rate per robot speed forwards [1/m]
    push_backward: float = 1.2  # ... backwards
    arm_frequency: float = 12.0  # the arm spring's natural frequency [rad/s]
    arm_damping: float = 0.9  # its damping ratio
    arm_noise: float = 0.004  # potentiometer noise (std, normalised)
    kick_v_max: float = 12.0  # [m/s]
    kick_tau: float = 14.0  # [ms]
    kick_dead_time: float = 1.5  # [ms]
    kick_lob_share: float = 0.9
    kick_spread: float = 0.03  # relative std of the ball speed

    def __post_init__(self) -> None:
        positive = ("motor_time_constant", "slip_limit", "arm_gain", "arm_frequency", "arm_damping", "kick_v_max",
                    "kick_tau")
        for name in positive:
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise HardwareError(f"simulated drive: {name} must be positive, got {value}")
        if not 0.0 <= self.slip_share < 1.0:
            raise HardwareError(f"simulated drive: slip_share must lie in [0, 1), got {self.slip_share}")
        if self.counts_per_revolution <= 0:
            raise HardwareError("simulated drive: counts_per_revolution must be positive")


class SimulatedDrive(HardwareBackend):
    name = "sim"

    def __init__(self, world: DriveWorld, layout: WheelLayout, params: SimDriveParams | None = None,
                 seed: int = 0):
        params = params or SimDriveParams()
        self.world, self.layout, self.params = world, layout, params
        self.rng = np.random.default_rng(seed)
        n = layout.wheels
        self.set_points = np.zeros(n)
        self.motor = np.zeros(n)  # each motor's rim speed [m/s]
        self._turns = np.zeros(n)  # motor shaft travel in counts, not yet wrapped
        self.arm_wheels = (0.0, 0.0)
        self.depth = np.full(2, params.arm_entry)  # the ball's depth as each arm feels it
        self.arm = np.full(2, params.arm_rest)
        self.arm_rate = np.zeros(2)
        self.lob = False
        self._dribbling = False
        self._had_ball = False
        self._last: float | None = None
        self.kicks: list[tuple[float, float, bool]] = []  # (time, ball speed, lob) of each kick made
        self._counts_per_metre = params.counts_per_revolution * layout.gear_ratio / (math.pi * layout.wheel_diameter)

    # --- HardwareBackend ---------------------------------------------------------------------
    def read(self, now: float) -> HardwareState:
        if self._last is None:
            self._last = now
        dt = now - self._last
        if dt < 0.0:
            raise HardwareError(f"simulated drive read at {now} s, before its last read at {self._last} s")
        if dt > 0.0:
            self._advance(min(dt, 0.1))  # a long pause (a stopped simulation) is not one huge step
            self._last = now
        counts = tuple(int(c) % 2**32 for c in np.floor(self._turns))
        noise = self.rng.normal(0.0, self.params.arm_noise, 2)
        arms = np.clip(np.round((self.arm + noise) * 1023.0) / 1023.0, 0.0, 1.0)
        return HardwareState(now, counts, (float(arms[0]), float(arms[1])), True)

    def write(self, now: float, rim_speeds: np.ndarray, arm_wheels: tuple[float, float]) -> None:
        speeds = np.asarray(rim_speeds, dtype=float)
        if speeds.shape != (self.layout.wheels,) or not np.all(np.isfinite(speeds)):
            raise HardwareError(f"expected {self.layout.wheels} finite wheel speeds, got {rim_speeds}")
        self.set_points = speeds
        self.arm_wheels = (float(arm_wheels[0]), float(arm_wheels[1]))
        dribbling = self.arm_wheels != (0.0, 0.0)
        if dribbling != self._dribbling:
            self._dribbling = dribbling
            self.world.set_dribbling(dribbling)

    def set_lever(self, lob: bool) -> None:
        self.lob = lob

    def fire(self, now: float, pulse_ms: float) -> None:
        p = self.params
        if not self.world.ball_in_handler():
            return  # the solenoid strikes air
        speed = p.kick_v_max * (1.0 - math.exp(-max(pulse_ms - p.kick_dead_time, 0.0) / p.kick_tau))
        speed *= (p.kick_lob_share if self.lob else 1.0) * (1.0 + self.rng.normal(0.0, p.kick_spread))
        if self.world.kick(max(speed, 0.0), self.lob):
            self.kicks.append((now, speed, self.lob))

    def close(self) -> None:
        self.set_points = np.zeros(self.layout.wheels)
        self.world.drive(self.layout, np.zeros(self.layout.wheels))
        if self._dribbling:
            self.world.set_dribbling(False)
            self._dribbling = False

    # --- the physics -------------------------------------------------------------------------
    def _advance(self, dt: float) -> None:
        p = self.params
        ground = np.asarray(self.world.ground_speeds(self.layout), dtype=float)
        lagged = self.motor + (self.set_points - self.motor) * (1.0 - math.exp(-dt / p.motor_time_constant))
        self.motor = np.clip(lagged, ground - p.slip_limit, ground + p.slip_limit)
        self._turns += self.motor * dt * self._counts_per_metre
        self.world.drive(self.layout, ground + (self.motor - ground) * (1.0 - p.slip_share))
        self._advance_arms(dt, ground)

    def _advance_arms(self, dt: float, ground: np.ndarray) -> None:
        p = self.params
        ball = self.world.ball_in_handler()
        if ball and not self._had_ball:
            self.depth[:] = p.arm_entry
        self._had_ball = ball
        if ball:
            vx = self.layout.body_velocity(ground)[0]
            push = (p.push_forward if vx >= 0.0 else p.push_backward) * vx
            self.depth = np.clip(self.depth + (p.arm_gain * np.asarray(self.arm_wheels) + push) * dt, 0.2, 1.0)
            target = self.depth
        else:
            target = np.full(2, p.arm_rest)
        w, z = p.arm_frequency, p.arm_damping
        steps = max(1, int(math.ceil(dt / 0.002)))  # the spring is stiff: integrate it finely
        h = dt / steps
        for _ in range(steps):
            self.arm_rate += (w * w * (target - self.arm) - 2.0 * z * w * self.arm_rate) * h
            self.arm = np.clip(self.arm + self.arm_rate * h, 0.0, 1.0)
