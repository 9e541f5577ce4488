"""Every shot with its outcome and every goal explained, from the plain records of one match (no ROS).

Requires: a ``MatchLog`` (kicks with their ball velocity in 3-D, touches, goals with the ball's height, model
tracks, referee states, coach commands, each team's goalie), the ``MatchSummary`` that ``match_analysis.analyse``
made of it (teams, goals credited, kicks classified) and the match's ``WorldDescription`` (field [m], ball radius).
Provides: ``explain`` -> ``ShotReport``: every ``Shot`` (where from, speed, kind, on target or not, and its outcome:
goal, saved, blocked or wide) and every goal's ``GoalAnatomy`` (time, scorer and assist, the shot, its height at the
line, what led to it, where the goalie and the nearest defenders were); ``to_json()``; ``shot_counts``. The shot map
is ``match_plots.plot_shot_map``.

Definitions (``DEFINITIONS`` repeats them in report.json):

- shot: a kick in play towards the goal its team attacks from at most ``SHOT_DISTANCE`` (10 m) from its centre: a
  lob (kind 1), or a ground kick whose straight line crosses the attacked goal line within ``SHOT_WIDE_MARGIN``
  (1 m) outside a post and that rolls that far (``match_analysis.is_shot``); on target:
  that line crosses between the posts (a lob: also below the bar, in a flight without drag);
- a shot's outcome, by the first of: a goal for its team within ``SHOT_TIME`` (4 s) with no touch by the shooter's
  team in between (touches by defenders deflect it) -> goal (disallowed: the referee did not count it); a touch by
  another robot: the defending goalie -> saved, another defender -> blocked, a teammate -> wide; a stop of play, the
  shooter's own next touch or the end of the recording -> wide;
- a goal's shot: the shot that ended in it; without one the ball was pushed in (no kick) or it is an own goal;
  scorer: the shooter, else the last robot of the scoring team to touch the ball (own goal: the defender who
  touched it last); assist: the teammate whose completed pass the scorer received last, within ``ASSIST_TIME``
  (10 s) before the goal;
- height at the line: the ball centre's height when the simulator saw it in the goal [m];
- own goal: the defending team touched the ball last and no shot of the scoring team went in (a shot a defender
  deflected in is the shooter's goal);
- what led to a goal, the first that holds: own goal; set piece (the scoring
  team's restart started the running play within ``SET_PIECE_TIME`` (15 s) before the goal, and no defender touched
  the ball since); rebound (a shot by the scoring team was saved, blocked or went wide within ``REBOUND_TIME`` (5 s)
  before the goal's shot); scramble (at least ``SCRAMBLE_TOUCHES`` (3) changes of the last toucher, both teams
  among them, within ``SCRAMBLE_TIME`` (3 s) before the goal); turnover (the scoring team won the ball from the
  defenders in open play within ``TURNOVER_TIME`` (10 s) before the goal); else build-up (a longer possession);
- goalie and defenders: positions at the goal's shot (else at the goal) interpolated from the model tracks; the
  goalie is the team's goalie (``MatchLog.goalies``, else AgentID 1); each with its distance from the shot's line
  (from the ball where it was kicked to where that line crosses the goal line) [m]; the two nearest defenders are
  the field robots of the defending team nearest that line.
"""

from __future__ import annotations

import bisect
import math
from collections.abc import Sequence
from dataclasses import dataclass, field

import numpy as np

from nubot_common.commands import KickKind
from nubot_common.field import FieldGeometry
from nubot_common.naming import team_of
from nubot_common.world_description import WorldDescription
from nubot_match import match_analysis as ma

SHOT_TIME = 4.0  # a shot scores only this soon after the kick [s]
ASSIST_TIME = 10.0  # [s]
SET_PIECE_TIME = 15.0  # [s]
REBOUND_TIME = 5.0  # [s]
SCRAMBLE_TIME = 3.0  # [s]
SCRAMBLE_TOUCHES = 3
TURNOVER_TIME = 10.0  # [s]
GRAVITY = 9.8  # [m/s^2]
OUTCOMES = ("goal", "saved", "blocked", "wide", "disallowed")
CAUSES = ("own goal", "set piece", "rebound", "scramble", "turnover", "build-up")
_SET_PIECES = {1, 3, 5, 7, 9, 11}  # MatchMode OUR_KICKOFF .. OUR_FREEKICK, in the team's own view
_STARTROBOT = 15

