"""The hardware control node's core, without ROS: the controller behind one lock for the node's threads, a Shoot
that waits for the kicker's lever, and the loop's timing as the status reports it.

Requires: a ``HardwareController``. Provides: ``LoopTiming`` (the cycle's periods on the node's own clock: the wall
clock on a real robot, the simulator's under sim time; a period over 1.5 cycles is an overrun) and ``HardwareHost``
(``command_velocity``, ``ball_handle``, ``shoot``, ``cycle`` -> the cycle's report and, when due, a ``Status``).
"""

from __future__ import annotations

import threading
import time
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from nubot_hwcontrol.controller import CycleReport, HardwareController

SHOT_GRACE = 0.5  # [s, wall] a Shoot waits this long past the lever's delay for the shot to fire


class LoopTiming:
    """The periods between cycles, and the overruns among them. (A simulator's /clock ticks do not fall on the
    cycle's grid: 20 ms cycles land 15, 20 or 25 ms apart in sim time; wall periods would count cycles that were
    not late.)"""

    def __init__(self, rate: float):
        self.period = 1.0 / rate
        self.periods: list[float] = []
        self.overruns = 0
        self._last: float | None = None

    def tick(self, now: float) -> None:
        if self._last is not None and now > self._last:
            self.periods.append(now - self._last)
            if now - self._last > 1.5 * self.period:
                self.overruns += 1
        self._last = now

    def take(self) -> tuple[float, float]:
        """The median and 99th percentile period [s] since the last call (0 with none)."""
        periods, self.periods = self.periods, []
        if not periods:
            return 0.0, 0.0
        p50, p99 = np.percentile(periods, [50, 99])
        return float(p50), float(p99)


@dataclass(frozen=True)
class Status:
    """The controller's state as ``nubot_common/HardwareStatus`` gives it (the message's fields, its header
    aside)."""

    backend: str
    power_on: bool
    loop_period_p50: float
    loop_period_p99: float
    overruns: int
    wheel_set_points: list[float]
    wheel_speeds: list[float]
    limit_scale: float
    arms: list[float]
    holding: bool
    stuck: bool
    shots: int


class HardwareHost:
    """The controller for the node's threads: the commands' callbacks, the cycle's timer and the status."""

    def __init__(self, controller: HardwareController, status_rate: float, start: float,
                 wall: Callable[[], float] = time.monotonic):
        self.ctl = controller
        self.timing = LoopTiming(controller.params.rate)
        self.status_period = 1.0 / status_rate
        self._last_status = start
        self._wall = wall
        self.lock = threading.Lock()
        self._fired = threading.Condition(self.lock)
        self._last_cycle: float | None = None
        self.skipped = 0  # timer wakes at the very time of the last cycle, skipped

    def command_velocity(self, now: float, vx: float, vy: float, w: float) -> None:
        """Raises ``NubotCommonError`` or ``HardwareError`` for a refused command."""
        with self.lock:
            self.ctl.command_velocity(now, vx, vy, w)

    def ball_handle(self, enable: int) -> bool:
        with self.lock:
            return self.ctl.ball_handle(enable)

    def shoot(self, now: float, strength: float, shoot_pos: int) -> bool:
        """Ask for a shot and wait for the cycle that fires it; whether it fired (an unfired one is cancelled).
        Raises ``NubotCommonError`` or ``HardwareError`` for a refused one."""
        with self.lock:
            delay = self.ctl.shoot(now, strength, shoot_pos)
            if delay is None:
                return False
            shots = self.ctl.shots
            deadline = self._wall() + delay + SHOT_GRACE
            while self.ctl.shots == shots and self.ctl.kicker.pending is not None and self._wall() < deadline:
                self._fired.wait(0.05)
            if self.ctl.shots > shots:
                return True
            self.ctl.kicker.cancel()
            return False

    def cycle(self, now: float) -> tuple[CycleReport, Status | None] | None:
        """One control cycle at ``now`` [s] on the node's clock, and the status when it is due; None, and nothing
        done, at the very time of the last cycle (under sim time the timer can wake twice within one /clock tick:
        no fault, and this time's cycle ran already). Raises ``NubotCommonError`` or ``HardwareError`` for a cycle
        that failed, such as one before the last (the clock went back)."""
        if now == self._last_cycle:
            self.skipped += 1
            return None
        self.timing.tick(now)
        with self.lock:
            report = self.ctl.cycle(now)
            self._last_cycle = now
            if report.fired is not None:
                self._fired.notify_all()
        if now - self._last_status < self.status_period:
            return report, None
        self._last_status = now
        p50, p99 = self.timing.take()
        return report, Status(self.ctl.backend.name, report.state.power_on, p50, p99, self.timing.overruns,
                              list(report.set_points), list(report.odometry.rim_speeds), report.limit_scale,
                              list(report.state.arms), report.holding, report.odometry.stuck, self.ctl.shots)

    def close(self) -> None:
        with self.lock:
            self.ctl.close()
