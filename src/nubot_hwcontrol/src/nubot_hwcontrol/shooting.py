"""Shooting: the lever picks a flat or a lob shot, a relay then an IGBT pulse fires the solenoid, and the
pulse's length sets the ball's speed through a calibration table.

Provides: ``ShotCalibration`` (per lever position, the ball speed [m/s] each pulse length [ms] gives;
``pulse_for(strength, lob)`` interpolates it), ``fit_calibration`` (fits the table from measured
(pulse, ball speed) pairs with a saturating model ``v = v_max (1 - exp(-(p - p0) / tau))``), and ``Kicker``
(the firing sequence: the lever must have settled, the capacitor must have recharged).
``Shoot``'s ``strength`` is the ball speed asked for [m/s] (a lob's strength is its speed off the foot).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from nubot_common.commands import KickKind
from nubot_hwcontrol import HardwareError

FLAT, LOB = KickKind.GROUND, KickKind.LOB  # Shoot.ShootPos: the kicker's names for the kinds


@dataclass(frozen=True)
class ShotTable:
    """Ball speed [m/s] against pulse length [ms] for one lever position; both strictly increasing."""

    pulse_ms: tuple[float, ...]
    speed: tuple[float, ...]

    def __post_init__(self) -> None:
        p, v = np.asarray(self.pulse_ms, dtype=float), np.asarray(self.speed, dtype=float)
        if p.shape != v.shape or p.size < 2:
            raise HardwareError(f"a shot table needs at least 2 (pulse, speed) pairs of equal count, got "
                                f"{p.size} pulses and {v.size} speeds")
        if not (np.all(np.isfinite(p)) and np.all(np.isfinite(v))):
            raise HardwareError("a shot table's pulses and speeds must be finite")
        if np.any(np.diff(p) <= 0.0) or np.any(np.diff(v) <= 0.0):
            raise HardwareError(f"a shot table must increase in pulse and speed, got {self.pulse_ms} -> {self.speed}")
        if p[0] < 0.0 or v[0] < 0.0:
            raise HardwareError("a shot table's pulses and speeds must be non-negative")

    def pulse_for(self, speed: float) -> float:
        """The pulse [ms] for a ball speed [m/s], clamped to the table's range."""
        return float(np.interp(speed, self.speed, self.pulse_ms))

    def speed_for(self, pulse_ms: float) -> float:
        return float(np.interp(pulse_ms, self.pulse_ms, self.speed))


_PULSES = (4.0, 6.4, 8.8, 11.2, 13.6, 16.0, 18.4, 20.8, 23.2, 25.6, 28.0, 30.4, 32.8, 35.2, 37.6, 40.0)


@dataclass(frozen=True)
class ShotCalibration:
    # fitted to the simulated drive's kicker (`simulate_kicks`, then `fit_shot_calibration`); fit your robot's own
    flat: ShotTable = ShotTable(_PULSES, (1.976, 3.549, 4.874, 5.99, 6.93, 7.721, 8.387, 8.949, 9.421, 9.819, 10.154,
                                          10.437, 10.674, 10.874, 11.043, 11.185))
    lob: ShotTable = ShotTable(_PULSES, (1.778, 3.194, 4.387, 5.391, 6.237, 6.949, 7.549, 8.054, 8.479, 8.837, 9.139,
                                         9.393, 9.607, 9.787, 9.939, 10.066))

    def table(self, shoot_pos: int) -> ShotTable:
        if shoot_pos == FLAT:
            return self.flat
        if shoot_pos == LOB:
            return self.lob
        raise HardwareError(f"ShootPos must be -1 (flat) or 1 (lob), got {shoot_pos}")

    def pulse_for(self, strength: float, shoot_pos: int) -> float:
        if not math.isfinite(strength) or strength <= 0.0:
            raise HardwareError(f"shot strength must be a positive ball speed [m/s], got {strength}")
        return self.table(shoot_pos).pulse_for(strength)


@dataclass(frozen=True)
class CalibrationFit:
    table: ShotTable
    v_max: float  # [m/s]
    tau: float  # [ms]
    p0: float  # dead time of the solenoid [ms]
    rms: float  # residual of the measurements [m/s]
    samples: int


