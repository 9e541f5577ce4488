"""Statistics of one recorded match, from plain records (no ROS, no rosbags).

Requires: a ``MatchLog`` of plain records (``match_records``: model tracks, goals, kicks, ball touches,
referee states, the referee's calls, coach commands; times in sim seconds, positions in the world frame
[m]), the match's ``WorldDescription`` (its field [m] for shots, ``ball_name`` for the ball's track, the robot
``radius`` [m] as the default hull for collisions) and the attacked side per team to use when
no referee state was recorded. ``match_report`` builds these from a match bag.
Provides: ``analyse`` -> ``MatchSummary`` (score, goals, possession, passes, shots, referee
events, distance run per robot, robot-robot collisions, time to reach a free ball, the running
time the ball samples cover; ``to_json()``), and for sample times ``spread_repeated_times``
(times shared by consecutive samples spread out) and ``sample_durations`` (the sim time [s] each
sample covers). The plots are in ``match_plots``.

Definitions (``DEFINITIONS`` repeats them in report.json):

- team of a robot: its model name without the trailing digits (nubot3 -> nubot, ``nubot_common.naming``);
- sample times: a run of k consecutive samples sharing one time t, followed by the next distinct
  time t', is spread evenly over [t, t') (the last run over one typical step); each sample covers
  the sim time to the next sample (the last one: the median step);
- running time: the time during which the last ``GameState`` says ``running``
  (before the first one: not running); all of the recording if no ``GameState``;
- goal: every ``GoalEvent`` during running time (or within ``GOAL_GRACE`` after play stopped when the
  referee's score rose at that stop: the referee saw the goal first; not after full time), credited to
  the team that attacks that side at that time (``GameState.attack``, else the default attack); an own
  goal when the last touch was by the other team. The score is counted from these and compared with the last
  ``GameState.score``; a ball pushed into a goal while play is stopped is listed apart
  (``goals_outside_play``), as the referee does not count it, and so is one the referee disallowed (a
  ``goal_disallowed`` call within ``GOAL_GRACE``: ``goals_disallowed``);
- touch: a ``BallTouch`` or a ``KickEvent`` (a kicker touched the ball); a ``BallTouch`` by the kicker within
  ``KICK_TOUCH_TIME`` (0.05 s) after its kick is that kick;
- possession: the share of running time during which the last robot to touch the ball
  belongs to each team ("nobody" before the first touch);
- kick in play: a kick during running time; kicks outside it are counted apart only;
- shot: a kick in play from at most ``SHOT_DISTANCE`` (10 m) from the centre of the goal its team attacks,
  whose straight-line ground direction crosses that goal line at most ``SHOT_WIDE_MARGIN`` (1 m) outside a
  post and which, rolling at the ball's deceleration, gets there (a slower one is a pass), or any lob (kind 1)
  towards that goal (``match_shots`` says which were on target and how each ended);
- pass tried: a kick in play that is not a shot, aimed at a teammate (its line passes within
  ``PASS_AIM`` (1 m) of one ahead, within the distance the ball rolls; any kick when no teammate's
  track covers its time); the others are clearances, counted apart. A pass is completed when the next touch by a
  robot other than the kicker is by a teammate, intercepted when it is by an opponent,
  lost when a goal, a stop of play or another kick by the kicker comes first, unresolved
  when the recording ends first. Every outcome but completed is a failed pass;
- distance run: per robot, the sum of planar displacements between consecutive samples,
  leaving out steps longer than ``teleport_step`` (1 m: the referee or a reset moved it);
- referee events: the changes of ``GameState.last_event`` (empty texts left out), with times;
- fouls: the referee's calls (``/referee/foul``) per committing team and kind (``FOUL_KINDS``; also the goals it
  disallowed and the set pieces not taken in time);
- positions compared between models: each robot's track interpolated (``np.interp``) onto one
  time grid, leaving out the times its track does not cover (before its first or after its last
  sample); robots are cylinders of radius ``hull_radius`` (default: the world's robot radius, 0.26 m);
- collision: the onset, at a sample during running time, of contact of two robots: centres closer
  than 2 ``hull_radius`` + ``contact_tolerance`` (0.03 m). The pair counts again only after its
  centres were farther apart than 2 ``hull_radius`` + ``separation_margin`` (0.10 m); contact keeps
  its state through stoppages, so a contact begun outside running time never counts. Grid: the
  union of the robots' sample times. Counted per team pairing and per minute of running time;
- time to reach the ball: a free-ball episode starts at the first sample during running time at
  which no robot centre is within ``free_distance`` (1 m) of the ball and ends at the next sample
  at which one is within ``reach_distance`` (0.45 m); its duration is credited to the team of the
  nearest robot then. Episodes cut by the end of their running interval (a stoppage, the end of
  the recording) are dropped. Grid: the ball's sample times;
- ball time in play: the part of each ball sample's covered time that lies in running time; its sum
  is the running time the ball samples cover, and the heat map shows it per cell.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Iterable, Sequence
from dataclasses import dataclass, field

import numpy as np

from nubot_common.commands import KickKind
from nubot_common.field import FieldGeometry
from nubot_common.naming import is_robot_name, team_of
from nubot_common.world_description import WorldDescription
from nubot_match.match_records import (
    FOUL_KINDS,
    Call,
    CoachCommand,
    Goal,
    Kick,
    MatchLog,
    RefereeState,
    Touch,
    Track,
)

SHOT_WIDE_MARGIN = 1.0  # a ground kick crossing the goal line this far outside a post is still a shot [m]
PASS_AIM = 1.0  # a kick whose line passes this close to a teammate ahead is a pass to it [m]
SHOT_DISTANCE = 10.0  # a kick from farther from the goal's centre is no shot (a clearance or a pass) [m]
KICK_TOUCH_TIME = 0.05  # a touch by the kicker this soon after its kick is the kick itself [s]
GOAL_GRACE = 0.5  # a goal event this soon after play stopped still counts (the referee saw it first) [s]
NOBODY = "nobody"

DEFINITIONS = {
    "team": "a robot's team is its model name without the trailing digits",
    "running_time": "time during which the last GameState says running (none before the first GameState); "
                    "the whole recording when no GameState was recorded",
    "goal": "each /sim_visual/goal during running time (or up to 0.5 s after: the referee saw it first), "
            "credited to the team attacking that side (GameState.attack, else --attack); own goal when the last "
            "touch was by the other team; score_from_referee is the last GameState.score; goals_disallowed: the "
            "referee called goal_disallowed within 0.5 s (not counted); goals_outside_play: "
            "goal events while play was stopped (not counted)",
    "touch": "a BallTouch or a KickEvent (the kicker touched the ball); a BallTouch by the kicker within 0.05 s after "
             "its kick is that kick",
    "possession": "share of running time during which the last robot to touch the ball belongs to each team",
    "kick_in_play": "a kick during running time; kicks outside it are only counted (kicks_outside_play)",
    "shot": "a kick in play from at most 10 m from the attacked goal's centre whose straight ground direction crosses "
            "the attacked goal line at most 1 m outside a post, or any such lob (kind 1) towards that goal",
    "pass": "a kick in play that is not a shot and is aimed at a teammate (its line passes within 1 m of one ahead, "
            "within the ball's rolling distance; else a clearance, counted apart); completed when the next touch by "
            "another robot is by a teammate, "
            "intercepted when by an opponent, lost when a goal, a stop of play or another kick by the kicker comes "
            "first, unresolved when the recording ends first; failed = tried - completed",
    "distance_run": "sum of planar displacements between consecutive model-state samples, "
                    "steps longer than teleport_step_m left out (teleports by the referee or a reset)",
    "referee_events": "changes of GameState.last_event (empty texts left out) with their sim times",
    "fouls": "the referee's calls (/referee/foul) per team that committed them and kind: carrying, charging, pushing, "
             "illegal_defence, illegal_attack (fouls), goal_disallowed, slow_restart (docs/rules.md)",
    "time": "sim time [s]: header stamps; model states: their header stamp, or (bags without it, or a zero stamp) "
            "the latest /clock before them; k consecutive samples sharing a time t, followed by the next distinct "
            "time t', are spread evenly over [t, t')",
    "ball_time_in_play": "running time covered by ball samples: each sample covers the sim time to the next one "
                         "(the last one: the median step), counted only where it lies in running time; the heat "
                         "map shows these seconds per cell",
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

_PASS_OUTCOMES = ("completed", "intercepted", "lost", "unresolved")


@dataclass(frozen=True)
class KickOutcome:
    kick: Kick
    team: str
    in_play: bool
    shot: bool
    pass_outcome: str  # completed | intercepted | lost | unresolved, "" for shots, clearances, kicks outside play
    receiver: str  # robot of the next touch that decided the pass, "" otherwise
    clearance: bool = False  # in play, neither a shot nor aimed at a teammate (see ``aimed_at_teammate``)


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


@dataclass(frozen=True)
class BallTime:
    """Ball samples during running time: positions ``xy`` [m] (N, 2) and the running time [s] (N,) each covers."""

    xy: np.ndarray
    seconds: np.ndarray

    @property
    def total(self) -> float:
        """The running time [s] the ball samples cover."""
        return float(self.seconds.sum())


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
    world: WorldDescription  # its field was used for shots, its ball_name for the ball's track
    teleport_step: float
    warnings: list[str]
    goals_outside_play: list[CreditedGoal] = field(default_factory=list)  # pushed in while play was stopped
    goals_disallowed: list[CreditedGoal] = field(default_factory=list)  # in play, but the referee did not count them
    collisions: list[Collision] = field(default_factory=list)
    ball_reaches: list[BallReach] = field(default_factory=list)
    ball_reaches_dropped: int = 0  # free-ball episodes cut by the end of their running interval
    ball_in_play: BallTime = field(default_factory=lambda: BallTime(np.zeros((0, 2)), np.zeros(0)))
    hull_radius: float = 0.26  # [m]
    contact_tolerance: float = 0.03  # [m]
    separation_margin: float = 0.10  # [m]
    free_distance: float = 1.0  # [m]
    reach_distance: float = 0.45  # [m]
    calls: list[Call] = field(default_factory=list)  # the referee's fouls and other calls
    stopped_time: float = 0.0  # [s] play stood still within the halves (``stopped_time``)

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

    def foul_counts(self) -> dict[str, dict[str, int]]:
        """Per team the fouls it committed by kind (``FOUL_KINDS``), and its disallowed goals and slow restarts."""
        kinds = (*FOUL_KINDS, "goal_disallowed", "slow_restart")
        counts = {t: dict.fromkeys(kinds, 0) for t in self.teams}
        for c in self.calls:
            team = counts.setdefault(c.team, dict.fromkeys(kinds, 0))
            team[c.kind] = team.get(c.kind, 0) + 1
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
                    "median_s": _round3(float(np.median(seconds))) if seconds else None,
                    "mean_s": _round3(float(np.mean(seconds))) if seconds else None}

        per_team: dict[str, list[float]] = {t: [] for t in self.teams}
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
            "stopped_time_s": r3(self.stopped_time),
            "score": self.score,
            "score_from_referee": self.referee_score,
            "score_agrees": self.score_agrees,
            "goals": [{"t": r3(g.goal.t), "team": g.team, "side": g.goal.side, "last_touch": g.goal.last_touch,
                       "own_goal": g.own_goal, "half": g.half,
                       "game_time": None if g.game_time is None else r3(g.game_time),
                       "ball": [r3(g.goal.ball_xy[0]), r3(g.goal.ball_xy[1])]} for g in self.goals],
            "goals_outside_play": [{"t": r3(g.goal.t), "side": g.goal.side, "last_touch": g.goal.last_touch}
                                   for g in self.goals_outside_play],
            "goals_disallowed": [{"t": r3(g.goal.t), "side": g.goal.side, "team": g.team,
                                  "last_touch": g.goal.last_touch} for g in self.goals_disallowed],
            "possession": {k: {"share": round(share[k], 4), "seconds": r3(v)}
                           for k, v in self.possession_seconds.items()},
            "passes": self.pass_counts(),
            "shots": self.shot_counts(),
            "kicks_outside_play": sum(1 for k in self.kicks if not k.in_play),
            "clearances": {t: sum(1 for k in self.kicks if k.clearance and k.team == t) for t in self.teams},
            "kicks": [{"t": r3(k.kick.t), "robot": k.kick.robot, "team": k.team, "kind": k.kick.kind,
                       "in_play": k.in_play, "shot": k.shot, "pass": k.pass_outcome, "receiver": k.receiver,
                       "clearance": k.clearance} for k in self.kicks],
            "referee_events": [{"t": r3(t), "event": e} for t, e in self.referee_events],
            "fouls": self.foul_counts(),
            "referee_calls": [{"t": r3(c.t), "kind": c.kind, "team": c.team, "robot": c.robot, "restart": c.restart,
                               "position": [r3(c.position[0]), r3(c.position[1])], "rule": c.rule, "text": c.text}
                              for c in self.calls],
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
            "ball_time_in_play_s": r3(self.ball_in_play.total),
            "field": {"length_m": self.world.field.length, "width_m": self.world.field.width,
                      "goal_width_m": self.world.field.goal_width},
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


def stopped_time(referee: Sequence[RefereeState], intervals: Sequence[tuple[float, float]]) -> float:
    """Return the time [s] play stood still within the halves: the gaps between running intervals of one half (a
    gap across a change of half is the half-time break, not counted)."""
    stopped = 0.0
    for (_, b), (a, _) in zip(intervals, intervals[1:]):
        before, after = state_at(referee, b - 1e-9), state_at(referee, a)
        if before is not None and after is not None and before.half == after.half:
            stopped += a - b
    return stopped


def goal_stops(referee: Sequence[RefereeState], intervals: Sequence[tuple[float, float]]) -> list[bool]:
    """Return for each running interval whether play stopped for a goal: the referee's score rose within
    ``GOAL_GRACE`` of the interval's end (rather than full time, a foul or a coach's stop)."""
    stops = []
    for _, b in intervals:
        before = [sum(s.score) for s in referee if s.t < b]
        after = [sum(s.score) for s in referee if b <= s.t <= b + GOAL_GRACE]
        stops.append(bool(before and after) and max(after) > before[-1])
    return stops


def overlap(t0: float, t1: float, intervals: Iterable[tuple[float, float]]) -> float:
    """Return how much of [t0, t1) lies inside the intervals [s]."""
    return sum(max(0.0, min(t1, b) - max(t0, a)) for a, b in intervals)


def time_in_intervals(t0: np.ndarray, t1: np.ndarray, intervals: Iterable[tuple[float, float]]) -> np.ndarray:
    """Return for each [t0, t1) how much of it lies inside the intervals [s] (``overlap`` for arrays)."""
    t0, t1 = np.asarray(t0, dtype=float), np.asarray(t1, dtype=float)
    seconds = np.zeros(np.broadcast(t0, t1).shape)
    for a, b in intervals:
        seconds += np.clip(np.minimum(t1, b) - np.maximum(t0, a), 0.0, None)
    return seconds


def spread_repeated_times(t: np.ndarray) -> np.ndarray:
    """Return the sample times [s] with each run of k equal consecutive times t, followed by the next distinct time
    t', spread evenly over [t, t'); the last run (or one followed by an earlier time) spreads over the median step
    between distinct times."""
    t = np.asarray(t, dtype=float)
    if len(t) < 2:
        return t.copy()
    starts_run = np.concatenate([[True], t[1:] != t[:-1]])
    first = np.flatnonzero(starts_run)  # each run's first sample
    run = np.cumsum(starts_run) - 1  # each sample's run
    steps = np.diff(t[first])
    forward = steps[steps > 0.0]
    span = np.append(steps, 0.0)  # each run's time until the next run
    span[span <= 0.0] = float(np.median(forward)) if len(forward) else 0.0
    length = np.diff(np.append(first, len(t)))
    return t + span[run] * (np.arange(len(t)) - first[run]) / length[run]


def sample_durations(t: np.ndarray) -> np.ndarray:
    """Return the sim time [s] each sample covers: the time to the next sample (none if that goes back), the
    median step for the last one."""
    t = np.asarray(t, dtype=float)
    if len(t) < 2:
        return np.zeros(len(t))
    steps = np.clip(np.diff(t), 0.0, None)
    return np.append(steps, np.median(steps))


def inside(t: float, intervals: Sequence[tuple[float, float]]) -> int:
    """Return the index of the interval holding t, -1 if none (the last interval includes its end)."""
    for i, (a, b) in enumerate(intervals):
        if a <= t < b or (i == len(intervals) - 1 and t == b):
            return i
    return -1


def interval_index(t: np.ndarray, intervals: Sequence[tuple[float, float]]) -> np.ndarray:
    """Return for each time the index of the interval holding it, -1 if none (``inside`` for an array)."""
    t = np.asarray(t, dtype=float)
    if not intervals:
        return np.full(len(t), -1)
    starts, ends = np.asarray(intervals, dtype=float).T
    i = np.searchsorted(starts, t, side="right") - 1
    inside = (i >= 0) & ((t < ends[i]) | ((i == len(starts) - 1) & (t == ends[-1])))
    return np.where(inside, i, -1)


def state_at(referee: Sequence[RefereeState], t: float) -> RefereeState | None:
    """Return the referee state in force at t (the first one before any was published)."""
    if not referee:
        return None
    i = bisect.bisect_right([s.t for s in referee], t) - 1
    return referee[max(i, 0)]


def attack_at(referee: Sequence[RefereeState], t: float, default_attack: dict[str, int]) -> dict[str, int]:
    """Return the side each team attacks at time t: the referee's if known, else ``default_attack``."""
    attack = dict(default_attack)
    state = state_at(referee, t)
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
        state = state_at(log.referee, goal.t)
        if state is None:
            half, game_time = 0, None
        else:
            ahead = goal.t - state.t if state.running and goal.t >= state.t else 0.0
            half, game_time = state.half, state.game_time + ahead
        credited.append(CreditedGoal(goal, team, own, half, game_time))
    return credited, warnings


