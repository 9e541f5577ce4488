"""Statistics and plots of one recorded match, from plain records (no ROS, no rosbags).

Requires: a ``MatchLog`` of plain records (model tracks, goals, kicks, ball touches,
referee states, coach commands; times in sim seconds, positions in the world frame [m]),
a ``FieldSize`` [m] and the attacked side per team to use when no referee state was
recorded. ``match_report.py`` builds these records from a match bag.
Provides: ``analyse`` -> ``MatchSummary`` (score, goals, possession, passes, shots,
referee events, distance run per robot, robot-robot collisions, time to reach a free ball;
``to_json()``) and the Agg plots ``plot_ball_heatmap`` and ``plot_trajectories``.

Definitions (``DEFINITIONS`` repeats them in report.json):

- team of a robot: its model name without the trailing digits (nubot3 -> nubot);
- running time: the time during which the last ``GameState`` says ``running``
  (before the first one: not running); all of the recording if no ``GameState``;
- goal: every ``GoalEvent`` during running time (or within ``GOAL_GRACE`` after it ended: the
  referee may have seen the goal first), credited to the team that attacks that side
  at that time (``GameState.attack``, else the default attack); an own goal when the last
  touch was by the other team. The score is counted from these and compared with the last
  ``GameState.score``; a ball pushed into a goal while play is stopped is listed apart
  (``goals_outside_play``), as the referee does not count it;
- touch: a ``BallTouch`` or a ``KickEvent`` (a kicker touched the ball);
- possession: the share of running time during which the last robot to touch the ball
  belongs to each team ("nobody" before the first touch);
- kick in play: a kick during running time; kicks outside it are counted apart only;
- shot: a kick in play whose straight-line ground direction crosses the goal line its team
  attacks between the posts, or any lob (kind 1) towards the half its team attacks;
- pass tried: a kick in play that is not a shot. It is completed when the next touch by a
  robot other than the kicker is by a teammate, intercepted when it is by an opponent,
  lost when a goal, a stop of play or another kick by the kicker comes first, unresolved
  when the recording ends first. Every outcome but completed is a failed pass;
- distance run: per robot, the sum of planar displacements between consecutive samples,
  leaving out steps longer than ``teleport_step`` (1 m: the referee or a reset moved it);
- referee events: the changes of ``GameState.last_event`` (empty texts left out), with times;
- positions compared between models: each robot's track interpolated (``np.interp``) onto one
  time grid, leaving out the times its track does not cover (before its first or after its last
  sample); robots are cylinders of radius ``hull_radius`` (0.26 m);
- collision: the onset, at a sample during running time, of contact of two robots: centres closer
  than 2 ``hull_radius`` + ``contact_tolerance`` (0.03 m). The pair counts again only after its
  centres were farther apart than 2 ``hull_radius`` + ``separation_margin`` (0.10 m); contact keeps
  its state through stoppages, so a contact begun outside running time never counts. Grid: the
  union of the robots' sample times. Counted per team pairing and per minute of running time;
- time to reach the ball: a free-ball episode starts at the first sample during running time at
  which no robot centre is within ``free_distance`` (1 m) of the ball and ends at the next sample
  at which one is within ``reach_distance`` (0.45 m); its duration is credited to the team of the
  nearest robot then. Episodes cut by the end of their running interval (a stoppage, the end of
  the recording) are dropped. Grid: the ball's sample times.
"""

from __future__ import annotations

import bisect
import math
import re
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np

BALL = "football"
GOAL_GRACE = 0.5  # a goal event this soon after play stopped still counts (the referee saw it first) [s]
NOBODY = "nobody"

