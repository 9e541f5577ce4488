"""Drive one robot along given waypoints with the motion layer: the chapter's Fig. 13 experiment.

Requires: ``PathTrackingParams`` (waypoints in the team frame [m], final heading [rad], the
motion parameters), the match's ``WorldDescription`` and, each cycle, the time [s], the robot's pose and the
obstacles it sees (team frame [m]).
Provides: ``PathTracker.step`` -> body-frame (Vx, Vy, w) and a ``TrackingSample`` (reference,
commanded velocity, error, compute time, finished). A pose observed before the cycle's time
is carried forward with the commanded velocity (at most 0.1 s). Until ``start_delay`` has passed since
the first cycle the robot stands still; once the reference has reached the goal and the robot
is within ``arrive_tolerance`` of it, below ``stop_speed``, the run is finished. The tolerance is on the pose the
robot sees (self-localization's, 2 cm of noise in the simulator) and is met at the slow turn of a small overshoot
too: at 0.05 m the robot really stands within 0.1 m of its goal.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from dataclasses import field as dc_field

from nubot_common.geometry import Pose2D
from nubot_common.params import require_non_negative, require_positive
from nubot_common.world_description import WorldDescription
from nubot_control.motion import MotionController
from nubot_control.params import MotionParams


@dataclass(frozen=True)
class PathTrackingParams:
    waypoints: tuple[tuple[float, float], ...] = ((-2.0, 2.0), (2.0, -2.0), (6.0, 2.0))  # p1, p2, p3 [m]
    heading: float = 0.0  # final heading [rad]
    start_delay: float = 1.0  # stand still this long after the first cycle [s]
    arrive_tolerance: float = 0.05  # [m]
    stop_speed: float = 0.05  # [m/s]
    rate: float = 33.0  # control cycles [Hz]
    motion: MotionParams = dc_field(default_factory=MotionParams)

    def __post_init__(self) -> None:
        if not self.waypoints:
            raise ValueError("waypoints must name at least the goal")
        for point in self.waypoints:
            if len(point) != 2 or not all(math.isfinite(c) for c in point):
                raise ValueError(f"a waypoint is [x, y] in metres, got {point!r}")
        require_positive(self, "arrive_tolerance", "stop_speed", "rate")
        require_non_negative(self, "start_delay")


@dataclass(frozen=True)
class TrackingSample:
    reference: tuple[float, float]  # where the robot should be now [m]
    reference_velocity: tuple[float, float]  # [m/s]
    position: tuple[float, float]  # [m]
    command: tuple[float, float]  # commanded velocity, team frame [m/s]
    error: float  # |position - reference| [m]
    compute_time: float  # [s] wall time of planning and tracking
    finished: bool


class PathTracker:
    def __init__(self, params: PathTrackingParams, world: WorldDescription):
        self.params = params
        self.motion = MotionController(params.motion, world, 1.0 / params.rate)
        self._first: float | None = None
        self._last: float | None = None
        self.finished = False

    def step(self, t: float, me: Pose2D, obstacles: list[tuple[float, float]], seen_at: float | None = None
             ) -> tuple[tuple[float, float, float], TrackingSample]:
        """One cycle at time ``t``; ``me`` was observed at ``seen_at`` (default ``t``) and is carried forward
        to ``t`` with the velocity commanded since (vision frames come at 30 Hz, the cycles at 33 Hz)."""
        p = self.params
        lag = 0.0 if seen_at is None else min(max(t - seen_at, 0.0), 0.1)
        if lag > 0.0:
            vx, vy = self.motion.velocity
            me = Pose2D(me.x + vx * lag, me.y + vy * lag, me.theta + self.motion.w * lag)
        if self._first is None:
            self._first = t
        dt = 1.0 / p.rate if self._last is None else min(max(t - self._last, 1e-3), 0.2)
        self._last = t
        goal = p.waypoints[-1]
        if t - self._first < p.start_delay or self.finished:
            self.motion.reset()
            still = TrackingSample((me.x, me.y), (0.0, 0.0), (me.x, me.y), (0.0, 0.0), 0.0, 0.0, self.finished)
            return (0.0, 0.0, 0.0), still
        command = self.motion.follow(me, list(p.waypoints), p.heading, obstacles, dt)
        assert self.motion.reference is not None  # set by every follow()
        (rx, ry), ref_v = self.motion.reference
        vx, vy = self.motion.velocity
        at_goal = math.hypot(rx - goal[0], ry - goal[1]) < 1e-3 or math.hypot(*ref_v) < 1e-6
        self.finished = (at_goal and math.hypot(me.x - goal[0], me.y - goal[1]) < p.arrive_tolerance
                         and math.hypot(vx, vy) < p.stop_speed)
        sample = TrackingSample((rx, ry), ref_v, (me.x, me.y), (vx, vy), math.hypot(me.x - rx, me.y - ry),
                                self.motion.compute_time, self.finished)
        return command, sample