def goalies_by_role(goalie_cycles: dict[str, int]) -> dict[str, str]:
    """Each team's goalie: of the robots that announced the role GOALIE, the one that did so most often."""
    best: dict[str, tuple[int, str]] = {}
    for robot, cycles in goalie_cycles.items():
        team = team_of(robot)
        if cycles > 0 and (cycles, robot) > best.get(team, (0, "")):
            best[team] = (cycles, robot)
    return {team: robot for team, (_, robot) in sorted(best.items())}


def touch_sequence(log: MatchLog) -> list[Touch]:
    """Return ball touches and kicks (a kick is a touch by the kicker) in time order; a touch by the kicker within
    ``KICK_TOUCH_TIME`` after its kick is the kick itself (the simulator reports it as a touch when another robot
    had touched the held ball last) and is left out."""
    kicks = sorted((k.t, k.robot) for k in log.kicks)
    times = [t for t, _ in kicks]

    def the_kick(touch: Touch) -> bool:
        i = bisect.bisect_right(times, touch.t) - 1
        while i >= 0 and touch.t - kicks[i][0] <= KICK_TOUCH_TIME:
            if kicks[i][1] == touch.robot:
                return True
            i -= 1
        return False

    touches = [*(x for x in log.touches if not the_kick(x)), *(Touch(t, robot) for t, robot in kicks)]
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