DEFINITIONS = {
    "team": "a robot's team is its model name without the trailing digits",
    "running_time": "time during which the last GameState says running (none before the first GameState); "
                    "the whole recording when no GameState was recorded",
    "goal": "each /sim_visual/goal during running time (or up to 0.5 s after: the referee saw it first), "
            "credited to the team attacking that side (GameState.attack, else --attack); own goal when the last "
            "touch was by the other team; score_from_referee is the last GameState.score; goals_outside_play: "
            "goal events while play was stopped (not counted)",
    "touch": "a BallTouch or a KickEvent (the kicker touched the ball)",
    "possession": "share of running time during which the last robot to touch the ball belongs to each team",
    "kick_in_play": "a kick during running time; kicks outside it are only counted (kicks_outside_play)",
    "shot": "a kick in play whose straight ground direction crosses the attacked goal line between the posts, "
            "or any lob (kind 1) towards the attacked half",
    "pass": "a kick in play that is not a shot; completed when the next touch by another robot is by a teammate, "
            "intercepted when by an opponent, lost when a goal, a stop of play or another kick by the kicker comes "
            "first, unresolved when the recording ends first; failed = tried - completed",
    "distance_run": "sum of planar displacements between consecutive model-state samples, "
                    "steps longer than teleport_step_m left out (teleports by the referee or a reset)",
    "referee_events": "changes of GameState.last_event (empty texts left out) with their sim times",
    "time": "sim time [s]: header stamps; model states at the latest /clock before them",
    "robot_positions": "robot tracks interpolated onto one time grid, left out where a track does not cover the "
                       "time (before its first or after its last sample); robots are cylinders of hull_radius_m",
    "collisions": "onsets, at samples during running time, of two robots' centres closer than contact_distance_m "
                  "(2 hull_radius_m + a 0.03 m tolerance); a pair counts again only after its centres were "
                  "farther apart than separation_distance_m (2 hull_radius_m + 0.10 m); a contact begun outside "
                  "running time is not counted; grid: the union of the robots' sample times; per_minute of running "
                  "time",
    "ball_reach": "a free-ball episode starts at the first sample during running time with no robot centre within "
                  "free_distance_m of the ball and ends at the next sample with one within reach_distance_m; its "
                  "duration is the time to reach the ball, credited to the team of the nearest robot then; episodes "
                  "cut by the end of their running interval (stoppage, end of recording) are dropped; grid: the "
                  "ball's sample times",
}

_ROBOT_NAME = re.compile(r"^(?P<team>[A-Za-z_]+?)(?P<number>\d+)$")
_PASS_OUTCOMES = ("completed", "intercepted", "lost", "unresolved")
_TEAM_COLOURS = (("Blues", "blue"), ("Reds", "red"), ("Greens", "green"), ("Purples", "purple"),
                 ("Oranges", "orange"), ("Greys", "grey"))


def team_of(robot: str) -> str:
    """Return the team of a robot model name (nubot3 -> nubot); the name itself if it has no number."""
    match = _ROBOT_NAME.match(robot)
    return match["team"] if match else robot


def is_robot(name: str) -> bool:
    return bool(_ROBOT_NAME.match(name))


@dataclass(frozen=True)
class FieldSize:
    """Field dimensions [m]; the defaults are the chapter's 18 x 12 m field (MSL 2015)."""

    length: float = 18.0
    width: float = 12.0
    goal_width: float = 2.4  # between the posts
    goal_depth: float = 0.6
    penalty_area_length: float = 2.25
    penalty_area_width: float = 6.5
    goal_area_length: float = 0.75
    goal_area_width: float = 3.5
    center_circle_radius: float = 2.0
    border: float = 1.0  # run-off area drawn around the lines

    def __post_init__(self) -> None:
        for name, value in vars(self).items():
            if not value > 0.0:
                raise ValueError(f"field {name} must be positive, got {value}")
        if self.goal_width >= self.width:
            raise ValueError(f"goal width {self.goal_width} m must be smaller than the field width {self.width} m")


@dataclass(frozen=True)
class Track:
    """Planar positions of one model over time: ``t`` [s] (N,), ``xy`` [m] (N, 2), world frame."""

    name: str
    t: np.ndarray
    xy: np.ndarray


@dataclass(frozen=True)
class Goal:
    t: float  # [s]
    side: int  # goal at +x (1) or -x (-1)
    ball_xy: tuple[float, float]  # [m]
    last_touch: str  # robot, "" if none


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


@dataclass(frozen=True)
class KickOutcome:
    kick: Kick
    team: str
    in_play: bool
    shot: bool
    pass_outcome: str  # completed | intercepted | lost | unresolved, "" for shots and kicks outside play
    receiver: str  # robot of the next touch that decided the pass, "" otherwise


@dataclass(frozen=True)
class CreditedGoal:
    goal: Goal
    team: str  # credited team ("" if no team attacks that side)
    own_goal: bool
    half: int  # 0 when no GameState
    game_time: float | None  # game clock [s] when known


@dataclass(frozen=True)
class Collision:
    t: float  # [s] onset of the contact
    robots: tuple[str, str]  # sorted names

    @property
    def same_team(self) -> bool:
        return team_of(self.robots[0]) == team_of(self.robots[1])


@dataclass(frozen=True)
class BallReach:
    """A free-ball episode that a robot ended by reaching the ball."""

    t_free: float  # [s] first sample with the ball free
    t_reached: float  # [s]
    robot: str  # the robot nearest the ball at t_reached

    @property
    def seconds(self) -> float:
        return self.t_reached - self.t_free

    @property
    def team(self) -> str:
        return team_of(self.robot)


