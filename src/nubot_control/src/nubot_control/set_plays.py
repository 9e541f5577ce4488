"""Formations for every game command, obeying the MSL distance rules (team frame, own goal at -x).

Requires: the MatchMode, the ball, the team's valid robots and their roles, ``PlayParams``.
Provides: ``formation`` -> ``Formation`` (a target pose per AgentID, the taker and the
receiver of our set piece: the chapter's static pass ``staticpassNum``/``staticcatchNum``).
Rules: at the opponent's set pieces every robot keeps ``set_play_distance`` (3 m) from the
ball, and at kickoffs stays in its own half, outside the centre circle for the opponent's;
at a drop ball everyone keeps ``drop_ball_distance`` (1 m). The field robots' spots lie on the field, out of the
penalty areas (the robot playing a drop ball: out of the goal areas) and 0.8 m apart, each the legal spot nearest
its place on a ring between the ball and the own goal (``_spots``). At the opponent's penalty only
the goalie stays near its goal, the others beyond the penalty area; PARKINGROBOT lines the
team up along the side line of its own half. ``KeptFormation`` holds one command's formation while its inputs stay
(the team, the roles, and the ball within ``HOLD_DISTANCE`` of where it was made).
"""

from __future__ import annotations

import functools
import math
from dataclasses import dataclass
from typing import Any

import numpy as np

from nubot_common.arrays import FloatArray
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import OUR_SET_PLAYS, THEIR_SET_PLAYS, MatchMode
from nubot_common.percepts import RobotReport
from nubot_common.team_play import Role
from nubot_common.world_state import FusedBall
from nubot_control.areas import AREA_MARGIN, in_area
from nubot_control.params import PlayParams

_MARGIN = 0.3  # kept beyond every rule distance [m]
_GOALIE_LINE = 0.4  # the goalie waits this far in front of its goal line [m]
_TAKER_GAP = 0.55  # the taker waits this far from the ball centre, facing it [m]
_APART = 0.8  # formation spots at least this far apart, centre to centre [m]
_AREA_GAP = 0.3  # formation spots this far beyond the motion layer's wall around a penalty area [m]


@dataclass(frozen=True)
class Formation:
    targets: dict[int, Pose2D]
    taker: int = 0  # AgentID that kicks our set piece (staticpassNum), 0 if none
    receiver: int = 0  # AgentID that receives it (staticcatchNum), 0 if none


_facing = Pose2D.looking_at
HOLD_DISTANCE = _MARGIN  # a formation made for a ball this far [m] from where it lies keeps every rule distance


class KeptFormation:
    """The formation of the command in force, made again only when the command, the team or the roles change or
    the ball moved more than ``HOLD_DISTANCE`` from where it was made. The fused estimate of a placed ball moves by a
    median 0.1 m from one cycle to the next (the set pieces of a seeded lockstep match): the spots stay where they are
    instead of following it, and the formation, which searches the field for legal spots, is not made every cycle."""

    def __init__(self) -> None:
        self._made: tuple[tuple[Any, ...], FieldGeometry, PlayParams, float, float, Formation] | None = None

    def clear(self) -> None:
        self._made = None

    def formation(self, mode: MatchMode, ball: FusedBall, team: list[RobotReport], roles: dict[int, Role],
                  field: FieldGeometry, play: PlayParams) -> Formation:
        """``formation``'s answer, the one kept while it holds."""
        inputs = (mode, tuple(m.agent_id for m in team), tuple(sorted(roles.items())))
        made = self._made
        if (made is not None and made[0] == inputs and made[1] is field and made[2] is play
                and math.hypot(ball.x - made[3], ball.y - made[4]) <= HOLD_DISTANCE):
            return made[5]
        plan = formation(mode, ball, team, roles, field, play)
        self._made = (inputs, field, play, ball.x, ball.y, plan)
        return plan


def keep_away(x: float, y: float, ball: FusedBall, radius: float) -> tuple[float, float]:
    """Push (x, y) radially out of the circle of ``radius`` around the ball (towards the own goal if on it)."""
    dx, dy = x - ball.x, y - ball.y
    d = math.hypot(dx, dy)
    if d >= radius:
        return x, y
    if d < 1e-6:
        dx, dy, d = -1.0, 0.0, 1.0
    return ball.x + dx / d * radius, ball.y + dy / d * radius