def shot_line(kick: Kick, side: int, field: FieldGeometry) -> tuple[float, float] | None:
    """Where the kick's straight ground line crosses the goal line at ``side`` (+1/-1) [m], or None if it goes away
    from that line (or starts behind it)."""
    vx, vy = kick.velocity[0], kick.velocity[1]
    x0, y0 = kick.ball_xy
    goal_x = side * field.half_length
    if vx * side <= 1e-9 or (goal_x - x0) * side <= 0.0:
        return None
    return goal_x, y0 + vy * (goal_x - x0) / vx


def is_shot(kick: Kick, side: int, field: FieldGeometry, decel: float = 0.0) -> bool:
    """True when the kick goes towards the goal at ``side`` (+1/-1) from at most ``SHOT_DISTANCE`` from its centre:
    any lob, or a ground kick whose line crosses the goal line at most ``SHOT_WIDE_MARGIN`` outside a post and that,
    rolling at ``decel`` [m/s^2] (0: without slowing), gets there (a slower ball is a pass, not a shot)."""
    if kick.velocity[0] * side <= 0.0:
        return False
    if math.hypot(side * field.half_length - kick.ball_xy[0], kick.ball_xy[1]) > SHOT_DISTANCE:
        return False
    if kick.kind == KickKind.LOB:
        return True
    crossing = shot_line(kick, side, field)
    if crossing is None or abs(crossing[1]) > field.goal_width / 2.0 + SHOT_WIDE_MARGIN:
        return False
    speed2 = kick.velocity[0] ** 2 + kick.velocity[1] ** 2
    return speed2 >= 2.0 * decel * math.dist(crossing, kick.ball_xy)