DEFINITIONS = {
    "shot": f"a kick in play towards the attacked goal from at most {ma.SHOT_DISTANCE:g} m from its centre: any lob "
            f"(kind 1) towards it, or a ground "
            f"kick whose straight line crosses the attacked goal line within {ma.SHOT_WIDE_MARGIN:g} m outside a post "
            "and that rolls that far at the ball's deceleration (a slower one is a pass); "
            "on target: between the posts (a lob also below the bar, flight without drag)",
    "shot_outcome": f"goal: a goal for the shooter's team within {SHOT_TIME:g} s, no touch by that team in between "
                    "(disallowed: one the referee did not count); "
                    "else the first touch by another robot: the defending goalie -> saved, another defender -> "
                    "blocked, a teammate -> wide; a stop of play, the shooter's own next touch or the end -> wide",
    "own_goal": "the defenders touched the ball last and no shot of the scoring team went in (a deflected shot is the "
                "shooter's goal)",
    "scorer": "the shooter of the goal's shot, else the scoring team's last toucher (own goal: the defender)",
    "assist": f"the teammate whose completed pass the scorer received last, within {ASSIST_TIME:g} s of the goal",
    "height_at_line_m": "ball centre height when the simulator saw the ball in the goal",
    "cause": f"first that holds: own goal; set piece (own restart started play within {SET_PIECE_TIME:g} s before "
             f"the goal, no defender touch since); rebound (a shot saved, blocked or wide within {REBOUND_TIME:g} s "
             f"before the goal's shot); scramble (>= {SCRAMBLE_TOUCHES} changes of last toucher, both teams, within "
             f"{SCRAMBLE_TIME:g} s before the goal); turnover (ball won from the defenders in open play within "
             f"{TURNOVER_TIME:g} s before the goal); else build-up",
    "goalie_and_defenders": "positions at the goal's shot (else at the goal) from the model tracks, each with its "
                            "distance from the shot's line (kick point to where it crosses the goal line)",
}


@dataclass(frozen=True)
class Shot:
    t: float  # [s]
    robot: str
    team: str
    kind: int  # -1 ground, 1 lob
    origin: tuple[float, float]  # ball where it was kicked, world frame [m]
    target: tuple[float, float]  # where its line crosses the attacked goal line (x = side * half length) [m]
    side: int  # the attacked goal: +1 at +x, -1 at -x
    speed: float  # initial ball speed [m/s]
    distance: float  # from the kick point to the attacked goal's centre [m]
    on_target: bool
    outcome: str  # one of OUTCOMES
    by: str = ""  # the robot that saved, blocked or received it
    half: int = 0

    def origin_attacking_right(self) -> tuple[float, float]:
        """The kick point as if the team attacked +x (for one shot map per team)."""
        return self.origin[0] * self.side, self.origin[1] * self.side


@dataclass(frozen=True)
class Defender:
    robot: str
    xy: tuple[float, float]  # world frame [m]
    line_distance: float  # from the shot's line [m]


@dataclass(frozen=True)
class GoalAnatomy:
    goal: ma.CreditedGoal
    own_goal: bool  # the defenders put it in, and no shot of the scoring team did (a deflected shot is not one)
    scorer: str
    assist: str
    shot: Shot | None  # None: pushed in without a kick, or an own goal without the scoring team's shot
    height: float  # ball centre at the line [m], NaN unknown
    cause: str  # one of CAUSES
    goalie: Defender | None
    defenders: tuple[Defender, ...]  # the two field defenders nearest the shot's line