@dataclass
class MatchSummary:
    """The statistics of one match; times in sim seconds, distances in metres."""

    teams: list[str]
    start: float
    end: float
    running_time: float
    goals: list[CreditedGoal]
    score: dict[str, int]
    referee_score: dict[str, int] | None
    possession_seconds: dict[str, float]  # per team and NOBODY
    kicks: list[KickOutcome]
    distance_run: dict[str, float]  # per robot [m]
    referee_events: list[tuple[float, str]]
    coach_commands: list[CoachCommand]
    field: FieldSize
    teleport_step: float
    warnings: list[str]
    goals_outside_play: list[CreditedGoal] = field(default_factory=list)  # pushed in while play was stopped
    collisions: list[Collision] = field(default_factory=list)
    ball_reaches: list[BallReach] = field(default_factory=list)
    ball_reaches_dropped: int = 0  # free-ball episodes cut by the end of their running interval
    hull_radius: float = 0.26  # [m]
    contact_tolerance: float = 0.03  # [m]
    separation_margin: float = 0.10  # [m]
    free_distance: float = 1.0  # [m]
    reach_distance: float = 0.45  # [m]

    @property
    def score_agrees(self) -> bool:
        if self.referee_score is None:
            return True
        return all(self.referee_score.get(t, 0) == self.score.get(t, 0) for t in {*self.score, *self.referee_score})

    def possession_share(self) -> dict[str, float]:
        total = self.running_time
        return {k: (v / total if total > 0 else 0.0) for k, v in self.possession_seconds.items()}

    def pass_counts(self) -> dict[str, dict[str, int]]:
        keys = ("tried", "completed", "failed", *_PASS_OUTCOMES[1:])
        counts = {t: dict.fromkeys(keys, 0) for t in self.teams}
        for k in self.kicks:
            if k.pass_outcome:
                c = counts.setdefault(k.team, dict.fromkeys(keys, 0))
                c["tried"] += 1
                c[k.pass_outcome] += 1
                c["failed"] += k.pass_outcome != "completed"
        return counts

    def shot_counts(self) -> dict[str, int]:
        counts = dict.fromkeys(self.teams, 0)
        for k in self.kicks:
            if k.shot:
                counts[k.team] = counts.get(k.team, 0) + 1
        return counts

    def collision_counts(self) -> dict:
        """Return the total, the count per team pairing and the rate per minute of running time."""
        same = dict.fromkeys(self.teams, 0)
        for c in self.collisions:
            if c.same_team:
                team = team_of(c.robots[0])
                same[team] = same.get(team, 0) + 1
        minutes = self.running_time / 60.0
        return {"total": len(self.collisions), "same_team": same,
                "opponents": sum(1 for c in self.collisions if not c.same_team),
                "per_minute": len(self.collisions) / minutes if minutes > 0 else 0.0}

    def ball_reach_stats(self) -> dict:
        """Return the number, median and mean [s] of the times to reach the ball, overall and per team."""
        def stats(seconds: list[float]) -> dict:
            return {"episodes": len(seconds),
                    "median_s": _round3(np.median(seconds)) if seconds else None,
                    "mean_s": _round3(np.mean(seconds)) if seconds else None}

        per_team = {t: [] for t in self.teams}
        for r in self.ball_reaches:
            per_team.setdefault(r.team, []).append(r.seconds)
        return {**stats([r.seconds for r in self.ball_reaches]),
                "per_team": {t: stats(s) for t, s in per_team.items()}}

    def to_json(self) -> dict:
        r3 = _round3
        share = self.possession_share()
        clashes = self.collision_counts()
        return {
            "teams": self.teams,
            "start_s": r3(self.start),
            "end_s": r3(self.end),
            "duration_s": r3(self.end - self.start),
            "running_time_s": r3(self.running_time),
            "score": self.score,
            "score_from_referee": self.referee_score,
            "score_agrees": self.score_agrees,
            "goals": [{"t": r3(g.goal.t), "team": g.team, "side": g.goal.side, "last_touch": g.goal.last_touch,
                       "own_goal": g.own_goal, "half": g.half,
                       "game_time": None if g.game_time is None else r3(g.game_time),
                       "ball": [r3(g.goal.ball_xy[0]), r3(g.goal.ball_xy[1])]} for g in self.goals],
            "goals_outside_play": [{"t": r3(g.goal.t), "side": g.goal.side, "last_touch": g.goal.last_touch}
                                   for g in self.goals_outside_play],
            "possession": {k: {"share": round(share[k], 4), "seconds": r3(v)}
                           for k, v in self.possession_seconds.items()},
            "passes": self.pass_counts(),
            "shots": self.shot_counts(),
            "kicks_outside_play": sum(1 for k in self.kicks if not k.in_play),
            "kicks": [{"t": r3(k.kick.t), "robot": k.kick.robot, "team": k.team, "kind": k.kick.kind,
                       "in_play": k.in_play, "shot": k.shot, "pass": k.pass_outcome, "receiver": k.receiver}
                      for k in self.kicks],
            "referee_events": [{"t": r3(t), "event": e} for t, e in self.referee_events],
            "coach_commands": [{"t": r3(c.t), "team": c.team, "match_mode": c.match_mode}
                               for c in self.coach_commands],
            "distance_run_m": {r: r3(d) for r, d in self.distance_run.items()},
            "collisions": {**clashes, "per_minute": r3(clashes["per_minute"]),
                           "contact_distance_m": r3(2 * self.hull_radius + self.contact_tolerance),
                           "separation_distance_m": r3(2 * self.hull_radius + self.separation_margin),
                           "events": [{"t": r3(c.t), "robots": list(c.robots)} for c in self.collisions]},
            "ball_reach": {**self.ball_reach_stats(), "durations_s": [r3(r.seconds) for r in self.ball_reaches],
                           "dropped": self.ball_reaches_dropped, "free_distance_m": self.free_distance,
                           "reach_distance_m": self.reach_distance,
                           "events": [{"t_free": r3(r.t_free), "t_reached": r3(r.t_reached), "robot": r.robot,
                                       "team": r.team} for r in self.ball_reaches]},
            "field_m": {"length": self.field.length, "width": self.field.width, "goal_width": self.field.goal_width},
            "teleport_step_m": self.teleport_step,
            "hull_radius_m": self.hull_radius,
            "definitions": DEFINITIONS,
            "warnings": self.warnings,
        }