def aimed_at_teammate(kick: Kick, tracks: dict[str, Track], decel: float) -> bool | None:
    """Whether the kick's line passes within ``PASS_AIM`` of a teammate ahead, within the distance the ball rolls at
    ``decel`` [m/s^2] (and ``PASS_AIM`` more); None when no teammate's track covers the kick's time."""
    team = team_of(kick.robot)
    mates = [tracks[n] for n in tracks if is_robot_name(n) and team_of(n) == team and n != kick.robot
             and len(tracks[n].t) and tracks[n].t[0] <= kick.t <= tracks[n].t[-1]]
    if not mates:
        return None
    vx, vy = kick.velocity[0], kick.velocity[1]
    speed = math.hypot(vx, vy)
    if speed < 1e-6:
        return False
    ux, uy = vx / speed, vy / speed
    reach = speed * speed / (2.0 * decel) + PASS_AIM if decel > 0.0 else math.inf
    for track in mates:
        near = track.around(kick.t, kick.t)
        x = float(np.interp(kick.t, near.t, near.xy[:, 0])) - kick.ball_xy[0]
        y = float(np.interp(kick.t, near.t, near.xy[:, 1])) - kick.ball_xy[1]
        if 0.0 < x * ux + y * uy < reach and abs(x * uy - y * ux) < PASS_AIM:
            return True
    return False


