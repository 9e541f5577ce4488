"""Behaviours: what one robot wants this cycle, given its role (team frame, own goal at -x).

Requires: ``TeamState`` (with the field) and ``ControlParams``. Provides: ``Intent`` (a target
pose, a speed limit, whether the dribbler should be on, an optional ``KickCommand``, an optional
pass command) and one function per behaviour: ``chase_ball``, ``search_ball`` (the ball is not
known: go towards where it was last seen, stop short of it and turn on the spot), ``attack`` (with
the ball: shoot with a ground or lob shot, pass to a teammate, or dribble on), ``catch_pass``,
``support`` (defend, assist, midfield spots), ``mark`` and ``keep_goal``. No behaviour drives to a
ball the world model does not know.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from enum import IntEnum

from nubot_common.ball_flight import time_to_x
from nubot_common.commands import KickCommand, KickKind
from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.percepts import RobotReport
from nubot_common.team_play import PassCommand, Role
from nubot_control.params import ControlParams
from nubot_control.role_allocation import support_positions
from nubot_control.team_state import TeamState

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
    SEARCH = 10


@dataclass(frozen=True)
class Intent:
    target: Pose2D
    action: Action
    speed_limit: float | None = None  # [m/s]
    dribble: bool = False
    kick: KickCommand | None = None
    pass_cmd: PassCommand | None = None


_facing = Pose2D.looking_at


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


def search_ball(state: TeamState, params: ControlParams) -> Intent:
    """The ball is not known: keep ``search_distance`` from where it was last seen, then turn on the spot."""
    me, ball = state.me.pose, state.ball
    dist = max(me.distance_to(ball.x, ball.y), 1e-6)
    keep = params.play.search_distance
    x, y = ball.x + (me.x - ball.x) / dist * keep, ball.y + (me.y - ball.y) / dist * keep
    if dist > keep + 0.3:
        return Intent(_facing(x, y, ball.x, ball.y), Action.SEARCH)
    return Intent(Pose2D(x, y, wrap_angle(me.theta + params.play.search_turn)), Action.SEARCH)  # keeps turning


def chase_ball(state: TeamState, params: ControlParams) -> Intent:
    """Go to the ball and face it, coming from the side away from the opponent goal when far."""
    me, ball = state.me.pose, state.ball
    if not ball.known:
        return search_ball(state, params)
    dist = me.distance_to(ball.x, ball.y)
    goal_x = state.field.half_length
    if dist > 1.2:
        ux, uy = ball.x - goal_x, ball.y
        u = max(math.hypot(ux, uy), 1e-6)
        tx, ty = ball.x + ux / u * 0.6, ball.y + uy / u * 0.6  # behind the ball as seen from the goal
    else:
        heading = math.atan2(ball.y - me.y, ball.x - me.x)
        tx, ty = ball.x - 0.38 * math.cos(heading), ball.y - 0.38 * math.sin(heading)
    near = dist < params.play.grab_distance + 0.3
    # No faster at the ball than the ball handler keeps it (dribble_speed), braking for it in time.
    m = params.motion
    arrive = math.sqrt(m.dribble_speed ** 2 + 2.0 * m.max_accel * max(dist - params.play.grab_distance, 0.0))
    return Intent(_facing(tx, ty, ball.x, ball.y), Action.CHASE, speed_limit=arrive, dribble=near)


def _aim_at_goal(state: TeamState, params: ControlParams) -> tuple[float, float]:
    f = state.field
    gx = f.half_length
    me = state.me.pose
    best, best_gap = (gx, 0.0), -1.0
    for y in (-0.35 * f.goal_width, 0.0, 0.35 * f.goal_width):
        gap = min((math.hypot(ox - gx, oy - y) for ox, oy in state.opponents if ox > me.x), default=10.0)
        if gap > best_gap + 1e-9:
            best, best_gap = (gx, y), gap
    return best


def _pass_target(state: TeamState, params: ControlParams) -> RobotReport | None:
    me = state.me.pose
    candidates = []
    for mate in state.mates:
        if mate.agent_id == state.goalie_id:
            continue
        d = me.distance_to(mate.pose.x, mate.pose.y)
        if 2.0 < d < 8.0 and line_is_clear(me.x, me.y, mate.pose.x, mate.pose.y, list(state.opponents)):
            candidates.append(mate)
    return max(candidates, key=lambda m: (m.pose.x, -m.agent_id)) if candidates else None


def attack(state: TeamState, params: ControlParams, wants_pass: bool = False) -> Intent:
    """With the ball: shoot when in range, else pass when pressed or asked to, else dribble on."""
    me, play, f = state.me.pose, params.play, state.field
    aim = _aim_at_goal(state, params)
    to_goal = me.distance_to(*aim)
    pressed = any(math.hypot(ox - me.x, oy - me.y) < _PRESSURE_RADIUS for ox, oy in state.opponents)
    if to_goal < play.shoot_range:
        face = _facing(me.x, me.y, *aim)
        if abs(wrap_angle(face.theta - me.theta)) < play.aim_tolerance:
            clear = line_is_clear(me.x, me.y, aim[0], aim[1], list(state.opponents))
            kind = KickKind.GROUND if clear or to_goal > play.lob_range else KickKind.LOB
            return Intent(face, Action.SHOOT, dribble=True, kick=KickCommand(kind, play.shot_speed))
        return Intent(face, Action.SHOOT, speed_limit=0.3, dribble=True)
    mate = _pass_target(state, params) if (pressed or wants_pass) else None
    if mate is not None and mate.pose.x > me.x - 1.0:
        return pass_to(state, mate, params)
    tx = f.half_length - play.shoot_range + 1.0
    ty = max(-f.half_width + 1.0, min(f.half_width - 1.0, me.y * 0.5 + aim[1] * 0.5))
    return Intent(_facing(tx, ty, *aim), Action.DRIBBLE, speed_limit=params.motion.dribble_speed, dribble=True)


def pass_to(state: TeamState, mate: RobotReport, params: ControlParams, static: bool = False) -> Intent:
    """Turn to ``mate`` on the spot and pass along the ground, at a speed that suits the distance."""
    me, play = state.me.pose, params.play
    plan = PassCommand(state.me.agent_id, mate.agent_id, (me.x, me.y), (mate.pose.x, mate.pose.y),
                       is_dynamic_pass=not static, is_static_pass=static)
    face = _facing(me.x, me.y, mate.pose.x, mate.pose.y)
    if abs(wrap_angle(face.theta - me.theta)) < play.aim_tolerance * 1.5:
        d = me.distance_to(mate.pose.x, mate.pose.y)
        strength = int(round(max(3.0, min(8.0, play.pass_speed_per_metre * d))))
        return Intent(face, Action.PASS, dribble=True, kick=KickCommand(KickKind.GROUND, strength), pass_cmd=plan)
    return Intent(face, Action.PASS, speed_limit=0.3, dribble=True, pass_cmd=plan)


def catch_pass(state: TeamState, plan: PassCommand, params: ControlParams) -> Intent:
    """Stand at the catch point facing the ball, dribbler on."""
    ball = state.ball
    cx, cy = plan.catch_pt
    if plan.is_passout and ball.known:
        # Meet the rolling ball on its line, as close to the catch point as possible.
        speed = math.hypot(ball.vx, ball.vy)
        if speed > 0.5:
            ux, uy = ball.vx / speed, ball.vy / speed
            t = max(0.0, (cx - ball.x) * ux + (cy - ball.y) * uy)
            x, y = ball.x + ux * t, ball.y + uy * t
            return Intent(_facing(x, y, ball.x, ball.y), Action.CATCH, dribble=True)
    return Intent(_facing(cx, cy, ball.x, ball.y), Action.CATCH, dribble=True)


def support(state: TeamState, role: Role, params: ControlParams) -> Intent:
    """Hold the role's spot; with the ball lost, the spots stay where they were for its last position."""
    spots = support_positions(state.ball, state.field)
    x, y = spots.get(role, spots[Role.MIDFIELD])
    action = Action.DEFEND if role == Role.PASSIVE else Action.POSITION
    return Intent(_facing(x, y, state.ball.x, state.ball.y), action)


