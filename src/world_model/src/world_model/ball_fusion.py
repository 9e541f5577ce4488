"""Ball fusion: whose ball to believe, how fast it moves, how sure we are.

Requires: ``BallPercept`` streams (own sensors, each teammate's reports), the
observers' poses, ``WorldModelParams``. Provides: ``BallTrack`` (recent positions of
one source, duplicates dropped), ``fit_velocity`` (least-squares line through the
positions of the last ``velocity_window`` seconds, in closed form; the noisy per-frame
velocities are never used), ``BallCandidate`` and ``choose_ball`` (own sensors first,
else the valid teammate nearest to the ball it reports, then the freshest) and
``ball_confidence`` (in [0, 1]: decays linearly to 0 at ``ball_timeout``, grows with
the number of robots seeing the ball). Units: [s], [m], [m/s]. Compiled (``world_model._kernels``, from
``cpp/fusion.cpp``, where ``WorldModel``'s own fusion uses them); this module is their Python API.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING

from nubot_common.geometry import Pose2D
from nubot_common.kernels import load_kernels
from nubot_common.percepts import BallPercept
from nubot_common.world_state import BallSource

if TYPE_CHECKING:
    from world_model import _kernels  # its interface: _kernels.pyi
else:
    _kernels = load_kernels("world_model")


def fit_velocity(samples: Sequence[tuple[float, float, float]], min_samples: int) -> tuple[float, float] | None:
    """Slope (vx, vy) [m/s] of the least-squares lines x(t), y(t) through (t, x, y); None if underdetermined (fewer
    than ``min_samples``, or no spread in time). Times are taken relative to the last sample, so the fit stays well
    conditioned; it is what numpy.polyfit's degree-1 fit gives, up to rounding."""
    velocity = _kernels.fit_velocity(samples, min_samples)
    return None if velocity is None else (velocity[0], velocity[1])


class BallTrack:
    """The recent ball observations of one source (own sensors or one teammate)."""

    def __init__(self, keep: float):
        self.keep = keep  # observations older than this behind the newest are dropped [s]
        self._track = _kernels.BallTrack(keep)

    def __len__(self) -> int:
        return len(self._track)

    @property
    def latest(self) -> BallPercept | None:
        latest = self._track.latest
        return None if latest is None else BallPercept(*latest)

    def add(self, obs: BallPercept) -> None:
        """Append ``obs``; a repeat (the relay resends the latest message) or a late one is ignored; one far older
        than the newest (the clock went back: a restarted simulation) starts the track anew."""
        self._track.add(obs.stamp, obs.x, obs.y, obs.vx, obs.vy, obs.velocity_known)

    def clear(self) -> None:
        self._track.clear()

    def velocity(self, window: float, min_samples: int) -> tuple[float, float] | None:
        """Least-squares velocity over the observations within ``window`` of the newest one (made once per new
        observation)."""
        velocity = self._track.velocity(window, min_samples)
        return None if velocity is None else (velocity[0], velocity[1])


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
    """Own sensors first; else the teammate nearest to its ball, the freshest on a tie, then the lower AgentID."""
    if own is not None:
        return own
    best = _kernels.choose_ball([(c.agent_id, c.observation.x, c.observation.y, c.observer.x, c.observer.y,
                                  c.observer.theta, c.age) for c in team])
    return team[best] if best >= 0 else None


def ball_confidence(age: float, sightings: int, ball_timeout: float, sighting_confidence: float) -> float:
    """Confidence in [0, 1]: freshness (1 now, 0 at ``ball_timeout``) times support from ``sightings`` robots."""
    return _kernels.ball_confidence(age, sightings, ball_timeout, sighting_confidence)