def _round3(x: float) -> float:
    return round(float(x), 3)


# --- time structure -------------------------------------------------------------------------------------------


def running_intervals(referee: Sequence[RefereeState], start: float, end: float) -> list[tuple[float, float]]:
    """Return the [t0, t1) intervals of running play; the whole [start, end] if there is no referee state."""
    if not referee:
        return [(start, end)] if end > start else []
    intervals: list[tuple[float, float]] = []
    for state, nxt in zip(referee, [*referee[1:], None]):
        t1 = end if nxt is None else nxt.t
        if not state.running or t1 <= state.t:
            continue
        if intervals and intervals[-1][1] == state.t:
            intervals[-1] = (intervals[-1][0], t1)
        else:
            intervals.append((state.t, t1))
    return intervals


def overlap(t0: float, t1: float, intervals: Iterable[tuple[float, float]]) -> float:
    """Return how much of [t0, t1) lies inside the intervals [s]."""
    return sum(max(0.0, min(t1, b) - max(t0, a)) for a, b in intervals)


def _inside(t: float, intervals: Sequence[tuple[float, float]]) -> int:
    """Return the index of the interval holding t, -1 if none (the last interval includes its end)."""
    for i, (a, b) in enumerate(intervals):
        if a <= t < b or (i == len(intervals) - 1 and t == b):
            return i
    return -1


def interval_index(t: np.ndarray, intervals: Sequence[tuple[float, float]]) -> np.ndarray:
    """Return for each time the index of the interval holding it, -1 if none (``_inside`` for an array)."""
    t = np.asarray(t, dtype=float)
    if not intervals:
        return np.full(len(t), -1)
    starts, ends = np.asarray(intervals, dtype=float).T
    i = np.searchsorted(starts, t, side="right") - 1
    inside = (i >= 0) & ((t < ends[i]) | ((i == len(starts) - 1) & (t == ends[-1])))
    return np.where(inside, i, -1)


def _state_at(referee: Sequence[RefereeState], t: float) -> RefereeState | None:
    """Return the referee state in force at t (the first one before any was published)."""
    if not referee:
        return None
    i = bisect.bisect_right([s.t for s in referee], t) - 1
    return referee[max(i, 0)]


def attack_at(referee: Sequence[RefereeState], t: float, default_attack: dict[str, int]) -> dict[str, int]:
    """Return the side each team attacks at time t: the referee's if known, else ``default_attack``."""
    attack = dict(default_attack)
    state = _state_at(referee, t)
    if state is not None:
        attack.update({team: int(side) for team, side in zip(state.teams, state.attack)})
    return attack


def default_attack_for(teams: Sequence[str], team: str, side: int) -> dict[str, int]:
    """Return ``team`` attacking ``side`` and every other team the opposite side."""
    return {t: (side if t == team else -side) for t in {*teams, team}}