def mark(state: TeamState, opponent: tuple[float, float], params: ControlParams) -> Intent:
    """Stand between an opponent and the own goal, 1 m from the opponent."""
    ox, oy = opponent
    gx = -state.field.half_length
    dx, dy = gx - ox, -oy
    d = max(math.hypot(dx, dy), 1e-6)
    return Intent(_facing(ox + dx / d, oy + dy / d, state.ball.x, state.ball.y), Action.MARK)


def keep_goal(state: TeamState, params: ControlParams) -> Intent:
    """Guard the goal: meet a lob where it comes down into the goal (the RGB-D cameras' flight), stand where a ball
    coming at the goal crosses the guarded line, else on the line from the goal's centre to the ball; clear a slow
    ball in the goal area; the goal's centre when the ball is lost."""
    f, ball, me, play = state.field, state.ball, state.me, params.play
    line_x = -f.half_length + play.goalie_line
    if state.me.holding:
        face = _facing(me.pose.x, me.pose.y, 0.0, 3.0 if me.pose.y >= 0 else -3.0)
        ok = abs(wrap_angle(face.theta - me.pose.theta)) < 0.3
        kick = KickCommand(KickKind.GROUND, 8) if ok else None
        return Intent(face, Action.KEEP_GOAL, dribble=True, kick=kick, speed_limit=0.5)
    lob = _meet_lob(state, params)
    if lob is not None:
        return lob
    if not ball.known:
        return Intent(Pose2D(line_x, 0.0, 0.0), Action.KEEP_GOAL)
    in_area = ball.x < -f.half_length + f.penalty_area_length and abs(ball.y) < f.penalty_area_width / 2
    if in_area and math.hypot(ball.vx, ball.vy) < 1.0:
        intent = chase_ball(state, params)
        return Intent(intent.target, Action.KEEP_GOAL, dribble=intent.dribble)
    if ball.vx < -0.5:  # the ball comes at the goal: stand where it will cross the line
        t = (line_x - ball.x) / ball.vx
        y = ball.y + ball.vy * t
    else:  # on the line from the goal's centre to the ball: the angle a shot has is shared out evenly
        y = ball.y * play.goalie_line / max(ball.x + f.half_length, play.goalie_line)
    half = f.goal_width / 2 - 0.2
    y = max(-half, min(half, y))
    return Intent(_facing(line_x, y, ball.x, ball.y), Action.KEEP_GOAL)


def _meet_lob(state: TeamState, params: ControlParams) -> Intent | None:
    """Where to meet a ball flying at the goal: where it comes down in front of the goal, or where it crosses the
    lob line (just ahead of the goal line, where a lob aimed under the bar is lowest); None for any other ball."""
    flight, f, play = state.flight, state.field, params.play
    if flight is None or flight.touchdown is None or flight.ball.vx > -0.5:
        return None
    b = flight.ball
    stand_x = -f.half_length + play.lob_line
    x, y, _ = flight.touchdown
    if x < stand_x:  # it would land in the goal: meet it on the lob line
        t = time_to_x(b.x, b.vx, stand_x)
        if t is None:
            return None
        x, y = stand_x, b.y + b.vy * t
    if abs(y) > f.goal_width / 2 + 0.5:  # wide of the goal
        return None
    return Intent(_facing(x, y, b.x, b.y), Action.KEEP_GOAL)
