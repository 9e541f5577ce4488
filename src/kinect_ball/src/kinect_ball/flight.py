"""The ball's 3-D track and the parabola fitted to its current flight (gravity known), with its touchdown.

Requires: sightings of the ball's centre (``Sighting``: stamp [s], team frame [m], standard error [m]) in time
order, the ball's radius [m] and ``FlightParams``. Provides ``FlightTracker.add`` -> ``Ball3dPercept`` (velocity:
the fitted curve's slope at the latest stamp, once the flight has enough sightings) and ``FlightTracker.touchdown``
(``nubot_common.ball_flight.landing`` of that percept down to z = radius). ``fit_flight`` is the fit on its own.

The fit: x and y linear in time, z a parabola whose curvature is gravity (so only z0 and vz are fitted), weighted
least squares (weights 1/sigma^2) over the current flight's sightings in the last ``window`` seconds, with times
counted from the latest sighting so the intercepts are the position and the slopes the velocity now. A ball
whose recent heights all lie within ``ground_band`` of its radius rolls: z is fitted as a line. A new flight
starts after a gap of ``max_gap`` s, when a sighting lies more than ``max_jump`` (plus 3 sigma) from the current
fit's prediction (a kick, a deflection), or when the fit puts the ball below the ground at the new stamp (a
bounce: the earlier parabola no longer holds).
"""

from __future__ import annotations

from collections import deque
from dataclasses import dataclass

import numpy as np

from nubot_common.ball_flight import GRAVITY, Landing, landing
from nubot_common.params import require_positive
from nubot_common.percepts import Ball3dPercept


@dataclass(frozen=True)
class FlightParams:
    gravity: float = GRAVITY  # [m/s^2] along z
    window: float = 1.0  # [s] of the current flight fitted
    max_gap: float = 0.25  # [s] without a sighting ends a flight
    max_jump: float = 0.35  # [m] a sighting this far off the fit starts a new flight
    min_points: int = 4  # sightings before the velocity is known
    min_span: float = 0.08  # [s] ... spanning at least this long
    ground_band: float = 0.05  # [m] heights within the radius plus this count as on the ground
    max_points: int = 60  # sightings kept (two cameras at 30 Hz for 1 s)

    def __post_init__(self) -> None:
        if not -50.0 <= self.gravity < 0.0:
            raise ValueError(f"gravity must be negative (down) and at least -50, got {self.gravity}")
        require_positive(self, "window", "max_gap", "max_jump", "min_span", "ground_band")
        if not 2 <= self.min_points <= self.max_points:
            raise ValueError(f"min_points ({self.min_points}) must lie in [2, max_points ({self.max_points})]")


@dataclass(frozen=True)
class Sighting:
    stamp: float  # [s]
    x: float  # [m], team frame
    y: float
    z: float  # height of the ball's centre [m]
    sigma: float  # [m] standard error of the position


@dataclass(frozen=True)
class FlightFit:
    stamp: float  # the latest sighting's [s]
    position: np.ndarray  # (3,) [m] at ``stamp``
    velocity: np.ndarray  # (3,) [m/s] at ``stamp``
    on_ground: bool  # fitted as rolling (z a line)
    gravity: float  # [m/s^2] the curvature of z (0 on the ground)

    def predict(self, stamp: float) -> np.ndarray:
        dt = stamp - self.stamp
        p = self.position + self.velocity * dt
        p[2] += 0.5 * self.gravity * dt * dt
        return p


def fit_flight(sightings: list[Sighting], gravity: float, radius: float, ground_band: float) -> FlightFit:
    """The weighted least-squares curve through ``sightings`` (at least two, time order)."""
    t = np.array([s.stamp for s in sightings])
    xyz = np.array([[s.x, s.y, s.z] for s in sightings])
    w = 1.0 / np.maximum(np.array([s.sigma for s in sightings]), 1e-4)
    tr = t - t[-1]
    on_ground = bool(np.all(xyz[:, 2] <= radius + ground_band))
    g = 0.0 if on_ground else gravity
    a = np.stack([np.ones_like(tr), tr], axis=1) * w[:, None]
    target = xyz.copy()
    target[:, 2] -= 0.5 * g * tr * tr
    coef, *_ = np.linalg.lstsq(a, target * w[:, None], rcond=None)  # 2 x 3: intercepts, slopes
    return FlightFit(float(t[-1]), coef[0].copy(), coef[1].copy(), on_ground, g)


class FlightTracker:
    def __init__(self, params: FlightParams, radius: float):
        self.params, self.radius = params, radius
        self.track: deque[Sighting] = deque(maxlen=params.max_points)
        self.fit: FlightFit | None = None
        self.flights = 0  # flights started so far

    def reset(self) -> None:
        self.track.clear()
        self.fit = None

    def _starts_new_flight(self, s: Sighting) -> bool:
        if not self.track:
            return True
        if s.stamp - self.track[-1].stamp > self.params.max_gap:
            return True
        if self.fit is None:
            return bool(np.linalg.norm(np.array([s.x, s.y, s.z]) - self._last_xyz()) > self.params.max_jump
                        + 3.0 * s.sigma + 10.0 * (s.stamp - self.track[-1].stamp))
        predicted = self.fit.predict(s.stamp)
        if not self.fit.on_ground and predicted[2] < self.radius - 3.0 * s.sigma:
            return True  # the fitted flight has come down: what follows is a bounce or a roll
        return bool(np.linalg.norm(np.array([s.x, s.y, s.z]) - predicted) > self.params.max_jump + 3.0 * s.sigma)

    def _last_xyz(self) -> np.ndarray:
        last = self.track[-1]
        return np.array([last.x, last.y, last.z])

    def add(self, s: Sighting) -> Ball3dPercept:
        """Add a sighting (later than the previous one) and return the ball as the current flight's fit gives it."""
        if self.track and s.stamp <= self.track[-1].stamp:
            self.reset()  # time went back (a bag looped, the simulation reset)
        if self._starts_new_flight(s):
            self.track.clear()
            self.fit = None
            self.flights += 1
        self.track.append(s)
        while self.track[0].stamp < s.stamp - self.params.window:
            self.track.popleft()
        p = self.params
        if len(self.track) < 2:
            self.fit = None
            return Ball3dPercept(s.stamp, s.x, s.y, s.z)
        self.fit = fit_flight(list(self.track), p.gravity, self.radius, p.ground_band)
        if len(self.track) < p.min_points or s.stamp - self.track[0].stamp < p.min_span:
            return Ball3dPercept(s.stamp, s.x, s.y, s.z)
        (x, y, z), (vx, vy, vz) = self.fit.position, self.fit.velocity
        return Ball3dPercept(s.stamp, float(x), float(y), float(z), float(vx), float(vy), float(vz), True)

    def touchdown(self, percept: Ball3dPercept) -> Landing | None:
        """Where and when the ball of ``percept`` comes down to the ground (its centre at the radius); None
        without a velocity."""
        if not percept.velocity_known:
            return None
        return landing(percept.x, percept.y, percept.z, percept.vx, percept.vy, percept.vz, self.radius,
                       self.params.gravity)