# --- statistics -----------------------------------------------------------------------------------------------


def credit_goals(log: MatchLog, default_attack: dict[str, int]) -> tuple[list[CreditedGoal], list[str]]:
    """Credit each goal event to the team attacking that side; return the goals and warnings."""
    credited, warnings = [], []
    for goal in log.goals:
        attack = attack_at(log.referee, goal.t, default_attack)
        teams = sorted(t for t, side in attack.items() if side == goal.side)
        if len(teams) != 1:
            warnings.append(f"goal at t={goal.t:.3f} s: {len(teams)} teams attack side {goal.side}; not credited")
        team = teams[0] if len(teams) == 1 else ""
        own = bool(goal.last_touch) and bool(team) and team_of(goal.last_touch) != team
        state = _state_at(log.referee, goal.t)
        if state is None:
            half, game_time = 0, None
        else:
            ahead = goal.t - state.t if state.running and goal.t >= state.t else 0.0
            half, game_time = state.half, state.game_time + ahead
        credited.append(CreditedGoal(goal, team, own, half, game_time))
    return credited, warnings


def touch_sequence(log: MatchLog) -> list[Touch]:
    """Return ball touches and kicks (a kick is a touch by the kicker) in time order."""
    touches = [*log.touches, *(Touch(k.t, k.robot) for k in log.kicks)]
    return sorted(touches, key=lambda x: x.t)


def possession(touches: Sequence[Touch], intervals: Sequence[tuple[float, float]], end: float,
               teams: Sequence[str]) -> dict[str, float]:
    """Return the running time [s] during which each team (or nobody) touched the ball last."""
    seconds = dict.fromkeys([*teams, NOBODY], 0.0)
    owner, since = NOBODY, min((a for a, _ in intervals), default=end)
    for touch in touches:
        if touch.t > since:
            seconds[owner] = seconds.get(owner, 0.0) + overlap(since, touch.t, intervals)
            since = touch.t
        owner = team_of(touch.robot)
    seconds[owner] = seconds.get(owner, 0.0) + overlap(since, end, intervals)
    return seconds


def is_shot(kick: Kick, side: int, field_size: FieldSize) -> bool:
    """True when the kick goes towards the goal at ``side`` (+1/-1): between the posts, or any lob into that half."""
    vx, vy = kick.velocity[0], kick.velocity[1]
    if vx * side <= 0.0:
        return False
    if kick.kind == 1:
        return True
    x0, y0 = kick.ball_xy
    goal_x = side * field_size.length / 2.0
    if (goal_x - x0) * side <= 0.0:
        return False
    y_at_line = y0 + vy * (goal_x - x0) / vx
    return abs(y_at_line) <= field_size.goal_width / 2.0


def classify_kicks(log: MatchLog, intervals: Sequence[tuple[float, float]], default_attack: dict[str, int],
                   field_size: FieldSize) -> list[KickOutcome]:
    """Classify every kick: in play or not, shot or pass, and how each pass ended."""
    touches = touch_sequence(log)
    goal_times = [g.t for g in log.goals]
    outcomes = []
    for kick in log.kicks:
        team = team_of(kick.robot)
        in_play = _inside(kick.t, intervals) >= 0
        side = attack_at(log.referee, kick.t, default_attack).get(team, 0)
        shot = in_play and side != 0 and is_shot(kick, side, field_size)
        outcome, receiver = "", ""
        if in_play and not shot:
            outcome, receiver = _pass_outcome(kick, touches, goal_times, intervals, log.end)
        outcomes.append(KickOutcome(kick, team, in_play, shot, outcome, receiver))
    return outcomes


def _pass_outcome(kick: Kick, touches: Sequence[Touch], goal_times: Sequence[float],
                  intervals: Sequence[tuple[float, float]], end: float) -> tuple[str, str]:
    _, b = intervals[_inside(kick.t, intervals)]
    stop = min([b if b < end else math.inf, *(g for g in goal_times if g > kick.t)])  # play ends here
    for touch in touches[bisect.bisect_right([t.t for t in touches], kick.t):]:
        if touch.t >= stop or touch.robot == kick.robot:  # the kicker kicked again before anybody else touched
            return "lost", ""
        if team_of(touch.robot) == team_of(kick.robot):
            return "completed", touch.robot
        return "intercepted", touch.robot
    return ("lost", "") if stop < math.inf else ("unresolved", "")


def distance_run(track: Track, teleport_step: float = 1.0) -> float:
    """Return the planar path length [m], leaving out steps longer than ``teleport_step`` [m]."""
    if len(track.xy) < 2:
        return 0.0
    steps = np.hypot(*np.diff(track.xy, axis=0).T)
    return float(steps[steps <= teleport_step].sum())


