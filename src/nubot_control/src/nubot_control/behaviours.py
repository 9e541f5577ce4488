"""Behaviours: what one robot wants this cycle, given its role (team frame, own goal at -x).

Requires: ``TeamState`` and ``ControlParams``. Provides: ``Intent`` (a target pose, a speed
limit, whether the dribbler should be on, an optional kick (strength [m/s], ShootPos),
an optional pass plan) and one function per behaviour: ``chase_ball``, ``attack`` (with
the ball: shoot with a ground or lob shot, pass to a teammate, or dribble on),
``catch_pass``, ``support`` (defend, assist, midfield spots), ``mark`` and ``keep_goal``.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

from nubot_common.geometry import Pose2D, wrap_angle
from nubot_control.params import ControlParams
from nubot_control.role_allocation import support_positions
from nubot_control.roles import Role
from nubot_control.team_state import Mate, PassPlan, TeamState

GROUND = -1
LOB = 1
_BLOCK_RADIUS = 0.55  # an opponent this close to a kick's line blocks it [m]
_PRESSURE_RADIUS = 1.5  # an opponent this close makes the holder look for a pass [m]


class Action(IntEnum):
    STOP = 0
    POSITION = 1
    CHASE = 2
    DRIBBLE = 3
    SHOOT = 4
    PASS = 5
    CATCH = 6
    DEFEND = 7
    KEEP_GOAL = 8
    MARK = 9


@dataclass(frozen=True)
class Intent:
    target: Pose2D
    action: Action
    speed_limit: float | None = None  # [m/s]
    dribble: bool = False
    kick: tuple[int, int] | None = None  # (strength [m/s], ShootPos)
    pass_plan: PassPlan | None = None


def _facing(x: float, y: float, fx: float, fy: float) -> Pose2D:
    return Pose2D(x, y, math.atan2(fy - y, fx - x))


def line_is_clear(ax: float, ay: float, bx: float, by: float, obstacles: list[tuple[float, float]],
                  radius: float = _BLOCK_RADIUS) -> bool:
    """True when no obstacle lies within ``radius`` of the segment from A to B."""
    dx, dy = bx - ax, by - ay
    length2 = dx * dx + dy * dy
    for ox, oy in obstacles:
        t = 0.0 if length2 < 1e-12 else max(0.0, min(1.0, ((ox - ax) * dx + (oy - ay) * dy) / length2))
        if math.hypot(ax + t * dx - ox, ay + t * dy - oy) < radius:
            return False
    return True


def chase_ball(state: TeamState, params: ControlParams) -> Intent:
    """Go to the ball and face it, coming from the side away from the opponent goal when far."""
    me, ball = state.me.pose, state.ball
    dist = me.distance_to(ball.x, ball.y)
    goal_x = params.field.half_length
    if dist > 1.2:
        ux, uy = ball.x - goal_x, ball.y
        u = max(math.hypot(ux, uy), 1e-6)
        tx, ty = ball.x + ux / u * 0.6, ball.y + uy / u * 0.6  # behind the ball as seen from the goal
    else:
        heading = math.atan2(ball.y - me.y, ball.x - me.x)
        tx, ty = ball.x - 0.38 * math.cos(heading), ball.y - 0.38 * math.sin(heading)
    near = dist < params.play.grab_distance + 0.3
    return Intent(_facing(tx, ty, ball.x, ball.y), Action.CHASE, dribble=near)


def _aim_at_goal(state: TeamState, params: ControlParams) -> tuple[float, float]:
    f = params.field
    gx = f.half_length
    me = state.me.pose
    best, best_gap = (gx, 0.0), -1.0
    for y in (-0.35 * f.goal_width, 0.0, 0.35 * f.goal_width):
        gap = min((math.hypot(ox - gx, oy - y) for ox, oy in state.opponents if ox > me.x), default=10.0)
        if gap > best_gap + 1e-9:
            best, best_gap = (gx, y), gap
    return best


def _pass_target(state: TeamState, params: ControlParams) -> Mate | None:
    me = state.me.pose
    candidates = []
    for mate in state.mates:
        if not mate.valid or mate.agent_id == state.goalie_id:
            continue
        d = me.distance_to(mate.pose.x, mate.pose.y)
        if 2.0 < d < 8.0 and line_is_clear(me.x, me.y, mate.pose.x, mate.pose.y, list(state.opponents)):
            candidates.append(mate)
    return max(candidates, key=lambda m: (m.pose.x, -m.agent_id), default=None)


def attack(state: TeamState, params: ControlParams, wants_pass: bool = False) -> Intent:
    """With the ball: shoot when in range, else pass when pressed or asked to, else dribble on."""
    me, play, f = state.me.pose, params.play, params.field
    aim = _aim_at_goal(state, params)
    to_goal = me.distance_to(*aim)
    pressed = any(math.hypot(ox - me.x, oy - me.y) < _PRESSURE_RADIUS for ox, oy in state.opponents)
    if to_goal < play.shoot_range:
        face = _facing(me.x, me.y, *aim)
        if abs(wrap_angle(face.theta - me.theta)) < play.aim_tolerance:
            clear = line_is_clear(me.x, me.y, aim[0], aim[1], list(state.opponents))
            kind = GROUND if clear or to_goal > play.lob_range else LOB
            return Intent(face, Action.SHOOT, dribble=True, kick=(play.shot_speed, kind))
        return Intent(face, Action.SHOOT, speed_limit=0.3, dribble=True)
    mate = _pass_target(state, params) if (pressed or wants_pass) else None
    if mate is not None and mate.pose.x > me.x - 1.0:
        return pass_to(state, mate, params)
    tx = f.half_length - play.shoot_range + 1.0
    ty = max(-f.half_width + 1.0, min(f.half_width - 1.0, me.y * 0.5 + aim[1] * 0.5))
    return Intent(_facing(tx, ty, *aim), Action.DRIBBLE, speed_limit=params.motion.dribble_speed, dribble=True)


def pass_to(state: TeamState, mate: Mate, params: ControlParams) -> Intent:
    """Turn to ``mate`` on the spot and pass along the ground, at a speed that suits the distance."""
    me, play = state.me.pose, params.play
    plan = PassPlan(state.me.agent_id, mate.agent_id, mate.pose.x, mate.pose.y)
    face = _facing(me.x, me.y, mate.pose.x, mate.pose.y)
    if abs(wrap_angle(face.theta - me.theta)) < play.aim_tolerance * 1.5:
        d = me.distance_to(mate.pose.x, mate.pose.y)
        strength = int(round(max(3.0, min(8.0, play.pass_speed_per_metre * d))))
        return Intent(face, Action.PASS, dribble=True, kick=(strength, GROUND), pass_plan=plan)
    return Intent(face, Action.PASS, speed_limit=0.3, dribble=True, pass_plan=plan)


def catch_pass(state: TeamState, plan: PassPlan, params: ControlParams) -> Intent:
    """Stand at the catch point facing the ball, dribbler on."""
    ball = state.ball
    if plan.kicked and ball.known:
        # Meet the rolling ball on its line, as close to the catch point as possible.
        speed = math.hypot(ball.vx, ball.vy)
        if speed > 0.5:
            ux, uy = ball.vx / speed, ball.vy / speed
            t = max(0.0, (plan.catch_x - ball.x) * ux + (plan.catch_y - ball.y) * uy)
            x, y = ball.x + ux * t, ball.y + uy * t
            return Intent(_facing(x, y, ball.x, ball.y), Action.CATCH, dribble=True)
    return Intent(_facing(plan.catch_x, plan.catch_y, ball.x, ball.y), Action.CATCH, dribble=True)


def support(state: TeamState, role: Role, params: ControlParams) -> Intent:
    spots = support_positions(state.ball, params.field)
    x, y = spots.get(role, spots[Role.MIDFIELD])
    action = Action.DEFEND if role == Role.PASSIVE else Action.POSITION
    return Intent(_facing(x, y, state.ball.x, state.ball.y), action)


def mark(state: TeamState, opponent: tuple[float, float], params: ControlParams) -> Intent:
    """Stand between an opponent and the own goal, 1 m from the opponent."""
    ox, oy = opponent
    gx = -params.field.half_length
    dx, dy = gx - ox, -oy
    d = max(math.hypot(dx, dy), 1e-6)
    return Intent(_facing(ox + dx / d, oy + dy / d, state.ball.x, state.ball.y), Action.MARK)


def keep_goal(state: TeamState, params: ControlParams) -> Intent:
    """Guard the goal line; clear a slow ball that comes into the goal area."""
    f, ball, me = params.field, state.ball, state.me
    line_x = -f.half_length + 0.4
    if state.me.holding:
        face = _facing(me.pose.x, me.pose.y, 0.0, 3.0 if me.pose.y >= 0 else -3.0)
        ok = abs(wrap_angle(face.theta - me.pose.theta)) < 0.3
        return Intent(face, Action.KEEP_GOAL, dribble=True, kick=(8, GROUND) if ok else None, speed_limit=0.5)
    in_area = ball.x < -f.half_length + f.penalty_area_length and abs(ball.y) < f.penalty_area_width / 2
    if in_area and math.hypot(ball.vx, ball.vy) < 1.0:
        intent = chase_ball(state, params)
        return Intent(intent.target, Action.KEEP_GOAL, dribble=intent.dribble)
    y = ball.y
    if ball.vx < -0.5:  # the ball comes at the goal: stand where it will cross the line
        t = (line_x - ball.x) / ball.vx
        y = ball.y + ball.vy * t
    half = f.goal_width / 2 - 0.2
    y = max(-half, min(half, y))
    return Intent(_facing(line_x, y, ball.x, ball.y), Action.KEEP_GOAL)
