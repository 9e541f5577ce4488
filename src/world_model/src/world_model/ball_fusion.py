"""Ball fusion: whose ball to believe, how fast it moves, how sure we are.

Requires: ``BallPercept`` streams (own sensors, each teammate's reports), the
observers' poses, ``WorldModelParams``. Provides: ``BallTrack`` (recent positions of
one source, duplicates dropped), ``fit_velocity`` (least-squares line through the
positions of the last ``velocity_window`` seconds, in closed form; the noisy per-frame
velocities are never used), ``BallCandidate`` and ``choose_ball`` (own sensors first,
else the valid teammate nearest to the ball it reports, then the freshest) and
``ball_confidence`` (in [0, 1]: decays linearly to 0 at ``ball_timeout``, grows with
the number of robots seeing the ball). Units: [s], [m], [m/s].
"""

from __future__ import annotations

import math
from collections import deque
from collections.abc import Sequence
from dataclasses import dataclass

from nubot_common.geometry import Pose2D
from nubot_common.percepts import BallPercept
from nubot_common.world_state import BallSource

_TIME_JUMP = 1.0  # an observation this much older than the newest one means the clock went back [s]


def fit_velocity(samples: Sequence[tuple[float, float, float]], min_samples: int) -> tuple[float, float] | None:
    """Slope (vx, vy) [m/s] of the least-squares lines x(t), y(t) through (t, x, y); None if underdetermined."""
    if len(samples) < min_samples:
        return None
    # The closed-form slope sum((t - mean t)(x - mean x)) / sum((t - mean t)^2), what numpy.polyfit's degree-1
    # fit gives up to rounding, in plain floats: a dozen samples each cycle cost less than numpy's call overhead.
    last = samples[-1][0]
    times = [s[0] - last for s in samples]  # relative times keep the fit well conditioned
    if max(times) - min(times) < 1e-6:
        return None
    n = len(samples)
    t_mean = sum(times) / n
    x_mean = sum(s[1] for s in samples) / n
    y_mean = sum(s[2] for s in samples) / n
    stt = sxt = syt = 0.0
    for dt, (_, x, y) in zip(times, samples):
        dt -= t_mean
        stt += dt * dt
        sxt += dt * (x - x_mean)
        syt += dt * (y - y_mean)
    return sxt / stt, syt / stt


class BallTrack:
    """The recent ball observations of one source (own sensors or one teammate)."""

    def __init__(self, keep: float):
        self.keep = keep  # observations older than this behind the newest are dropped [s]
        self._samples: deque[BallPercept] = deque()
        self._fitted: tuple[object, tuple[float, float] | None] | None = None  # (key, velocity) of the last fit

    def __len__(self) -> int:
        return len(self._samples)

    @property
    def latest(self) -> BallPercept | None:
        return self._samples[-1] if self._samples else None

    def add(self, obs: BallPercept) -> None:
        """Append ``obs``; a repeat (the relay resends the latest message) or a late one is ignored."""
        latest = self.latest
        if latest is not None and obs.stamp <= latest.stamp:
            if obs.stamp >= latest.stamp - _TIME_JUMP:
                return
            self._samples.clear()  # the clock went back (simulator restarted)
        self._samples.append(obs)
        self._fitted = None
        while self._samples[0].stamp < obs.stamp - self.keep:
            self._samples.popleft()

    def clear(self) -> None:
        self._samples.clear()
        self._fitted = None

    def velocity(self, window: float, min_samples: int) -> tuple[float, float] | None:
        """Least-squares velocity over the observations within ``window`` of the newest one.

        The fit depends on the observations only, so it is made once per new observation (a world
        model asks for it several times a cycle: its snapshot, the packet it shares).
        """
        latest = self.latest
        if latest is None:
            return None
        key = (window, min_samples)
        if self._fitted is None or self._fitted[0] != key:
            recent = [(o.stamp, o.x, o.y) for o in self._samples if o.stamp >= latest.stamp - window]
            self._fitted = (key, fit_velocity(recent, min_samples))
        return self._fitted[1]


@dataclass(frozen=True)
class BallCandidate:
    """A fresh ball observation and who made it."""

    agent_id: int
    source: BallSource
    observation: BallPercept
    observer: Pose2D  # the observing robot's pose
    age: float  # [s]

    @property
    def distance(self) -> float:
        """Observer to ball [m]: the nearer robot sees the ball better."""
        return self.observer.distance_to(self.observation.x, self.observation.y)


def choose_ball(own: BallCandidate | None, team: Sequence[BallCandidate]) -> BallCandidate | None:
    """Own sensors first; else the teammate nearest to its ball, the freshest on a tie."""
    if own is not None:
        return own
    if not team:
        return None
    return min(team, key=lambda c: (c.distance, c.age, c.agent_id))


def ball_confidence(age: float, sightings: int, ball_timeout: float, sighting_confidence: float) -> float:
    """Confidence in [0, 1]: freshness (1 now, 0 at ``ball_timeout``) times support from ``sightings`` robots."""
    if sightings <= 0:
        return 0.0
    freshness = min(1.0, max(0.0, 1.0 - age / ball_timeout))
    support = 1.0 - (1.0 - sighting_confidence) ** sightings
    return freshness * support


def agreeing(candidates: Sequence[BallCandidate], x: float, y: float, radius: float) -> tuple[int, ...]:
    """AgentIDs whose ball lies within ``radius`` of (x, y), sorted."""
    return tuple(sorted({c.agent_id for c in candidates
                         if math.hypot(c.observation.x - x, c.observation.y - y) <= radius}))