def _inside(x: float, y: float, field: FieldGeometry, margin: float = 0.5) -> tuple[float, float]:
    return (max(-field.half_length + margin, min(field.half_length - margin, x)),
            max(-field.half_width + margin, min(field.half_width - margin, y)))


def clear_of(x: float, y: float, ball: FusedBall, radius: float, field: FieldGeometry,
             margin: float = 0.5) -> tuple[float, float]:
    """The point nearest (x, y) that lies on the field, ``margin`` inside its lines, and at least ``radius`` from the
    ball: (x, y) itself, pushed out of the circle around the ball, or where the circle meets the lines there, so that
    a ball near a goal line or a corner never sends a robot off the field or behind a goal."""
    lo_x, hi_x = -field.half_length + margin, field.half_length - margin
    lo_y, hi_y = -field.half_width + margin, field.half_width - margin
    px, py = min(max(x, lo_x), hi_x), min(max(y, lo_y), hi_y)
    if math.hypot(px - ball.x, py - ball.y) >= radius:
        return px, py
    qx, qy = keep_away(px, py, ball, radius)
    candidates = [(qx, qy)] if lo_x <= qx <= hi_x and lo_y <= qy <= hi_y else []
    for line_x in (lo_x, hi_x):  # where the circle crosses the lines, each way
        h = radius * radius - (line_x - ball.x) ** 2
        candidates += [(line_x, ball.y + s * math.sqrt(h)) for s in (-1.0, 1.0) if h >= 0.0]
    for line_y in (lo_y, hi_y):
        h = radius * radius - (line_y - ball.y) ** 2
        candidates += [(ball.x + s * math.sqrt(h), line_y) for s in (-1.0, 1.0) if h >= 0.0]
    eps = 1e-9
    inside = [(cx, cy) for cx, cy in candidates if lo_x - eps <= cx <= hi_x + eps and lo_y - eps <= cy <= hi_y + eps]
    if not inside:  # the circle covers the whole field: as far as the field allows
        return min(max(qx, lo_x), hi_x), min(max(qy, lo_y), hi_y)
    return min(inside, key=lambda c: math.hypot(c[0] - x, c[1] - y))


def _goalie_spot(ball: FusedBall, field: FieldGeometry) -> Pose2D:
    y = max(-field.goal_width / 2 + 0.3, min(field.goal_width / 2 - 0.3, ball.y * 0.3))
    return _facing(-field.half_length + _GOALIE_LINE, y, ball.x, ball.y)


def _ring(ball: FusedBall, field: FieldGeometry, count: int, radius: float) -> list[tuple[float, float]]:
    """Ideal spots between the ball and the own goal on a ring ``radius`` around the ball, 0.6 rad apart."""
    own = (-field.half_length, 0.0)
    base = math.atan2(own[1] - ball.y, own[0] - ball.x)
    return [(ball.x + radius * math.cos(base + (k - (count - 1) / 2.0) * 0.6),
             ball.y + radius * math.sin(base + (k - (count - 1) / 2.0) * 0.6)) for k in range(count)]


def _legal(x: Any, y: Any, ball: FusedBall, radius: float, field: FieldGeometry,
           penalty_areas: bool) -> Any:  # x, y floats or arrays: a bool or a bool array
    """Where a field robot may wait: on the field 0.5 m inside its lines, ``radius`` or more from the ball, and out
    of both penalty areas (or, for the robot playing the ball, both goal areas) by more than the margin the motion
    layer walls them off with (``areas``)."""
    ok = (abs(x) <= field.half_length - 0.5 + 1e-9) & (abs(y) <= field.half_width - 0.5 + 1e-9)
    ok = ok & ((x - ball.x) ** 2 + (y - ball.y) ** 2 >= (radius - 1e-9) ** 2)
    for own in (True, False):
        ok = ok & ~in_area(x, y, field, own, not penalty_areas, AREA_MARGIN + _AREA_GAP)
    return ok


