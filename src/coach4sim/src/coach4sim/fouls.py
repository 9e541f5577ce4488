"""The fouls the automatic referee calls and whether a goal counts, under the MSL rules (docs/rules.md), pure.

Requires: ``RefereeParams`` (the field [m], the robots' radius [m], the rules' numbers), the teams as they play now
(``TeamSpec``: prefix, attacked goal, goalie) and, during play, every snapshot the referee judges (sim time [s], the
ball and every robot's position in the world frame [m], the robot holding the ball, the robots that touched or kicked
the ball since the previous snapshot).
Provides: ``RefereeCall`` (what was called: kind, the team and robot that committed it, where, the rule, in words),
``FoulWatch.update`` -> the foul of a snapshot, if any:

- carrying (RC-12.0.1): a robot keeps the ball more than ``carry_distance`` (3 m, straight line) from where it caught
  it; the circle moves only after a release anyone can see (the ball ``release_distance`` from the robot, or another
  robot touched it);
- charging (RC-12.3.2): a robot comes into contact with an opponent moving towards it faster than ``charge_speed``;
- pushing (RC-12.3.2): in contact with an opponent, a robot keeps moving towards it faster than ``push_speed`` for
  ``push_time``;
- illegal defence (RC-12.3.4, RC-12.3.10): a second field robot in its own penalty area, one there longer than
  ``area_time``, or a field robot in its own goal area (the goalie may stay);
- illegal attack (RC-12.3.5, RC-12.3.10): a second robot in the opponents' penalty area, one there longer than
  ``area_time``, or one in their goal area;

``restart_spot`` (where a free kick is taken: the ball, or the nearest restart point from a penalty area, RC-13.4.1)
and ``GoalCheck`` (a goal counts unless it came straight from the scoring team's own set piece before another of its
robots touched the ball (RC-8.4.1, RC-13), from a dropped ball before two robots touched it (RC-8.6), or from a shot
taken in the scoring team's own half (RC-10.1.1)). Robot speeds come from their displacement between snapshots. A
robot is in an area when its centre is, the line included.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from coach4sim.params import RefereeParams, TeamSpec
from nubot_common.field import FieldGeometry
from nubot_common.naming import is_robot_name, team_of

FOULS = ("carrying", "charging", "pushing", "illegal_defence", "illegal_attack")  # calls that stop play for a foul
OTHER_CALLS = ("goal_disallowed", "slow_restart")
_CONTACT_TOLERANCE = 0.03  # robots closer than their two radii and this touch [m]
_TELEPORT_SPEED = 10.0  # a robot seemingly faster than this was moved by hand, not driven [m/s]


@dataclass(frozen=True)
class RefereeCall:
    kind: str  # one of FOULS or OTHER_CALLS
    team: str  # the team that committed it
    robot: str  # the robot that committed it ("" the team)
    position: tuple[float, float]  # where: the ball for carrying and areas, the robot for contact [m]
    rule: str
    text: str
    restart: str = ""  # the restart it gave, in words, filled by the referee ("" play goes on)
    time: float = 0.0  # [s]
    penalty: bool = False  # a foul in the offender's own penalty area that gives a penalty kick

    @property
    def is_foul(self) -> bool:
        return self.kind in FOULS


def in_penalty_area(x: float, y: float, attack: int, f: FieldGeometry, own: bool = True) -> bool:
    """Whether (x, y) lies in the penalty area of the team attacking ``attack`` (its own, or the one it attacks):
    between the goal line and the area's line, both included (behind the goal line is outside the field, not in the
    area)."""
    towards = -attack if own else attack  # the goal line of that area lies at towards * half_length
    depth = x * towards
    return f.half_length - f.penalty_area_length <= depth <= f.half_length and abs(y) <= f.penalty_area_width / 2.0


def in_goal_area(x: float, y: float, attack: int, f: FieldGeometry, own: bool = True) -> bool:
    """As ``in_penalty_area``, for the goal area."""
    towards = -attack if own else attack
    depth = x * towards
    return f.half_length - f.goal_area_length <= depth <= f.half_length and abs(y) <= f.goal_area_width / 2.0


def restart_spot(x: float, y: float, f: FieldGeometry, margin: float) -> tuple[float, float]:
    """Where a free kick for a foul with the ball at (x, y) is taken: there (inside the lines by ``margin``), or from
    a penalty area the nearest restart point (on the lines through the penalty marks, halfway to the touch lines)."""
    if any(in_penalty_area(x, y, side, f) for side in (1, -1)):
        mark = f.half_length - f.penalty_mark_distance
        spots = [(sx * mark, sy * f.half_width / 2.0) for sx in (1, -1) for sy in (1, -1)]
        return min(spots, key=lambda s: math.hypot(s[0] - x, s[1] - y))
    return (min(max(x, -(f.half_length - margin)), f.half_length - margin),
            min(max(y, -(f.half_width - margin)), f.half_width - margin))


@dataclass
class _Carry:
    robot: str
    catch: tuple[float, float]  # where it caught the ball [m]


class FoulWatch:
    def __init__(self, params: RefereeParams):
        self.params = params
        self._previous: tuple[float, Mapping[str, tuple[float, float]]] | None = None
        self._carry: _Carry | None = None
        self._contact: set[tuple[str, str]] = set()
        self._pushing_since: dict[tuple[str, str], float] = {}  # (pusher, pushed) -> since [s]
        self._inside_since: dict[tuple[str, str], float] = {}  # (robot, area) -> since [s]

    def reset(self) -> None:
        """Play stopped: contacts, pushes and times in the areas start anew when it resumes; the ball's carrier
        too (a restart is a new catch)."""
        self._previous, self._carry = None, None
        self._contact.clear()
        self._pushing_since.clear()
        self._inside_since.clear()

    def update(self, t: float, ball: tuple[float, float], robots: Mapping[str, tuple[float, float]], holder: str,
               touched: Sequence[str], teams: Sequence[TeamSpec]) -> RefereeCall | None:
        """The foul of this snapshot (the first one found), if any."""
        players = {name: xy for name, xy in robots.items() if is_robot_name(name)}
        velocities = self._velocities(t, players)
        self._previous = (t, dict(players))
        by_prefix = {spec.prefix: spec for spec in teams}
        return (self._carrying(ball, players, holder, touched, by_prefix)
                or self._contacts(t, players, velocities, by_prefix)
                or self._areas(t, ball, players, by_prefix))

    def _velocities(self, t: float, robots: Mapping[str, tuple[float, float]]) -> dict[str, tuple[float, float]]:
        if self._previous is None or t - self._previous[0] <= 1e-6:
            return {name: (0.0, 0.0) for name in robots}
        t0, before = self._previous
        dt = t - t0
        velocities = {}
        for name, (x, y) in robots.items():
            vx, vy = ((x - before[name][0]) / dt, (y - before[name][1]) / dt) if name in before else (0.0, 0.0)
            # faster than any robot drives: it was put there (a reset, a test), it did not move
            velocities[name] = (vx, vy) if math.hypot(vx, vy) <= _TELEPORT_SPEED else (0.0, 0.0)
        return velocities

    # --- carrying (RC-12.0.1) ------------------------------------------------------------------------------
    def _carrying(self, ball: tuple[float, float], robots: Mapping[str, tuple[float, float]], holder: str,
                  touched: Sequence[str], teams: Mapping[str, TeamSpec]) -> RefereeCall | None:
        p, carry = self.params, self._carry
        if carry is not None:
            away = carry.robot not in robots or math.dist(robots[carry.robot], ball) > p.release_distance
            others = any(r != carry.robot for r in touched) or (holder and holder != carry.robot)
            if (holder != carry.robot and away) or others:
                carry = self._carry = None  # released for all to see: the next catch starts a new circle
        if holder and team_of(holder) in teams and carry is None:
            carry = self._carry = _Carry(holder, ball)
        if carry is None or holder != carry.robot:
            return None
        carried = math.dist(ball, carry.catch)
        if carried <= p.carry_distance:
            return None
        self._carry = None
        return RefereeCall("carrying", team_of(holder), holder, ball, "RC-12.0.1",
                           f"{holder} carried the ball {carried:.2f} m from where it caught it (at most "
                           f"{p.carry_distance:g} m)")

    # --- contact (RC-12.3.2) -------------------------------------------------------------------------------
    def _contacts(self, t: float, robots: Mapping[str, tuple[float, float]],
                  velocities: Mapping[str, tuple[float, float]], teams: Mapping[str, TeamSpec]) -> RefereeCall | None:
        p = self.params
        touching = 2.0 * p.world.robot.radius + _CONTACT_TOLERANCE
        names = sorted(n for n in robots if team_of(n) in teams)
        contact: set[tuple[str, str]] = set()
        call = None
        for i, a in enumerate(names):
            for b in names[i + 1:]:
                if team_of(a) == team_of(b):
                    continue
                (ax, ay), (bx, by) = robots[a], robots[b]
                distance = math.hypot(bx - ax, by - ay)
                if distance >= touching or distance < 1e-9:
                    continue
                contact.add((a, b))
                ux, uy = (bx - ax) / distance, (by - ay) / distance
                towards = {a: velocities[a][0] * ux + velocities[a][1] * uy,
                           b: -(velocities[b][0] * ux + velocities[b][1] * uy)}
                mover = max((a, b), key=lambda r: (towards[r], r))
                other = b if mover == a else a
                if (a, b) not in self._contact and towards[mover] > p.charge_speed and call is None:
                    call = self._contact_foul("charging", mover, other, robots, teams,
                                              f"{mover} ran into {other} at {towards[mover]:.1f} m/s (at most "
                                              f"{p.charge_speed:g} m/s into an opponent)")
                for pusher, pushed in ((a, b), (b, a)):
                    key = (pusher, pushed)
                    if towards[pusher] <= p.push_speed:
                        self._pushing_since.pop(key, None)
                        continue
                    since = self._pushing_since.setdefault(key, t)
                    if t - since >= p.push_time and call is None:
                        call = self._contact_foul("pushing", pusher, pushed, robots, teams,
                                                  f"{pusher} kept pushing {pushed} for {t - since:.1f} s (at most "
                                                  f"{p.push_time:g} s into an opponent)")
        for key in list(self._pushing_since):
            if tuple(sorted(key)) not in contact:
                del self._pushing_since[key]
        self._contact = contact
        if call is not None:
            self._pushing_since.clear()
        return call

    def _contact_foul(self, kind: str, offender: str, victim: str, robots: Mapping[str, tuple[float, float]],
                      teams: Mapping[str, TeamSpec], text: str) -> RefereeCall:
        x, y = robots[offender]
        own_area = in_penalty_area(x, y, teams[team_of(offender)].attack, self.params.field)
        return RefereeCall(kind, team_of(offender), offender, (x, y), "RC-12.3.2", text,
                           penalty=own_area)

    # --- the areas (RC-12.3.4, RC-12.3.5, RC-12.3.10) ------------------------------------------------------
    def _areas(self, t: float, ball: tuple[float, float], robots: Mapping[str, tuple[float, float]],
               teams: Mapping[str, TeamSpec]) -> RefereeCall | None:
        p, f = self.params, self.params.field
        inside: set[tuple[str, str]] = set()
        call = None
        for prefix, spec in teams.items():
            goalie = f"{prefix}{spec.goalie}"
            members = sorted(n for n in robots if team_of(n) == prefix)
            for own, kind, rule in ((True, "illegal_defence", "RC-12.3.4"), (False, "illegal_attack", "RC-12.3.5")):
                players = [n for n in members if not (own and n == goalie)]
                area = [n for n in players if in_penalty_area(*robots[n], spec.attack, f, own)]
                goal_area = [n for n in players if in_goal_area(*robots[n], spec.attack, f, own)]
                for n in area:
                    inside.add((n, kind))
                    self._inside_since.setdefault((n, kind), t)
                if call is not None:
                    continue
                whose = "its own" if own else "the opponents'"
                if goal_area:
                    call = RefereeCall(kind, prefix, goal_area[0], ball, "RC-12.3.10",
                                       f"{goal_area[0]} in {whose} goal area")
                elif len(area) > p.area_robots:
                    latest = max(area, key=lambda n: (self._inside_since[(n, kind)], n))
                    call = RefereeCall(kind, prefix, latest, ball, rule,
                                       f"{len(area)} {'field robots' if own else 'robots'} of {prefix} in {whose} "
                                       f"penalty area (at most {p.area_robots})")
                else:
                    longest = [n for n in area if t - self._inside_since[(n, kind)] > p.area_time]
                    if longest:
                        call = RefereeCall(kind, prefix, longest[0], ball, rule,
                                           f"{longest[0]} in {whose} penalty area for more than {p.area_time:g} s")
        for key in list(self._inside_since):
            if key not in inside:
                del self._inside_since[key]
        return call


@dataclass
class GoalCheck:
    """Whether a goal counts (RC-8.4.1, RC-8.6, RC-10.1.1, RC-13): fed with every restart and every touch."""

    restart: str = ""  # the restart that started the play now running (``RestartKind`` words; "" by hand or none)
    restart_team: str = ""  # the team that took it ("" a dropped ball)
    touchers: list[str] = field(default_factory=list)  # robots that touched the ball since, in order, distinct
    last_touch: dict[str, tuple[str, tuple[float, float]]] = field(default_factory=dict)  # team -> (robot, where)

    def started(self, restart: str, team: str) -> None:
        """Play resumed with ``restart`` (e.g. "kickoff", "dropped ball", "" for a restart by hand) by ``team``."""
        self.restart, self.restart_team = restart, team
        self.touchers = []
        self.last_touch = {}

    def touched(self, robot: str, where: tuple[float, float] | None) -> None:
        if robot not in self.touchers:
            self.touchers.append(robot)
        if where is not None:
            self.last_touch[team_of(robot)] = (robot, where)

    def disallowed(self, team: str, attack: int, own_goal: bool) -> tuple[str, str]:
        """Why a goal for ``team`` (attacking ``attack``) does not count and the rule, or ("", "") if it does."""
        if own_goal:
            return "", ""
        if self.restart == "dropped ball" and len(self.touchers) < 2:
            return "no goal straight from a dropped ball: two robots must touch the ball first", "RC-8.6"
        if self.restart and self.restart not in ("dropped ball", "penalty") and self.restart_team == team:
            mine = [r for r in self.touchers if team_of(r) == team]
            if len(mine) < 2:
                rule = "RC-8.4.1" if self.restart == "kickoff" else "RC-13"
                return (f"no goal straight from {team}'s {self.restart}: another of its robots must touch the ball "
                        "first", rule)
        shooter = self.last_touch.get(team)
        if shooter is not None and shooter[1][0] * attack < 0.0:
            return (f"{shooter[0]} shot from its own half (x = {shooter[1][0]:+.1f} m): a goal counts only from a "
                    "shot in the opponents' half", "RC-10.1.1")
        return "", ""