@dataclass
class ShotReport:
    teams: list[str]
    shots: list[Shot]
    goals: list[GoalAnatomy]
    halves: int = 1  # halves the match had (at least one)
    goalies: dict[str, str] = field(default_factory=dict)

    def shot_counts(self) -> dict[str, dict[str, int]]:
        """Per team: shots, on target, and each outcome."""
        counts = {t: {"shots": 0, "on_target": 0, **dict.fromkeys(OUTCOMES, 0)} for t in self.teams}
        for s in self.shots:
            c = counts.setdefault(s.team, {"shots": 0, "on_target": 0, **dict.fromkeys(OUTCOMES, 0)})
            c["shots"] += 1
            c["on_target"] += s.on_target
            c[s.outcome] += 1
        return counts

    def cause_counts(self) -> dict[str, int]:
        counts = dict.fromkeys(CAUSES, 0)
        for g in self.goals:
            counts[g.cause] += 1
        return counts

    def to_json(self) -> dict:
        r3 = _round3

        def xy(p: tuple[float, float]) -> list[float]:
            return [r3(p[0]), r3(p[1])]

        def defender(d: Defender | None) -> dict | None:
            return None if d is None else {"robot": d.robot, "xy": xy(d.xy), "line_distance_m": r3(d.line_distance)}

        def shot(s: Shot) -> dict:
            return {"t": r3(s.t), "robot": s.robot, "team": s.team, "kind": "lob" if s.kind == KickKind.LOB else "flat",
                    "origin": xy(s.origin), "target": xy(s.target), "speed_mps": r3(s.speed),
                    "distance_m": r3(s.distance), "on_target": s.on_target, "outcome": s.outcome, "by": s.by,
                    "half": s.half}

        return {
            "goalies": self.goalies,
            "counts": self.shot_counts(),
            "causes": self.cause_counts(),
            "shots": [shot(s) for s in self.shots],
            "goals": [{"t": r3(g.goal.goal.t), "half": g.goal.half,
                       "game_time": None if g.goal.game_time is None else r3(g.goal.game_time),
                       "team": g.goal.team, "scorer": g.scorer, "assist": g.assist, "own_goal": g.own_goal,
                       "cause": g.cause, "shot": None if g.shot is None else shot(g.shot),
                       "height_at_line_m": None if math.isnan(g.height) else r3(g.height),
                       "goalie": defender(g.goalie), "defenders": [defender(d) for d in g.defenders]}
                      for g in self.goals],
            "definitions": DEFINITIONS,
        }


def _round3(x: float) -> float:
    return round(float(x), 3)


# --- shots --------------------------------------------------------------------------------------------------


def on_target(kick: ma.Kick, side: int, field: FieldGeometry, ball_radius: float, height: float) -> bool:
    """The kick's line crosses the goal line between the posts; a lob also under the bar (``height``: the ball
    centre's height at the kick [m]; no drag, bounces count as under the bar)."""
    crossing = ma.shot_line(kick, side, field)
    if crossing is None or abs(crossing[1]) > field.goal_width / 2.0:
        return False
    if kick.kind != 1:
        return True
    vx, vz = kick.velocity[0], kick.velocity[2]
    t = (crossing[0] - kick.ball_xy[0]) / vx
    z = height + vz * t - 0.5 * GRAVITY * t * t
    return z < field.goal_height - ball_radius


def _first_after(times: Sequence[float], t: float) -> int:
    return bisect.bisect_right(times, t)


def classify_shots(summary: ma.MatchSummary, log: ma.MatchLog, goalies: dict[str, str]) -> list[Shot]:
    """Every shot of the match with its outcome (see ``DEFINITIONS``)."""
    f, radius = summary.world.field, summary.world.ball.radius
    touches = ma.touch_sequence(log)
    touch_times = [x.t for x in touches]
    intervals = ma.running_intervals(log.referee, log.start, log.end)
    default = ma.default_attack_for(summary.teams, *_default_attack(summary))
    shots = []
    for k in summary.kicks:
        if not k.shot:
            continue
        side = ma.attack_at(log.referee, k.kick.t, default).get(k.team, 0)
        crossing = ma.shot_line(k.kick, side, f) or (side * f.half_length, k.kick.ball_xy[1])
        stop = intervals[ma.inside(k.kick.t, intervals)][1]
        outcome, by = _outcome(k, side, summary, touches, touch_times, stop, goalies)
        state = ma.state_at(log.referee, k.kick.t)
        vx, vy, vz = k.kick.velocity
        shots.append(Shot(k.kick.t, k.kick.robot, k.team, k.kick.kind, k.kick.ball_xy, crossing, side,
                          math.sqrt(vx * vx + vy * vy + vz * vz),
                          math.hypot(side * f.half_length - k.kick.ball_xy[0], k.kick.ball_xy[1]),
                          on_target(k.kick, side, f, radius, radius), outcome, by, state.half if state else 0))
    return shots