def _spots(ideals: list[tuple[float, float]], ball: FusedBall, radius: float, field: FieldGeometry,
           taken: tuple[tuple[float, float], ...] = (), penalty_areas: bool = True) -> list[tuple[float, float]]:
    """One spot per ideal spot, in order: the ideal one moved onto the field out of the circle (``clear_of``) where it
    is legal (``_legal``) and ``_APART`` from the spots already given (and from ``taken``), else the nearest such
    spot on rings around the ball. Near the own goal the ring runs through the penalty area, into which the motion
    layer would push every robot to the same point of its line."""
    chosen = list(taken)
    spots: list[tuple[float, float]] = []
    grid = None
    for ix, iy in ideals:
        x, y = clear_of(ix, iy, ball, radius, field)
        spot = (x, y)
        if not (_legal(x, y, ball, radius, field, penalty_areas)
                and all((x - px) ** 2 + (y - py) ** 2 >= _APART ** 2 for px, py in chosen)):
            if grid is None:
                gx, gy = _ring_offsets(radius)
                gx, gy = gx + ball.x, gy + ball.y
                legal = _legal(gx, gy, ball, radius, field, penalty_areas)
                grid = gx[legal], gy[legal]
            cost = (grid[0] - ix) ** 2 + (grid[1] - iy) ** 2
            if chosen:  # no spot within _APART of one chosen (all of them at once: (chosen, grid) arrays)
                px, py = np.array(chosen).T[:, :, None]
                cost[((grid[0] - px) ** 2 + (grid[1] - py) ** 2 < _APART ** 2).any(axis=0)] = np.inf
            k = int(np.argmin(cost)) if cost.size else -1
            if k >= 0 and np.isfinite(cost[k]):  # else the field has no room left: the clamped ideal spot
                spot = (float(grid[0][k]), float(grid[1][k]))
        spots.append(spot)
        chosen.append(spot)
    return spots


@functools.lru_cache(maxsize=8)
def _ring_offsets(radius: float) -> tuple[FloatArray, FloatArray]:
    """Points on rings from ``radius`` to ``radius + 2`` m around the origin, 0.5 m and 5 degrees apart."""
    angle = np.radians(np.arange(0.0, 360.0, 5.0))
    r = radius + np.arange(0.0, 2.01, 0.5)[:, None]
    return (r * np.cos(angle)).ravel(), (r * np.sin(angle)).ravel()


def formation(mode: MatchMode, ball: FusedBall, team: list[RobotReport], roles: dict[int, Role], field: FieldGeometry,
              play: PlayParams) -> Formation:
    """Target poses for ``mode`` (a set piece, drop ball, park or stop)."""
    ids = sorted(m.agent_id for m in team)
    goalie = play.goalie_id if play.goalie_id in ids else 0
    field_ids = sorted((i for i in ids if i != goalie), key=lambda i: (roles.get(i, Role.NOROLE) != Role.ACTIVE,
                                                                       roles.get(i, Role.NOROLE), i))
    poses = {m.agent_id: m.pose for m in team}
    targets: dict[int, Pose2D] = {}
    if goalie:
        targets[goalie] = _goalie_spot(ball, field)
    if mode == MatchMode.STOPROBOT:
        return Formation({i: poses[i] for i in ids})
    if mode == MatchMode.PARKINGROBOT:
        for k, i in enumerate(sorted(ids)):
            targets[i] = Pose2D(-1.0 - 1.2 * k, -field.half_width - 0.5, math.pi / 2)
        return Formation(targets)
    if mode in THEIR_SET_PLAYS - {MatchMode.OPP_KICKOFF, MatchMode.OPP_PENALTY} or mode == MatchMode.DROPBALL:
        # Everyone keeps the rule's distance: the goalie along its line, the field robots on spots between the ball
        # and the own goal; at a drop ball the robot playing the ball (first) waits right behind it.
        drop = mode == MatchMode.DROPBALL
        radius = (play.drop_ball_distance if drop else play.set_play_distance) + _MARGIN
        taken: tuple[tuple[float, float], ...] = ()
        if goalie:
            gx, gy = clear_of(targets[goalie].x, targets[goalie].y, ball, radius, field, _GOALIE_LINE)
            targets[goalie] = _facing(gx, gy, ball.x, ball.y)
            taken = ((gx, gy),)
        ring = _ring(ball, field, len(field_ids), radius + (1.0 if drop else 0.0))
        if drop and field_ids:
            ring[0] = (ball.x - radius, ball.y)
            first = _spots(ring[:1], ball, radius, field, taken, penalty_areas=False)
            spots = first + _spots(ring[1:], ball, radius, field, taken + tuple(first))
        else:
            spots = _spots(ring, ball, radius, field, taken)
        for i, (x, y) in zip(field_ids, spots):
            targets[i] = _facing(x, y, ball.x, ball.y)
        return Formation(targets)
    if mode in (MatchMode.OUR_KICKOFF, MatchMode.OPP_KICKOFF):
        return _kickoff(mode == MatchMode.OUR_KICKOFF, ball, field_ids, targets, field, play)
    if mode == MatchMode.OUR_PENALTY or mode == MatchMode.OPP_PENALTY:
        return _penalty(mode == MatchMode.OUR_PENALTY, ball, field_ids, targets, field, play)
    if mode in OUR_SET_PLAYS:
        return _our_restart(ball, field_ids, targets, field, play)
    return Formation({i: poses[i] for i in ids})  # STARTROBOT, TEST: no formation


