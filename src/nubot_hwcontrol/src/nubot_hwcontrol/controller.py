"""One robot's hardware control: the 50 Hz cycle that turns commands into set-points and readings into
odometry, behind any ``HardwareBackend``.

Requires: a backend, the controller's parameters (``HwControlParams``, ``config/nubot_hwcontrol.yaml``).
Provides: ``HardwareController`` with ``command_velocity`` (VelCmd, body frame), ``ball_handle`` (BallHandle),
``shoot`` (Shoot) and ``cycle`` (read, odometry, ball handling, kinematics with limits, write, fire).
A velocity command older than ``command_timeout`` stops the base: a dead control node never leaves the
robot driving.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, field

import numpy as np

from nubot_common.kinematics import GOALIE, REGULAR, BodyLimits, WheelLayout
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import HardwareBackend, HardwareState
from nubot_hwcontrol.ball_handling import BallHandler, BallHandlingParams
from nubot_hwcontrol.odometry import OdometryEstimate, OdometryParams, WheelOdometry
from nubot_hwcontrol.shooting import FLAT, LOB, Kicker, KickerParams, ShotCalibration, ShotOrder


@dataclass(frozen=True)
class HwControlParams:
    rate: float = 50.0  # base commands and odometry [Hz]
    command_timeout: float = 0.2  # [s]
    regular: WheelLayout = REGULAR
    goalie: WheelLayout = GOALIE
    limits: BodyLimits = field(default_factory=BodyLimits)
    odometry: OdometryParams = field(default_factory=OdometryParams)
    ball_handling: BallHandlingParams = field(default_factory=BallHandlingParams)
    kicker: KickerParams = field(default_factory=KickerParams)
    calibration: ShotCalibration = field(default_factory=ShotCalibration)

    def __post_init__(self) -> None:
        if not (math.isfinite(self.rate) and 1.0 <= self.rate <= 1000.0):
            raise HardwareError(f"rate must lie in [1, 1000] Hz, got {self.rate}")
        if not (math.isfinite(self.command_timeout) and self.command_timeout > 0.0):
            raise HardwareError(f"command_timeout must be positive, got {self.command_timeout}")
        if self.odometry.counts_per_revolution <= 0:
            raise HardwareError("odometry.counts_per_revolution must be positive")

    def layout(self, goalie: bool) -> WheelLayout:
        return self.goalie if goalie else self.regular


@dataclass(frozen=True)
class CycleReport:
    state: HardwareState
    odometry: OdometryEstimate
    holding: bool
    set_points: tuple[float, ...]  # base wheels' rim speeds written [m/s]
    limit_scale: float  # the wheels' limit scaled the command by this (1: within)
    arm_wheels: tuple[float, float]
    fired: ShotOrder | None  # the shot fired this cycle


class HardwareController:
    def __init__(self, params: HwControlParams, backend: HardwareBackend, goalie: bool = False):
        self.params, self.backend = params, backend
        self.layout = params.layout(goalie)
        self.limits = params.limits
        self.odometry = WheelOdometry(self.layout, params.odometry)
        self.ball = BallHandler(params.ball_handling)
        self.kicker = Kicker(params.kicker, params.calibration)
        self._command = (0.0, 0.0, 0.0)
        self._command_time = -math.inf
        self._set_points = np.zeros(self.layout.wheels)
        self._last_cycle: float | None = None
        self.shots = 0
        self.report: CycleReport | None = None

    # --- the robot interface -------------------------------------------------------------------
    def command_velocity(self, now: float, vx: float, vy: float, w: float) -> tuple[float, float, float]:
        """Take a body-frame velocity command; returns it after the software limits (refuses non-finite)."""
        self._command = self.limits.apply(vx, vy, w)
        self._command_time = now
        return self._command

    def ball_handle(self, enable: int) -> bool:
        """Run (non-zero) or stop the arm wheels; whether the arms hold the ball now."""
        self.ball.enable(enable != 0)
        return self.ball.holding

    def shoot(self, now: float, strength: float, shoot_pos: int) -> float | None:
        """Ask for a shot: ``strength`` the ball speed [m/s], ``shoot_pos`` -1 flat or 1 lob. Returns the delay
        [s] until it fires (the lever moving), or None when it cannot: no ball held, or the capacitor is still
        recharging. Refuses a bad strength or ShootPos with ``HardwareError``."""
        if shoot_pos not in (FLAT, LOB):
            raise HardwareError(f"ShootPos must be -1 (flat) or 1 (lob), got {shoot_pos}")
        self.params.calibration.pulse_for(strength, shoot_pos)  # validates the strength
        lob = shoot_pos == LOB
        delay = self.kicker.ready_in(now, lob)
        if not self.ball.holding or delay > self.params.kicker.lever_time:
            return None
        order = self.kicker.request(now, strength, shoot_pos)
        self.backend.set_lever(order.lob)
        return delay

    # --- the cycle -----------------------------------------------------------------------------
    def cycle(self, now: float) -> CycleReport:
        dt = 1.0 / self.params.rate if self._last_cycle is None else now - self._last_cycle
        if dt <= 0.0:
            raise HardwareError(f"control cycle at {now} s is not after the previous one at {self._last_cycle} s")
        self._last_cycle = now
        state = self.backend.read(now)
        odo = self.odometry.update(now, state.encoder_counts, self._set_points)
        arm_wheels = self.ball.update(state.arms, odo.vx, dt)
        vx, vy, w = self._command if now - self._command_time <= self.params.command_timeout else (0.0, 0.0, 0.0)
        if not state.power_on:
            vx = vy = w = 0.0
        rim, scale = self.layout.limit(self.layout.wheel_speeds(vx, vy, w))
        self._set_points = rim
        self.backend.write(now, rim, arm_wheels)
        fired = None
        order = self.kicker.poll(now)
        if order is not None and self.ball.holding:
            self.backend.fire(now, order.pulse_ms)
            self.shots += 1
            fired = order
        self.report = CycleReport(state, odo, self.ball.holding, tuple(float(v) for v in rim), scale, arm_wheels,
                                  fired)
        return self.report

    def close(self) -> None:
        self.backend.close()