def classify_kicks(log: MatchLog, intervals: Sequence[tuple[float, float]], default_attack: dict[str, int],
                   field: FieldGeometry, decel: float = 0.78) -> list[KickOutcome]:
    """Classify every kick: in play or not, shot, pass (aimed at a teammate; how it ended) or clearance."""
    touches = touch_sequence(log)
    goal_times = [g.t for g in log.goals]
    outcomes = []
    for kick in log.kicks:
        team = team_of(kick.robot)
        in_play = inside(kick.t, intervals) >= 0
        side = attack_at(log.referee, kick.t, default_attack).get(team, 0)
        shot = in_play and side != 0 and is_shot(kick, side, field, decel)
        outcome, receiver, clearance = "", "", False
        if in_play and not shot:
            clearance = aimed_at_teammate(kick, log.tracks, decel) is False
            if not clearance:
                outcome, receiver = _pass_outcome(kick, touches, goal_times, intervals, log.end)
        outcomes.append(KickOutcome(kick, team, in_play, shot, outcome, receiver, clearance))
    return outcomes


def _pass_outcome(kick: Kick, touches: Sequence[Touch], goal_times: Sequence[float],
                  intervals: Sequence[tuple[float, float]], end: float) -> tuple[str, str]:
    _, b = intervals[inside(kick.t, intervals)]
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
    total = 0.0
    for start in range(0, len(track.xy) - 1, _STEPS_CHUNK):  # a piece at a time: a whole track's steps take MiBs
        steps = np.hypot(*np.diff(track.xy[start:start + _STEPS_CHUNK + 1], axis=0).T)
        total += float(steps[steps <= teleport_step].sum())
    track.let_go()
    return total