def _kickoff(ours: bool, ball: FusedBall, ids: list[int], targets: dict[int, Pose2D], field: FieldGeometry,
             play: PlayParams) -> Formation:
    circle = field.center_circle_radius + _MARGIN
    spots = [(-circle - 0.5, 0.0), (-4.0, -3.0), (-4.0, 3.0), (-6.0, 0.0)]
    taker = receiver = 0
    if ours and ids:
        taker = ids[0]
        targets[taker] = _facing(ball.x - _TAKER_GAP, ball.y, ball.x, ball.y)
        if len(ids) > 1:
            receiver = ids[1]
            targets[receiver] = _facing(-1.0, 2.5, ball.x, ball.y)
        rest = ids[2:]
        spots = [(-4.0, -3.0), (-6.0, 0.0), (-4.0, 3.0)]
    else:
        rest = ids
    for i, (x, y) in zip(rest, spots):
        targets[i] = _facing(min(x, -0.3), y, ball.x, ball.y)
    return Formation(targets, taker, receiver)


def _penalty(ours: bool, ball: FusedBall, ids: list[int], targets: dict[int, Pose2D], field: FieldGeometry,
             play: PlayParams) -> Formation:
    spot_x = (1.0 if ours else -1.0) * (field.half_length - field.penalty_mark_distance)
    line_x = 0.0 if ours else -field.half_length + field.penalty_area_length + play.set_play_distance + _MARGIN
    taker = 0
    rest = ids
    if ours and ids:
        taker, rest = ids[0], ids[1:]
        targets[taker] = _facing(spot_x - _TAKER_GAP, 0.0, field.half_length, 0.0)
    for k, i in enumerate(rest):
        y = (k - (len(rest) - 1) / 2.0) * 1.5
        x = line_x - 1.0 if ours else max(line_x, -field.half_length + field.penalty_area_length + 1.0)
        x, y = keep_away(x, y, FusedBall(spot_x, 0.0), play.set_play_distance + _MARGIN)
        targets[i] = _facing(x, y, spot_x, 0.0)
    return Formation(targets, taker)


def _our_restart(ball: FusedBall, ids: list[int], targets: dict[int, Pose2D], field: FieldGeometry,
                 play: PlayParams) -> Formation:
    if not ids:
        return Formation(targets)
    taker = ids[0]
    receiver = ids[1] if len(ids) > 1 else 0
    # The receiver stands 3 m away, towards the opponent goal and the middle of the field.
    towards = (min(ball.x + 2.5, field.half_length - 1.5), ball.y * 0.4)
    dx, dy = towards[0] - ball.x, towards[1] - ball.y
    d = max(math.hypot(dx, dy), 1e-6)
    rx, ry = _inside(ball.x + dx / d * 3.0, ball.y + dy / d * 3.0, field)
    aim = (rx, ry) if receiver else (field.half_length, 0.0)
    ax, ay = aim[0] - ball.x, aim[1] - ball.y
    a = max(math.hypot(ax, ay), 1e-6)
    targets[taker] = _facing(ball.x - ax / a * _TAKER_GAP, ball.y - ay / a * _TAKER_GAP, ball.x, ball.y)
    if receiver:
        targets[receiver] = _facing(rx, ry, ball.x, ball.y)
    placed = tuple((p.x, p.y) for p in targets.values())  # the goalie, the taker and the receiver
    spots = _spots(_ring(ball, field, max(len(ids) - 2, 0), 4.0), ball, 1.0, field, placed)
    for i, (x, y) in zip(ids[2:], spots):
        targets[i] = _facing(x, y, ball.x, ball.y)
    return Formation(targets, taker, receiver)
