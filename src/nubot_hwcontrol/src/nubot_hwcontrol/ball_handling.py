"""Ball handling: the two arms' PD control and the holding signal.

Each arm carries a driven wheel that rolls the ball in or lets it out; a potentiometer reads the arm's
position, normalised 0 (down, no ball) to 1 (pushed up all the way). The controller drives each wheel so its
arm sits at ``set_point``: ``u = kp (set_point - a) - kd da/dt + feed-forward``, where the feed-forward
cancels what the robot's own motion does to the ball (driving forwards pushes it in, backwards pulls it
away; the gains differ). ``u`` is the arm wheel's rim speed [m/s], positive rolls the ball in.
Holding: both arms above ``holding_threshold`` for ``holding_cycles`` cycles in a row (the ball is between
them and pressed in, not just touched by one).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_hwcontrol import HardwareError


@dataclass(frozen=True)
class BallHandlingParams:
    kp: float = 9.5  # [m/s per unit of arm position]
    kd: float = 2.4  # [m/s per unit/s]
    set_point: float = 0.65
    feedforward_forward: float = -0.6  # wheel speed per robot speed when driving forwards [1]
    feedforward_backward: float = -1.1  # ... and backwards (the ball must be pulled along: more) [1]
    max_wheel_speed: float = 2.5  # the arm wheels' limit [m/s]
    holding_threshold: float = 0.5
    holding_cycles: int = 10
    derivative_filter: float = 0.02  # time constant of the arm speed's low-pass [s]

    def __post_init__(self) -> None:
        values = (self.kp, self.kd, self.set_point, self.feedforward_forward, self.feedforward_backward,
                  self.max_wheel_speed, self.holding_threshold, self.derivative_filter)
        if not all(math.isfinite(v) for v in values):
            raise HardwareError(f"ball handling parameters must be finite, got {values}")
        if self.kp < 0.0 or self.kd < 0.0 or self.max_wheel_speed <= 0.0 or self.derivative_filter < 0.0:
            raise HardwareError("kp, kd and derivative_filter must be non-negative, max_wheel_speed positive")
        if not (0.0 < self.set_point < 1.0 and 0.0 < self.holding_threshold < 1.0):
            raise HardwareError("set_point and holding_threshold must lie in (0, 1)")
        if self.holding_cycles < 1:
            raise HardwareError(f"holding_cycles must be at least 1, got {self.holding_cycles}")


class ArmController:
    """PD control of one arm; remembers the last position for the derivative."""

    def __init__(self, params: BallHandlingParams):
        self.params = params
        self._last: float | None = None
        self.rate = 0.0  # filtered arm speed [1/s]

    def reset(self) -> None:
        self._last, self.rate = None, 0.0

    def update(self, position: float, dt: float, feedforward: float) -> float:
        p = self.params
        if self._last is not None and dt > 0.0:
            raw = (position - self._last) / dt
            alpha = dt / (dt + p.derivative_filter)
            self.rate += alpha * (raw - self.rate)
        self._last = position
        u = p.kp * (p.set_point - position) - p.kd * self.rate + feedforward
        return max(-p.max_wheel_speed, min(p.max_wheel_speed, u))


class BallHandler:
    """Both arms: their wheel speeds while enabled, and the holding signal."""

    def __init__(self, params: BallHandlingParams | None = None):
        params = params or BallHandlingParams()
        self.params = params
        self.arms = (ArmController(params), ArmController(params))
        self.enabled = False
        self._above = 0
        self.holding = False

    def enable(self, on: bool) -> None:
        if on and not self.enabled:
            for arm in self.arms:
                arm.reset()
        self.enabled = on

    def feedforward(self, robot_vx: float) -> float:
        p = self.params
        return (p.feedforward_forward if robot_vx >= 0.0 else p.feedforward_backward) * robot_vx

    def update(self, arms: tuple[float, float], robot_vx: float, dt: float) -> tuple[float, float]:
        """One cycle: the arms' positions (0-1) and the robot's forward speed [m/s] in, the arm wheels' rim
        speeds out (zero while disabled). Updates ``holding``."""
        if not all(math.isfinite(a) for a in (*arms, robot_vx, dt)):
            raise HardwareError(f"ball handling inputs must be finite, got arms {arms}, vx {robot_vx}, dt {dt}")
        p = self.params
        self._above = self._above + 1 if min(arms) > p.holding_threshold else 0
        self.holding = self._above >= p.holding_cycles
        if not self.enabled:
            return 0.0, 0.0
        ff = self.feedforward(robot_vx)
        left, right = (arm.update(a, dt, ff) for arm, a in zip(self.arms, arms))
        return left, right