_STEPS_CHUNK = 16384  # steps of a track summed at a time


_CHUNK = 2048  # samples compared at a time: the pairwise arrays of a whole match would take hundreds of MiB (45
# pairs x 2048 samples: about 4 MiB of arrays at a time)


def resample(tracks: Sequence[Track], t: np.ndarray) -> np.ndarray:
    """Return the positions (len(t), len(tracks), 2) [m] interpolated at times t; NaN where a track does not
    cover the time (before its first or after its last sample). Only the piece of each track around t is read, and
    its memory given back (``Track.let_go``): a pass over a whole match in pieces of t keeps one piece in memory."""
    xy = np.full((len(t), len(tracks), 2), np.nan)
    if len(t) == 0:
        return xy
    first, last = float(t.min()), float(t.max())
    for k, track in enumerate(tracks):
        if len(track.t) == 0:
            continue
        covered = (t >= track.t[0]) & (t <= track.t[-1])
        near = track.around(first, last)
        for axis in (0, 1):
            xy[covered, k, axis] = np.interp(t[covered], near.t, near.xy[:, axis])
        track.let_go()
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
    robots = sorted(n for n, track in tracks.items() if is_robot_name(n) and len(track.t))
    if len(robots) < 2 or not intervals:
        return []
    t = tracks[robots[0]].t  # a lockstep recorder samples all robots at the same times: those, without a copy
    if not (all(np.array_equal(tracks[r].t, t) for r in robots[1:]) and bool((np.diff(t) > 0).all())):
        t = np.unique(np.concatenate([tracks[r].t for r in robots]))
    running = interval_index(t, intervals) >= 0
    first, second = np.triu_indices(len(robots), k=1)
    found: list[Collision] = []
    before = np.zeros(len(first), dtype=bool)  # each pair's contact at the sample before the chunk
    for start in range(0, len(t), _CHUNK):  # a 2 x 15 min match: 45 pairs x 240,000 samples, in pieces
        part = t[start:start + _CHUNK]
        xy = resample([tracks[r] for r in robots], part)
        x, y = (np.ascontiguousarray(xy[..., axis]) for axis in (0, 1))  # (samples, robots) each
        distance = np.hypot(x[:, first] - x[:, second], y[:, first] - y[:, second])  # (samples, pairs); NaN: uncovered
        # the sample before the chunk leads, as the state the latch carries in (none before the first: apart)
        contact = _latch(np.vstack([before, distance < 2 * hull_radius + contact_tolerance]),
                         np.vstack([~before, distance > 2 * hull_radius + separation_margin]))
        onset = contact[1:] & ~contact[:-1] & running[start:start + _CHUNK, None]
        samples, pairs = np.nonzero(onset)  # row-major: in time order
        found += [Collision(float(part[i]), (robots[first[p]], robots[second[p]])) for i, p in zip(samples, pairs)]
        before = contact[-1]
    return found