def fit_calibration(pairs: Sequence[tuple[float, float]], points: int = 16) -> CalibrationFit:
    """Fit ``v = v_max (1 - exp(-(p - p0) / tau))`` to measured (pulse [ms], ball speed [m/s]) pairs and
    sample it into a table of ``points`` pulses over the measured range."""
    from scipy.optimize import curve_fit

    data = np.asarray(pairs, dtype=float)
    if data.ndim != 2 or data.shape[1] != 2:
        raise HardwareError(f"expected (pulse_ms, speed) pairs, got an array of shape {data.shape}")
    data = data[np.all(np.isfinite(data), axis=1)]
    if len(data) < 4 or len(np.unique(data[:, 0])) < 3:
        raise HardwareError(f"a fit needs at least 4 finite measurements at 3 or more pulse lengths, got {len(data)}")
    if np.any(data[:, 0] <= 0.0) or np.any(data[:, 1] < 0.0):
        raise HardwareError("pulses must be positive and speeds non-negative")
    pulse, speed = data[:, 0], data[:, 1]

    def model(p: np.ndarray, v_max: float, tau: float, p0: float) -> np.ndarray:
        return v_max * (1.0 - np.exp(-np.maximum(p - p0, 0.0) / tau))

    guess = (float(speed.max()) * 1.2, float(np.median(pulse)), 0.0)
    bounds = ([1e-3, 1e-3, -float(pulse.max())], [200.0, 1e4, float(pulse.min())])
    try:
        (v_max, tau, p0), _ = curve_fit(model, pulse, speed, p0=guess, bounds=bounds, maxfev=20000)
    except RuntimeError as exc:
        raise HardwareError(f"the calibration fit did not converge: {exc}") from exc
    rms = float(np.sqrt(np.mean((model(pulse, v_max, tau, p0) - speed) ** 2)))
    grid = np.linspace(max(float(pulse.min()), p0 + 1e-3), float(pulse.max()), points)
    table = ShotTable(tuple(round(float(p), 3) for p in grid),
                      tuple(round(float(v), 3) for v in model(grid, v_max, tau, p0)))
    return CalibrationFit(table, float(v_max), float(tau), float(p0), rms, len(data))


@dataclass(frozen=True)
class KickerParams:
    lever_time: float = 0.15  # the lever settles this long after it moved [s]
    recharge_time: float = 1.0  # the capacitor recharges this long after a shot [s]
    max_pulse_ms: float = 40.0

    def __post_init__(self) -> None:
        if not (self.lever_time >= 0.0 and self.recharge_time >= 0.0 and self.max_pulse_ms > 0.0):
            raise HardwareError("kicker times must be non-negative and max_pulse_ms positive")


@dataclass(frozen=True)
class ShotOrder:
    pulse_ms: float
    lob: bool


class Kicker:
    """The firing sequence. ``request`` asks for a shot; ``poll`` (every cycle) says when to fire."""

    def __init__(self, params: KickerParams | None = None, calibration: ShotCalibration | None = None):
        self.params, self.calibration = params or KickerParams(), calibration or ShotCalibration()
        self.lob = False  # lever position
        self._lever_moved = -math.inf
        self._last_shot = -math.inf
        self._pending: ShotOrder | None = None

    def ready_in(self, now: float, lob: bool) -> float:
        """Seconds until a shot of this kind could fire (0: now)."""
        lever_ready = self._lever_moved + self.params.lever_time if lob == self.lob else now + self.params.lever_time
        return max(lever_ready - now, self._last_shot + self.params.recharge_time - now, 0.0)

    def request(self, now: float, strength: float, shoot_pos: int) -> ShotOrder:
        pulse = min(self.calibration.pulse_for(strength, shoot_pos), self.params.max_pulse_ms)
        lob = shoot_pos == LOB
        if lob != self.lob:
            self.lob, self._lever_moved = lob, now
        self._pending = ShotOrder(pulse, lob)
        return self._pending

    def cancel(self) -> None:
        self._pending = None

    @property
    def pending(self) -> ShotOrder | None:
        return self._pending

    def poll(self, now: float) -> ShotOrder | None:
        """The shot to fire now, if one is pending and the lever and capacitor are ready."""
        order = self._pending
        if order is None or now < self._lever_moved + self.params.lever_time \
                or now < self._last_shot + self.params.recharge_time:
            return None
        self._pending, self._last_shot = None, now
        return order
