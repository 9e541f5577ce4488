"""The plain records of one match that a report is computed from (no ROS, no rosbags).

Provides: ``Track`` (a model's positions over time), ``Goal``, ``Kick``, ``Touch``, ``RefereeState``, ``Call`` (a
foul or another call of the referee), ``CoachCommand`` and ``MatchLog`` (all of them for one match, with its world
and each team's goalie), and ``FOUL_KINDS``. Times are sim time [s], positions world frame [m]. ``match_report``
builds them from a bag, ``nubot_match.record`` from a lockstep match; ``match_analysis`` turns them into statistics.
"""

from __future__ import annotations

import math
import mmap
from dataclasses import dataclass, field

import numpy as np

from nubot_common.world_description import WorldDescription


@dataclass(frozen=True)
class Track:
    """Planar positions of one model over time: ``t`` [s] (N,), ``xy`` [m] (N, 2), world frame."""

    name: str
    t: np.ndarray
    xy: np.ndarray

    def around(self, first: float, last: float) -> Track:
        """The samples from the last at or before ``first`` to the first at or after ``last`` (views, no copy):
        interpolating between ``first`` and ``last`` on them gives what it gives on the whole track, while only
        that piece of a long track is read."""
        lo = max(int(np.searchsorted(self.t, first, side="right")) - 1, 0)
        hi = int(np.searchsorted(self.t, last, side="left")) + 1
        return Track(self.name, self.t[lo:hi], self.xy[lo:hi])

    def let_go(self) -> None:
        """Give back the memory of the pages read so far when the positions map a file (a lockstep recorder's
        track): they are read again from the file when next used. A pass over a whole match calls this as it goes,
        so that its tracks are never all in memory at once."""
        base: object = self.xy
        while isinstance(base, np.ndarray):
            base = base.base
        if isinstance(base, memoryview):
            base = base.obj
        if isinstance(base, mmap.mmap):
            base.madvise(mmap.MADV_DONTNEED)


@dataclass(frozen=True)
class Goal:
    t: float  # [s]
    side: int  # goal at +x (1) or -x (-1)
    ball_xy: tuple[float, float]  # [m]
    last_touch: str  # robot, "" if none
    height: float = math.nan  # ball centre's height when seen in the goal [m], NaN unknown


@dataclass(frozen=True)
class Kick:
    t: float  # [s]
    robot: str
    kind: int  # -1 ground pass, 1 lob
    velocity: tuple[float, float, float]  # initial ball velocity, world frame [m/s]
    ball_xy: tuple[float, float]  # [m]


@dataclass(frozen=True)
class Touch:
    t: float  # [s]
    robot: str


@dataclass(frozen=True)
class RefereeState:
    t: float  # [s]
    teams: tuple[str, ...]
    score: tuple[int, ...]
    attack: tuple[int, ...]  # 1: attacks the goal at +x, -1 at -x
    half: int
    game_time: float  # game clock of this half [s]
    running: bool
    last_event: str


@dataclass(frozen=True)
class Call:
    """A call of the referee (``/referee/foul``): a foul, a disallowed goal, a slow restart."""

    t: float  # [s]
    kind: str  # FOUL_KINDS, goal_disallowed, slow_restart
    team: str  # who committed it
    robot: str  # "" the team
    restart: str  # what it gave, in words ("" play went on)
    position: tuple[float, float]  # [m]
    rule: str = ""
    text: str = ""


FOUL_KINDS = ("carrying", "charging", "pushing", "illegal_defence", "illegal_attack")  # coach4sim.fouls.FOULS


@dataclass(frozen=True)
class CoachCommand:
    t: float  # [s]
    team: str
    match_mode: int


@dataclass
class MatchLog:
    """Everything a match report needs, converted from a bag; lists sorted by time."""

    tracks: dict[str, Track] = field(default_factory=dict)
    goals: list[Goal] = field(default_factory=list)
    kicks: list[Kick] = field(default_factory=list)
    touches: list[Touch] = field(default_factory=list)
    referee: list[RefereeState] = field(default_factory=list)
    coach: list[CoachCommand] = field(default_factory=list)
    start: float = 0.0  # [s] first time seen
    end: float = 0.0  # [s] last time seen
    world: WorldDescription | None = None  # the world the bag recorded, None if it recorded none
    goalies: dict[str, str] = field(default_factory=dict)  # team -> its goalie's model name, where known
    calls: list[Call] = field(default_factory=list)  # the referee's fouls and other calls