def _default_attack(summary: ma.MatchSummary) -> tuple[str, int]:
    return (summary.teams[0], 1) if summary.teams else ("nubot", 1)


def _outcome(k: ma.KickOutcome, side: int, summary: ma.MatchSummary, touches: Sequence[ma.Touch],
             touch_times: Sequence[float], stop: float, goalies: dict[str, str]) -> tuple[str, str]:
    t0 = k.kick.t
    goal = next((g for g in (*summary.goals, *summary.goals_disallowed)
                 if t0 < g.goal.t <= t0 + SHOT_TIME and g.goal.side == side), None)
    for touch in touches[_first_after(touch_times, t0):]:
        if goal is not None and goal.goal.t <= touch.t:
            break
        if touch.t >= stop:
            return "wide", ""
        if touch.robot == k.kick.robot:
            if goal is None:
                return "wide", ""
            goal = None  # the shooter touched it again before the goal: it scored from that, not from this kick
            continue
        if team_of(touch.robot) == k.team:
            return "wide", touch.robot
        if goal is not None:
            continue  # a defender deflected it on its way in
        return ("saved" if goalies.get(team_of(touch.robot)) == touch.robot else "blocked"), touch.robot
    if goal is not None:
        return ("disallowed" if goal in summary.goals_disallowed else "goal"), ""
    return "wide", ""


# --- goals --------------------------------------------------------------------------------------------------


def explain(summary: ma.MatchSummary, log: ma.MatchLog) -> ShotReport:
    """Every shot and every goal of the match explained (see ``DEFINITIONS``)."""
    goalies = {team: log.goalies.get(team, f"{team}1") for team in summary.teams}
    shots = classify_shots(summary, log, goalies)
    touches = ma.touch_sequence(log)
    intervals = ma.running_intervals(log.referee, log.start, log.end)
    goals = [_anatomy(g, summary, log, shots, touches, intervals, goalies) for g in summary.goals]
    halves = max([1, *(s.half for s in log.referee)])
    return ShotReport(list(summary.teams), shots, goals, halves, goalies)


def _anatomy(g: ma.CreditedGoal, summary: ma.MatchSummary, log: ma.MatchLog, shots: Sequence[Shot],
             touches: Sequence[ma.Touch], intervals: Sequence[tuple[float, float]],
             goalies: dict[str, str]) -> GoalAnatomy:
    t = g.goal.t
    defending = next((team for team in summary.teams if team != g.team), "")
    shot = next((s for s in reversed(shots) if s.outcome == "goal" and s.team == g.team and s.t < t <= s.t + SHOT_TIME
                 and s.side == g.goal.side), None)
    before = [x for x in touches if x.t <= t]
    own_goal = g.own_goal and shot is None  # a shot that a defender deflected in is the shooter's goal
    if shot is not None:
        scorer = shot.robot
    elif own_goal:
        scorer = g.goal.last_touch
    else:
        scorer = next((x.robot for x in reversed(before) if team_of(x.robot) == g.team), g.goal.last_touch)
    assist = ""
    if not own_goal:
        received = [k for k in summary.kicks if k.pass_outcome == "completed" and k.receiver == scorer
                    and t - ASSIST_TIME <= k.kick.t < (shot.t if shot else t)]
        assist = received[-1].kick.robot if received else ""
    cause = "own goal" if own_goal else _cause(g, shot, shots, before, intervals, log, defending)
    at = shot.t if shot is not None else t
    goalie, defenders = _defenders(log, defending, goalies.get(defending, ""), at, shot, g, summary.world)
    return GoalAnatomy(g, own_goal, scorer, assist, shot, g.goal.height, cause, goalie, defenders)