def resample(tracks: Sequence[Track], t: np.ndarray) -> np.ndarray:
    """Return the positions (len(t), len(tracks), 2) [m] interpolated at times t; NaN where a track does not
    cover the time (before its first or after its last sample)."""
    xy = np.full((len(t), len(tracks), 2), np.nan)
    for k, track in enumerate(tracks):
        if len(track.t) == 0:
            continue
        covered = (t >= track.t[0]) & (t <= track.t[-1])
        for axis in (0, 1):
            xy[covered, k, axis] = np.interp(t[covered], track.t, track.xy[:, axis])
    return xy


def _latch(on: np.ndarray, off: np.ndarray) -> np.ndarray:
    """Return per column whether the last sample so far with ``on`` or ``off`` set had ``on`` (False before any)."""
    rows = np.arange(len(on))[:, None]
    last = np.maximum.accumulate(np.where(on | off, rows, -1), axis=0)
    return (last >= 0) & np.take_along_axis(on, np.maximum(last, 0), axis=0)


def collisions(tracks: dict[str, Track], intervals: Sequence[tuple[float, float]], hull_radius: float = 0.26,
               contact_tolerance: float = 0.03, separation_margin: float = 0.10) -> list[Collision]:
    """Return the onsets of robot-robot contact during running time, in time order (see ``DEFINITIONS``)."""
    if separation_margin < contact_tolerance:
        raise ValueError(f"separation margin {separation_margin} m must not be below the contact tolerance "
                         f"{contact_tolerance} m")
    robots = sorted(n for n, track in tracks.items() if is_robot(n) and len(track.t))
    if len(robots) < 2 or not intervals:
        return []
    t = np.unique(np.concatenate([tracks[r].t for r in robots]))
    xy = resample([tracks[r] for r in robots], t)
    first, second = np.triu_indices(len(robots), k=1)
    x, y = (np.ascontiguousarray(xy[..., axis]) for axis in (0, 1))  # (samples, robots) each
    distance = np.hypot(x[:, first] - x[:, second], y[:, first] - y[:, second])  # (samples, pairs), NaN: not covered
    contact = _latch(distance < 2 * hull_radius + contact_tolerance, distance > 2 * hull_radius + separation_margin)
    onset = contact.copy()
    onset[1:] &= ~contact[:-1]
    onset &= (interval_index(t, intervals) >= 0)[:, None]
    samples, pairs = np.nonzero(onset)  # row-major: in time order
    return [Collision(float(t[i]), (robots[first[p]], robots[second[p]])) for i, p in zip(samples, pairs)]


def ball_reaches(tracks: dict[str, Track], intervals: Sequence[tuple[float, float]], free_distance: float = 1.0,
                 reach_distance: float = 0.45) -> tuple[list[BallReach], int]:
    """Return the free-ball episodes ended by a robot reaching the ball, and how many the end of their running
    interval cut (dropped); see ``DEFINITIONS``."""
    if not reach_distance < free_distance:
        raise ValueError(f"reach distance {reach_distance} m must be below the free distance {free_distance} m")
    ball = tracks.get(BALL)
    robots = sorted(n for n, track in tracks.items() if is_robot(n) and len(track.t))
    if ball is None or len(ball.t) == 0 or not robots or not intervals:
        return [], 0
    gap = resample([tracks[r] for r in robots], ball.t) - ball.xy[:, None, :]
    distance = np.hypot(gap[..., 0], gap[..., 1])  # (samples, robots)
    distance[np.isnan(distance)] = np.inf  # robots not covered are left out
    nearest = distance.argmin(axis=1)
    nearest_distance = distance[np.arange(len(ball.t)), nearest]
    interval = interval_index(ball.t, intervals)
    running = interval >= 0
    free = np.flatnonzero(running & np.isfinite(nearest_distance) & (nearest_distance > free_distance))
    reached = np.flatnonzero(running & (nearest_distance <= reach_distance))
    free_interval = interval[free]  # non-decreasing
    episodes, dropped = [], 0
    k = 0  # next free sample that may start an episode
    while k < len(free):
        start = free[k]
        r = np.searchsorted(reached, start)
        if r == len(reached) or interval[reached[r]] != interval[start]:
            dropped += 1  # running time ended first: go on with the next running interval
            k = np.searchsorted(free_interval, interval[start], side="right")
            continue
        end = reached[r]
        episodes.append(BallReach(float(ball.t[start]), float(ball.t[end]), robots[nearest[end]]))
        k = np.searchsorted(free, end, side="right")
    return episodes, dropped