def nearest_robot(tracks: Sequence[Track], t: np.ndarray, xy: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Return, at each time of ``t``, which of ``tracks`` is nearest to the point ``xy`` (len(t), 2) [m] and how far
    it is (inf where no track covers the time)."""
    nearest = np.zeros(len(t), dtype=np.int16)  # an index into tracks (a match has at most a few dozen)
    nearest_distance = np.full(len(t), np.inf)
    for start in range(0, len(t), _CHUNK):
        end = start + _CHUNK
        gap = resample(tracks, t[start:end]) - xy[start:end, None, :]
        distance = np.hypot(gap[..., 0], gap[..., 1])  # (samples, robots)
        distance[np.isnan(distance)] = np.inf  # robots not covered are left out
        nearest[start:end] = distance.argmin(axis=1)
        nearest_distance[start:end] = distance[np.arange(len(distance)), nearest[start:end]]
    return nearest, nearest_distance


def ball_reaches(tracks: dict[str, Track], intervals: Sequence[tuple[float, float]], free_distance: float = 1.0,
                 reach_distance: float = 0.45, ball_name: str = "football") -> tuple[list[BallReach], int]:
    """Return the free-ball episodes ended by a robot reaching the ball (the track ``ball_name``), and how many the
    end of their running interval cut (dropped); see ``DEFINITIONS``."""
    if not reach_distance < free_distance:
        raise ValueError(f"reach distance {reach_distance} m must be below the free distance {free_distance} m")
    ball = tracks.get(ball_name)
    robots = sorted(n for n, track in tracks.items() if is_robot_name(n) and len(track.t))
    if ball is None or len(ball.t) == 0 or not robots or not intervals:
        return [], 0
    nearest, nearest_distance = nearest_robot([tracks[r] for r in robots], ball.t, ball.xy)
    ball.let_go()
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
    seen = {team_of(n) for n in log.tracks if is_robot_name(n)}
    seen |= {team_of(k.robot) for k in log.kicks} | {team_of(t.robot) for t in log.touches}
    seen |= {c.team for c in log.coach}
    return ordered + sorted(seen - set(ordered) - {""})


def analyse(log: MatchLog, world: WorldDescription, default_attack: tuple[str, int] = ("nubot", 1),
            teleport_step: float = 1.0, hull_radius: float | None = None, contact_tolerance: float = 0.03,
            separation_margin: float = 0.10, free_distance: float = 1.0,
            reach_distance: float = 0.45) -> MatchSummary:
    """Compute every statistic of the report in ``world`` (field, ball name, robot radius as the default
    ``hull_radius``); ``default_attack`` is (team, side) used without referee states; distances [m] as in
    ``DEFINITIONS``."""
    hull = world.robot.radius if hull_radius is None else hull_radius
    teams = teams_of(log)
    attack = default_attack_for(teams, *default_attack)
    intervals = running_intervals(log.referee, log.start, log.end)
    credited, warnings = credit_goals(log, attack)
    # A goal stops play: the referee may see it (by geometry) a moment before the simulator's event.
    ends = [b + GOAL_GRACE if goal else b for (_, b), goal in zip(intervals, goal_stops(log.referee, intervals))]
    in_play = [any(a <= g.goal.t <= e for (a, _), e in zip(intervals, ends)) for g in credited]
    refused = [t for t in (c.t for c in log.calls if c.kind == "goal_disallowed")]
    disallowed = [g for g, ok in zip(credited, in_play) if ok and any(0.0 <= t - g.goal.t <= GOAL_GRACE
                                                                        for t in refused)]
    goals = [g for g, ok in zip(credited, in_play) if ok and g not in disallowed]
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
    ball = log.tracks.get(world.ball_name)
    ball_in_play = ball_time_in_play(ball, intervals)
    if ball_in_play.total == 0.0:
        why = "no model of that name was recorded" if ball is None else "no sample falls in running time"
        warnings.append(f"no ball ({world.ball_name}) position during running time ({why}): the heat map is empty")
    reaches, dropped = ball_reaches(log.tracks, intervals, free_distance, reach_distance, world.ball_name)
    return MatchSummary(
        teams=teams, start=log.start, end=log.end, running_time=sum(b - a for a, b in intervals),
        goals=goals, goals_outside_play=stopped, goals_disallowed=disallowed, score=score,
        referee_score=referee_score,
        possession_seconds=possession(touch_sequence(log), intervals, log.end, teams),
        kicks=classify_kicks(log, intervals, attack, world.field, world.ball.rolling_friction * 9.8),
        distance_run={n: distance_run(tr, teleport_step) for n, tr in sorted(log.tracks.items()) if is_robot_name(n)},
        referee_events=referee_events(log.referee), coach_commands=log.coach, world=world,
        teleport_step=teleport_step, warnings=warnings,
        collisions=collisions(log.tracks, intervals, hull, contact_tolerance, separation_margin),
        ball_reaches=reaches, ball_reaches_dropped=dropped, ball_in_play=ball_in_play, hull_radius=hull,
        contact_tolerance=contact_tolerance, separation_margin=separation_margin, free_distance=free_distance,
        reach_distance=reach_distance, calls=sorted(log.calls, key=lambda c: c.t),
        stopped_time=stopped_time(log.referee, intervals))


def ball_time_in_play(ball: Track | None, intervals: Sequence[tuple[float, float]]) -> BallTime:
    """Return the ball samples whose covered time (``sample_durations``) overlaps running time, with that
    overlap [s] each."""
    if ball is None or len(ball.t) == 0:
        return BallTime(np.zeros((0, 2)), np.zeros(0))
    seconds = time_in_intervals(ball.t, ball.t + sample_durations(ball.t), intervals)
    keep = seconds > 0.0
    in_play = BallTime(ball.xy[keep], seconds[keep])
    ball.let_go()
    return in_play