def _cause(g: ma.CreditedGoal, shot: Shot | None, shots: Sequence[Shot], before: Sequence[ma.Touch],
           intervals: Sequence[tuple[float, float]], log: ma.MatchLog, defending: str) -> str:
    t = g.goal.t
    i = ma.inside(t, intervals)
    if i < 0:  # within the grace after the stop
        i = max((j for j, (a, _) in enumerate(intervals) if a <= t), default=-1)
    start = intervals[i][0] if i >= 0 else log.start
    restart = _restart_before(log, g.team, start)
    defended = [x for x in before if x.t >= start and team_of(x.robot) == defending]
    if restart in _SET_PIECES and t - start <= SET_PIECE_TIME and not defended:
        return "set piece"
    struck = shot.t if shot is not None else t
    if any(s.team == g.team and s.outcome != "goal" and struck - REBOUND_TIME <= s.t < struck for s in shots):
        return "rebound"
    first = bisect.bisect_left([x.t for x in before], max(t - SCRAMBLE_TIME, start))
    changes = sum(1 for j in range(max(first, 1), len(before)) if before[j].robot != before[j - 1].robot)
    if changes >= SCRAMBLE_TOUCHES and {team_of(x.robot) for x in before[first:]} >= {g.team, defending}:
        return "scramble"
    won = next((j for j in range(len(before) - 1, 0, -1)
                if team_of(before[j].robot) == g.team and team_of(before[j - 1].robot) == defending), None)
    if won is not None and before[won].t >= start and t - before[won].t <= TURNOVER_TIME and \
            all(team_of(x.robot) == g.team for x in before[won:]):
        return "turnover"
    return "build-up"


def _restart_before(log: ma.MatchLog, team: str, start: float) -> int | None:
    """The last command other than STARTROBOT that ``team`` got up to ``start`` (its own view), if any."""
    modes = [c.match_mode for c in log.coach if c.team == team and c.t <= start + 1e-6 and c.match_mode != _STARTROBOT]
    return modes[-1] if modes else None


def _defenders(log: ma.MatchLog, team: str, goalie: str, t: float, shot: Shot | None, g: ma.CreditedGoal,
               world: WorldDescription) -> tuple[Defender | None, tuple[Defender, ...]]:
    robots = sorted(n for n in log.tracks if team_of(n) == team and n != world.ball_name)
    if not robots:
        return None, ()
    positions = ma.resample([log.tracks[r] for r in robots], np.array([t]))[0]
    if shot is not None:
        a, b = shot.origin, shot.target
    else:
        a = b = g.goal.ball_xy
    out = []
    for robot, (x, y) in zip(robots, positions):
        if math.isnan(x):
            continue
        out.append(Defender(robot, (float(x), float(y)), _segment_distance((x, y), a, b)))
    keeper = next((d for d in out if d.robot == goalie), None)
    field_players = sorted((d for d in out if d.robot != goalie), key=lambda d: d.line_distance)
    return keeper, tuple(field_players[:2])


def _segment_distance(p: tuple[float, float], a: tuple[float, float], b: tuple[float, float]) -> float:
    dx, dy = b[0] - a[0], b[1] - a[1]
    length2 = dx * dx + dy * dy
    s = 0.0 if length2 < 1e-12 else max(0.0, min(1.0, ((p[0] - a[0]) * dx + (p[1] - a[1]) * dy) / length2))
    return math.hypot(a[0] + s * dx - p[0], a[1] + s * dy - p[1])


def goal_lines(report: ShotReport) -> list[str]:
    """One line per goal, as a person reads it."""
    lines = []
    for g in report.goals:
        clock = "" if g.goal.game_time is None else f"half {g.goal.half} {_mmss(g.goal.game_time)}"
        who = f"own goal by {g.scorer}" if g.own_goal else f"{g.scorer or '?'}"
        if g.assist:
            who += f" (assist {g.assist})"
        if g.shot is not None:
            s = g.shot
            x, y = s.origin_attacking_right()
            kind = "lob" if s.kind == KickKind.LOB else "flat"
            how = f"{kind} {s.speed:.1f} m/s from ({x:+.1f}, {y:+.1f}) attacking +x, {s.distance:.1f} m out"
        else:
            how = "no shot" if g.own_goal else "no shot (pushed in)"
        height = "" if math.isnan(g.height) else f", {g.height:.2f} m high at the line"
        keeper = "" if g.goalie is None else f"; goalie {g.goalie.robot} {g.goalie.line_distance:.1f} m off the line"
        backs = ", ".join(f"{d.robot} {d.line_distance:.1f} m" for d in g.defenders)
        lines.append(f"{clock} {g.goal.team or '?'}: {who}; {how}{height}; {g.cause}{keeper}"
                     + (f"; nearest defenders {backs}" if backs else ""))
    return lines


def _mmss(seconds: float) -> str:
    return f"{int(seconds // 60):d}:{int(seconds % 60):02d}"