def referee_events(referee: Sequence[RefereeState]) -> list[tuple[float, str]]:
    """Return the changes of ``last_event`` (empty texts left out)."""
    events, last = [], ""
    for state in referee:
        if state.last_event != last and state.last_event:
            events.append((state.t, state.last_event))
        last = state.last_event
    return events


def teams_of(log: MatchLog) -> list[str]:
    """Return the teams: the referee's order first, then the others seen, sorted."""
    ordered: list[str] = []
    for state in log.referee:
        ordered += [t for t in state.teams if t not in ordered]
    seen = {team_of(n) for n in log.tracks if is_robot(n)}
    seen |= {team_of(k.robot) for k in log.kicks} | {team_of(t.robot) for t in log.touches}
    seen |= {c.team for c in log.coach}
    return ordered + sorted(seen - set(ordered) - {""})


def analyse(log: MatchLog, field_size: FieldSize, default_attack: tuple[str, int] = ("nubot", 1),
            teleport_step: float = 1.0, hull_radius: float = 0.26, contact_tolerance: float = 0.03,
            separation_margin: float = 0.10, free_distance: float = 1.0,
            reach_distance: float = 0.45) -> MatchSummary:
    """Compute every statistic of the report; ``default_attack`` is (team, side) used without referee states;
    distances [m] as in ``DEFINITIONS``."""
    teams = teams_of(log)
    attack = default_attack_for(teams, *default_attack)
    intervals = running_intervals(log.referee, log.start, log.end)
    credited, warnings = credit_goals(log, attack)
    # A goal stops play: the referee may see it (by geometry) a moment before the simulator's event.
    in_play = [any(a <= g.goal.t <= b + GOAL_GRACE for a, b in intervals) for g in credited]
    goals = [g for g, ok in zip(credited, in_play) if ok]
    stopped = [g for g, ok in zip(credited, in_play) if not ok]
    score = dict.fromkeys(teams, 0)
    for g in goals:
        if g.team:
            score[g.team] = score.get(g.team, 0) + 1
    referee_score = None
    if log.referee:
        last = log.referee[-1]
        referee_score = {t: int(s) for t, s in zip(last.teams, last.score)}
    if not log.referee:
        warnings.append(f"no referee state recorded: all time counts as running; {default_attack[0]} attacks "
                        f"{'+x' if default_attack[1] > 0 else '-x'}")
    reaches, dropped = ball_reaches(log.tracks, intervals, free_distance, reach_distance)
    return MatchSummary(
        teams=teams, start=log.start, end=log.end, running_time=sum(b - a for a, b in intervals),
        goals=goals, goals_outside_play=stopped, score=score, referee_score=referee_score,
        possession_seconds=possession(touch_sequence(log), intervals, log.end, teams),
        kicks=classify_kicks(log, intervals, attack, field_size),
        distance_run={n: distance_run(tr, teleport_step) for n, tr in sorted(log.tracks.items()) if is_robot(n)},
        referee_events=referee_events(log.referee), coach_commands=log.coach, field=field_size,
        teleport_step=teleport_step, warnings=warnings,
        collisions=collisions(log.tracks, intervals, hull_radius, contact_tolerance, separation_margin),
        ball_reaches=reaches, ball_reaches_dropped=dropped, hull_radius=hull_radius,
        contact_tolerance=contact_tolerance, separation_margin=separation_margin, free_distance=free_distance,
        reach_distance=reach_distance)


def ball_samples_in_play(log: MatchLog, intervals: Sequence[tuple[float, float]]) -> np.ndarray:
    """Return the ball positions (N, 2) sampled during running time."""
    track = log.tracks.get(BALL)
    if track is None or len(track.t) == 0:
        return np.zeros((0, 2))
    keep = np.zeros(len(track.t), dtype=bool)
    for a, b in intervals:
        keep |= (track.t >= a) & (track.t <= b)
    return track.xy[keep]


# --- plots ----------------------------------------------------------------------------------------------------


def _new_figure(field_size: FieldSize):
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    hl, hw, b = field_size.length / 2, field_size.width / 2, field_size.border
    fig = Figure(figsize=(10, 10 * (hw + b) / (hl + b) + 0.8))
    FigureCanvasAgg(fig)
    ax = fig.add_subplot()
    ax.set_xlim(-hl - b, hl + b)
    ax.set_ylim(-hw - b, hw + b)
    ax.set_aspect("equal")
    ax.set_xlabel("x [m] (world frame)")
    ax.set_ylabel("y [m]")
    return fig, ax


