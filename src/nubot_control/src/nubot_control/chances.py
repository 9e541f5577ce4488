"""How likely a shot scores and whether a pass gets through: what the ball carrier weighs (team frame, goal at +x).

Requires: the field, the ball [m], the opponents' positions [m] (their goalie: the one nearest the goal's centre in
front of it), the kick's speed [m/s] and spread, ``ChanceParams``. Provides:

- ``shot_chance`` -> ``Shot`` (the best aim point across the goal mouth and its chance to score): the kick's
  direction scatters (``kick_direction_std``, plus the aim's own error); for each way it may go the ball must cross
  the goal line between the posts, pass the goalie beyond its reach (what it covers from where it stands in the time
  the ball takes to reach it, after ``reaction``) and pass every other opponent the same way; the chance is the share
  of the scatter that does, integrated over ``SAMPLES`` points of the normal distribution;
- ``lob_chance``: the same for a lob (which flies over field robots but not over the goalie, and whose height at the
  line scatters with the kick's speed: too high goes over the bar);
- ``pass_margin``: how much sooner [s] the ball reaches each point of a pass's line than any opponent can (negative:
  it can be intercepted); the ball slows at ``rolling_decel``.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np

from nubot_common.arrays import FloatArray
from nubot_common.field import FieldGeometry

SAMPLES = np.array([-2.0, -1.5, -1.0, -0.5, 0.0, 0.5, 1.0, 1.5, 2.0])  # standard normal quadrature nodes
_WEIGHTS = np.exp(-0.5 * SAMPLES ** 2)
WEIGHTS = _WEIGHTS / _WEIGHTS.sum()
AIMS = 9  # aim points across the goal mouth


@dataclass(frozen=True)
class ChanceParams:
    kick_direction_std: float = math.radians(2.0)  # the kick's scatter and the aim's error together [rad]
    kick_speed_std: float = 0.05  # the kick's speed scatter, a share of its speed
    reaction: float = 0.15  # an opponent starts moving this long after the kick [s]
    opponent_speed: float = 3.0  # how fast an opponent may go [m/s]
    opponent_accel: float = 3.0  # ... and speed up [m/s^2]
    robot_radius: float = 0.26  # [m]
    ball_radius: float = 0.11  # [m]
    rolling_decel: float = 0.78  # [m/s^2]
    goal_height: float = 1.0  # [m]
    robot_height: float = 0.75  # a lob lower than this (plus the ball's radius) hits the robot under it [m]
    lob_bar_margin: float = 0.15  # a lob is aimed to cross the line with its top this far under the bar [m]
    lob_horizontal_speed: float = 6.0  # [m/s]
    lob_max_flight_time: float = 1.6  # [s]
    lob_max_speed: float = 8.6  # [m/s]
    gravity: float = 9.8  # [m/s^2]


@dataclass(frozen=True)
class Shot:
    aim: tuple[float, float]  # on the goal line [m]
    chance: float  # of scoring, 0..1


def goalie_of(opponents: Sequence[tuple[float, float]], field: FieldGeometry) -> int | None:
    """The index of the opponent that keeps the goal at +x: the one nearest its centre, if within its penalty area."""
    best, best_d = None, math.inf
    for i, (x, y) in enumerate(opponents):
        d = math.hypot(field.half_length - x, y)
        if x > field.half_length - field.penalty_area_length and abs(y) < field.penalty_area_width / 2 and d < best_d:
            best, best_d = i, d
    return best


def _in_the_way(bx: float, by: float, ux: float, uy: float, length: float, speed: float,
                opponents: FloatArray, p: ChanceParams, over: Sequence[bool]) -> bool:
    """Whether an opponent the ball does not fly over (``over``, per opponent) can be in its way before it travels
    ``length`` along (ux, uy): one whose distance from the line is within its reach (robot and ball radius plus its
    move in the time the ball takes to get level with it)."""
    for (ox, oy), above in zip(opponents, over):
        along = (ox - bx) * ux + (oy - by) * uy
        if above or not 0.0 < along < length:
            continue
        side = abs((ox - bx) * uy - (oy - by) * ux)
        if side < p.robot_radius + p.ball_radius + float(_reach_array(np.array(along / speed), p)):
            return True
    return False


def _reach_array(t: FloatArray, p: ChanceParams) -> FloatArray:
    """How far [m] an opponent moves in each of the times ``t`` [s] after the kick (reacting, then speeding up to its
    top speed)."""
    t = np.maximum(t - p.reaction, 0.0)
    t_top = p.opponent_speed / p.opponent_accel
    return np.where(t <= t_top, 0.5 * p.opponent_accel * t * t,
                    0.5 * p.opponent_accel * t_top * t_top + p.opponent_speed * (t - t_top))


def shot_chances(balls: Sequence[tuple[float, float]], opponents: Sequence[tuple[float, float]],
                 field: FieldGeometry, speed: float, p: ChanceParams) -> list[Shot]:
    """``shot_chance`` for several ball positions at once (one array computation)."""
    gx = field.half_length
    half = field.goal_width / 2.0 - p.ball_radius
    b = np.asarray(balls, dtype=float).reshape(-1, 1, 1, 2)  # (N, 1, 1, 2)
    aims = np.linspace(-half * 0.85, half * 0.85, AIMS)  # (A,)
    bx, by = b[..., 0], b[..., 1]  # (N, 1, 1)
    theta = np.arctan2(aims[None, :, None] - by, gx - bx) + p.kick_direction_std * SAMPLES[None, None, :]  # N, A, S
    ux, uy = np.cos(theta), np.sin(theta)
    forward = ux > 1e-6
    safe_ux = np.where(forward, ux, 1.0)
    y_line = by + (gx - bx) * uy / safe_ux
    on_target = forward & (np.abs(y_line) < half) & (bx < gx)
    length = (gx - bx) / safe_ux
    opp = np.asarray(opponents, dtype=float).reshape(-1, 2)
    if len(opp):
        dx = opp[:, 0] - bx[..., None]  # (N, 1, 1, K)
        dy = opp[:, 1] - by[..., None]
        along = dx * ux[..., None] + dy * uy[..., None]  # (N, A, S, K)
        side = np.abs(dx * uy[..., None] - dy * ux[..., None])
        reach = p.robot_radius + p.ball_radius + _reach_array(along / speed, p)
        blocked = ((along > 0.0) & (along < length[..., None]) & (side < reach)).any(axis=-1)
        on_target &= ~blocked
    chance = (on_target * WEIGHTS).sum(axis=-1)  # (N, A)
    best = chance.argmax(axis=1)
    return [Shot((gx, float(aims[k])), float(chance[n, k])) for n, k in enumerate(best)]


def shot_chance(ball: tuple[float, float], opponents: Sequence[tuple[float, float]], field: FieldGeometry,
                speed: float, p: ChanceParams) -> Shot:
    """The best aim across the goal mouth at +x for a flat shot at ``speed`` [m/s], and its chance to score."""
    return shot_chances([ball], opponents, field, speed, p)[0]


def lob_chance(ball: tuple[float, float], opponents: Sequence[tuple[float, float]], field: FieldGeometry,
               p: ChanceParams) -> float:
    """The chance that a lob from ``ball`` straight at the goal's centre scores: its height at the line scatters with
    its speed (too high: over the bar); it flies over field robots where it is above them, not over the goalie."""
    bx, by = ball
    gx = field.half_length
    distance = math.hypot(gx - bx, by)
    if distance < 1.0:
        return 0.0
    g = p.gravity
    horizontal = max(p.lob_horizontal_speed, distance / p.lob_max_flight_time)
    flight = distance / horizontal
    top = field.goal_height - p.lob_bar_margin - p.ball_radius
    vz = (top - p.ball_radius + 0.5 * g * flight * flight) / flight
    scale = min(1.0, p.lob_max_speed / math.hypot(horizontal, vz))
    horizontal, vz = horizontal * scale, vz * scale
    opp = np.asarray(opponents, dtype=float).reshape(-1, 2)
    ux, uy = (gx - bx) / distance, -by / distance
    chance = 0.0
    for s, w in zip(1.0 + p.kick_speed_std * SAMPLES, WEIGHTS):
        h, v = horizontal * s, vz * s

        def height(x: float, h: float = h, v: float = v) -> float:
            t = x / h
            return p.ball_radius + v * t - 0.5 * g * t * t

        at_line = height(distance)
        if at_line > field.goal_height - p.ball_radius:
            continue  # over the bar
        if at_line < p.ball_radius and height(distance - 1.0) < p.ball_radius:
            continue  # lands well short
        over = [height(max((ox - bx) * ux + (oy - by) * uy, 0.0)) > p.robot_height + p.ball_radius
                for ox, oy in opp]
        if not _in_the_way(bx, by, ux, uy, distance, h, opp, p, over):
            chance += float(w)
    return chance


def ball_time(distance: float, speed: float, decel: float) -> float:
    """When [s] a ball kicked at ``speed`` [m/s] slowing at ``decel`` [m/s^2] has rolled ``distance`` [m] (inf:
    never)."""
    if decel <= 0.0:
        return distance / speed
    disc = speed * speed - 2.0 * decel * distance
    if disc < 0.0:
        return math.inf
    return (speed - math.sqrt(disc)) / decel


def pass_margin(ball: tuple[float, float], target: tuple[float, float], speed: float,
                opponents: Sequence[tuple[float, float]], p: ChanceParams, step: float = 0.5) -> float:
    """The least time [s] by which the ball, kicked at ``speed`` [m/s] from ``ball`` to ``target``, is ahead of every
    opponent at the points of its line (every ``step`` [m]); an opponent there in time intercepts it (negative)."""
    bx, by = ball
    length = math.hypot(target[0] - bx, target[1] - by)
    if length < 1e-6:
        return math.inf
    ux, uy = (target[0] - bx) / length, (target[1] - by) / length
    margin = math.inf
    for s in np.arange(min(0.6, length), length + 1e-9, step):
        px, py = bx + ux * s, by + uy * s
        t_ball = ball_time(float(s), speed, p.rolling_decel)
        for ox, oy in opponents:
            gap = max(math.hypot(ox - px, oy - py) - p.robot_radius - p.ball_radius, 0.0)
            t_opp = _time_to_cover(gap, p)
            margin = min(margin, t_opp - t_ball)
    return margin


def _time_to_cover(distance: float, p: ChanceParams) -> float:
    """How long [s] an opponent needs to move ``distance`` [m] (reacting, speeding up, at top speed)."""
    d_top = 0.5 * p.opponent_speed ** 2 / p.opponent_accel
    if distance <= d_top:
        return p.reaction + math.sqrt(2.0 * distance / p.opponent_accel)
    return p.reaction + p.opponent_speed / p.opponent_accel + (distance - d_top) / p.opponent_speed