def draw_field(ax, field_size: FieldSize, colour: str = "white", zorder: int = 2) -> None:
    """Draw the lines, the areas, the centre circle and both goals (world frame)."""
    from matplotlib.patches import Circle, Rectangle

    f = field_size
    hl, hw = f.length / 2, f.width / 2
    style = {"fill": False, "edgecolor": colour, "linewidth": 1.5, "zorder": zorder}
    ax.add_patch(Rectangle((-hl, -hw), f.length, f.width, **style))
    ax.plot([0, 0], [-hw, hw], color=colour, linewidth=1.5, zorder=zorder)
    ax.add_patch(Circle((0, 0), f.center_circle_radius, **style))
    for side in (-1, 1):
        for depth, width in ((f.penalty_area_length, f.penalty_area_width), (f.goal_area_length, f.goal_area_width)):
            x0 = side * hl if side < 0 else hl - depth
            ax.add_patch(Rectangle((x0, -width / 2), depth, width, **style))
        x_goal = side * hl if side > 0 else -hl - f.goal_depth
        ax.add_patch(Rectangle((x_goal, -f.goal_width / 2), f.goal_depth, f.goal_width, fill=True,
                               facecolor="0.85", edgecolor="black", linewidth=2, zorder=zorder))


def plot_ball_heatmap(ball_xy: np.ndarray, field_size: FieldSize, path: Path, sample_period: float,
                      bin_size: float = 0.5, title: str = "Ball heat map") -> None:
    """Write a PNG of the time the ball spent in each ``bin_size`` cell [s], field with a border."""
    hl, hw, b = field_size.length / 2, field_size.width / 2, field_size.border
    x_edges = np.arange(-hl - b, hl + b + 1e-9, bin_size)
    y_edges = np.arange(-hw - b, hw + b + 1e-9, bin_size)
    xy = ball_xy if len(ball_xy) else np.zeros((0, 2))
    counts, _, _ = np.histogram2d(xy[:, 0], xy[:, 1], bins=[x_edges, y_edges])
    seconds = np.ma.masked_equal(counts.T * sample_period, 0.0)
    fig, ax = _new_figure(field_size)
    ax.set_facecolor("#2e7d32")
    mesh = ax.pcolormesh(x_edges, y_edges, seconds, cmap="YlOrRd", zorder=1)
    fig.colorbar(mesh, ax=ax, label=f"ball time per {bin_size:g} m cell [s]", shrink=0.8)
    draw_field(ax, field_size)
    ax.set_title(f"{title}: {len(xy) * sample_period:.1f} s of ball positions")
    fig.savefig(path, dpi=100, bbox_inches="tight")


def plot_trajectories(tracks: dict[str, Track], teams: Sequence[str], field_size: FieldSize, path: Path,
                      teleport_step: float = 1.0, max_points: int = 4000, title: str = "Robot trajectories") -> None:
    """Write a PNG of every robot's path: one colour family per team, each robot labelled at its last position."""
    from matplotlib import colormaps

    fig, ax = _new_figure(field_size)
    ax.set_facecolor("#dcedc8")
    draw_field(ax, field_size, colour="0.4", zorder=1)
    robots = sorted(n for n in tracks if is_robot(n))
    legend = []
    for team_index, team in enumerate(teams):
        members = [r for r in robots if team_of(r) == team]
        cmap_name, colour_name = _TEAM_COLOURS[team_index % len(_TEAM_COLOURS)]
        cmap = colormaps[cmap_name]
        legend.append(f"{team} {colour_name}")
        for i, robot in enumerate(members):
            xy = tracks[robot].xy
            if len(xy) == 0:
                continue
            step = max(1, len(xy) // max_points)
            jumps = np.flatnonzero(np.hypot(*np.diff(xy, axis=0).T) > teleport_step) + 1
            line = np.insert(xy.astype(float), jumps, np.nan, axis=0)[::step]  # no lines across teleports
            colour = cmap(0.35 + 0.6 * (i + 1) / (len(members) + 1))
            ax.plot(line[:, 0], line[:, 1], color=colour, linewidth=1.2, alpha=0.85, label=robot, zorder=3)
            ax.plot(*xy[0], marker="o", markersize=4, color=colour, zorder=4)
            ax.plot(*xy[-1], marker="s", markersize=6, color=colour, markeredgecolor="black", zorder=4)
            ax.annotate(robot, xy[-1], xytext=(4, 4), textcoords="offset points", fontsize=8, color="black",
                        zorder=5)
    if robots:
        ax.legend(loc="upper left", bbox_to_anchor=(1.01, 1.0), fontsize=8, title="o start, \u25a0 end")
    ax.set_title(f"{title}: {', '.join(legend)}" if legend else title)
    fig.savefig(path, dpi=100, bbox_inches="tight")
