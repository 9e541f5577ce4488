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
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D, wrap_angle
from nubot_common.percepts import RobotReport
from nubot_common.records import fast_init
from nubot_common.team_play import PassCommand, Role
from nubot_control.chances import ChanceParams, lob_chance, pass_margin, shot_chance, shot_chances
from nubot_control.params import ControlParams
from nubot_control.role_allocation import support_positions
from nubot_control.team_state import TeamState

_BLOCK_RADIUS = 0.55  # an opponent this close to a kick's line blocks it [m]
_MIN_PASS = 2.5  # shorter passes only pass the pressure on [m]
_CLEAR_SPEED = 8  # a clearance [m/s]
_MEET_STEP = 0.8  # a receiver meets a pass this far up the ball's line from where it stands [m]
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


@fast_init
@dataclass(frozen=True)
class Intent:
    target: Pose2D
    action: Action
    speed_limit: float | None = None  # [m/s]
    dribble: bool = False
    kick: KickCommand | None = None
    pass_cmd: PassCommand | None = None
    urgent: bool = False  # no plan: straight there, as fast as the limits allow (the goalie stepping into a shot)


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


def _pressed(state: TeamState, radius: float = _PRESSURE_RADIUS) -> bool:
    me = state.me.pose
    return any(math.hypot(ox - me.x, oy - me.y) < radius for ox, oy in state.opponents)


@dataclass(frozen=True)
class PassOption:
    mate: RobotReport
    value: float  # the receiver's chance to score from where it stands, plus a little for the ground it gains
    margin: float  # [s] by which the ball beats every opponent along the line (``chances.pass_margin``)


def pass_options(state: TeamState, params: ControlParams, cp: ChanceParams) -> list[PassOption]:
    """The passes to teammates (not the goalie) 2.5-9 m away, best first, with what each is worth (the receiver's
    chance to score from where it stands and the ground it gains, less the pressure it is under) and how safe."""
    me, f, play = state.me.pose, state.field, params.play
    ball = (state.ball.x, state.ball.y)
    mates = [m for m in state.mates if m.agent_id != state.goalie_id
             and _MIN_PASS < me.distance_to(m.pose.x, m.pose.y) < 9.0]
    if not mates:
        return []
    chances = shot_chances([(m.pose.x, m.pose.y) for m in mates], state.opponents, f, play.shot_speed, cp)
    options = []
    for mate, shot in zip(mates, chances):
        speed = max(3.0, min(8.0, play.pass_speed_per_metre * me.distance_to(mate.pose.x, mate.pose.y)))
        margin = pass_margin(ball, (mate.pose.x, mate.pose.y), speed, state.opponents, cp)
        in_range = math.hypot(f.half_length - mate.pose.x, mate.pose.y) < play.shot_range
        marked = min((math.hypot(ox - mate.pose.x, oy - mate.pose.y) for ox, oy in state.opponents), default=9.0)
        pressure = max(0.0, _PRESSURE_RADIUS - marked) / _PRESSURE_RADIUS  # a receiver pressed at once is worth less
        value = (shot.chance if in_range else 0.0) + 0.03 * (mate.pose.x - me.x) - 0.3 * pressure
        options.append(PassOption(mate, value, margin))
    return sorted(options, key=lambda o: (-o.value, o.mate.agent_id))


def attack(state: TeamState, params: ControlParams, cp: ChanceParams, carried: float = 0.0,
           wants_pass: bool = False, caught_at: tuple[float, float] | None = None, held: float = 0.0) -> Intent:
    """With the ball: shoot when the shot's chance to score is good (``shot_threshold``), else pass when a safe
    pass is worth more or the robot is pressed or asked to, else dribble towards a better shot (or away from the
    pressure) within ``carry_limit`` of where it caught the ball (``caught_at``); when the ball has been carried
    ``carry_limit``, or held for ``hold_limit`` [s] (``held``), it must go: the best shot or pass there is, else it
    is pushed ahead and taken again (the rules allow that, not carrying it on)."""
    play, f = params.play, state.field
    ball = (state.ball.x, state.ball.y)
    must_go = carried >= play.carry_limit or held >= play.hold_limit
    to_goal = math.hypot(f.half_length - ball[0], ball[1])
    flat = shot_chance(ball, state.opponents, f, play.shot_speed, cp) if to_goal < play.shot_range else None
    lob = lob_chance(ball, state.opponents, f, cp) if 3.0 < to_goal < play.lob_range else 0.0
    shot = max(flat.chance if flat is not None else 0.0, lob)
    options = pass_options(state, params, cp)
    pressed = _pressed(state)
    safe = [o for o in options if o.margin >= play.pass_margin]  # pressed or not: a pass cut off near
    # our goal is a shot against us (most goals came from a ball won within 5 m of the goal)
    best_pass = safe[0].value if safe else -1.0
    if shot >= (play.last_chance if must_go else play.shot_threshold) and shot >= best_pass:
        if lob > (flat.chance if flat is not None else 0.0):
            return _shoot(state, (f.half_length, 0.0), KickCommand(KickKind.LOB, play.shot_speed), params)
        assert flat is not None
        return _shoot(state, flat.aim, KickCommand(KickKind.GROUND, play.shot_speed), params)
    if safe and (must_go or wants_pass or pressed or best_pass > shot + 0.15) and \
            (best_pass > -0.1 or ball[0] >= 0.0):
        return pass_to(state, safe[0].mate, params)
    if (pressed or must_go) and (caught_at or ball)[0] < 0.0:  # pressed in our half (where it was caught: a ball
        # on the halfway line must not flip the choice every cycle) with no pass forward: clear it up the field
        return clear(state, params, cp, Action.DRIBBLE)
    if must_go:
        if options:  # the least unsafe pass
            return pass_to(state, max(options, key=lambda o: o.margin).mate, params)
        if shot > 0.0 and flat is not None:
            return _shoot(state, flat.aim, KickCommand(KickKind.GROUND, play.shot_speed), params)
        return _push_ahead(state, params)
    return _dribble(state, params, cp, caught_at)


def _shoot(state: TeamState, aim: tuple[float, float], kick: KickCommand, params: ControlParams) -> Intent:
    """Turn on the spot to the aim and kick once facing it within ``shot_aim_tolerance``."""
    me = state.me.pose
    face = _facing(me.x, me.y, *aim)
    if abs(wrap_angle(face.theta - me.theta)) < params.play.shot_aim_tolerance:
        return Intent(face, Action.SHOOT, dribble=True, kick=kick)
    return Intent(face, Action.SHOOT, speed_limit=0.3, dribble=True)


def clearance_target(state: TeamState, cp: ChanceParams) -> tuple[float, float]:
    """Where to clear the ball to: of a few points up the field on both wings and in the middle, the one the ball
    reaches furthest ahead of every opponent (``chances.pass_margin``)."""
    me, f = state.me.pose, state.field
    ball = (state.ball.x, state.ball.y)
    x = min(ball[0] + 7.0, f.half_length - 2.0)
    targets = [(x, y) for y in (-f.half_width + 1.5, -f.half_width / 3, f.half_width / 3, f.half_width - 1.5)]
    return max(targets, key=lambda p: (pass_margin(ball, p, _CLEAR_SPEED, state.opponents, cp),
                                       -abs(wrap_angle(math.atan2(p[1] - me.y, p[0] - me.x) - me.theta))))


def clear(state: TeamState, params: ControlParams, cp: ChanceParams, action: Action) -> Intent:
    """Turn to the best clearance target and kick the ball there along the ground."""
    me = state.me.pose
    face = _facing(me.x, me.y, *clearance_target(state, cp))
    if abs(wrap_angle(face.theta - me.theta)) < 0.15:
        return Intent(face, action, dribble=True, kick=KickCommand(KickKind.GROUND, _CLEAR_SPEED))
    return Intent(face, action, speed_limit=0.3, dribble=True)


def _push_ahead(state: TeamState, params: ControlParams) -> Intent:
    """Let the ball go with a short kick towards the goal, to take it again beyond (a release the rules allow)."""
    me, f = state.me.pose, state.field
    face = _facing(me.x, me.y, f.half_length, me.y * 0.5)
    if abs(wrap_angle(face.theta - me.theta)) < params.play.aim_tolerance * 2.0:
        return Intent(face, Action.DRIBBLE, dribble=False, kick=KickCommand(KickKind.GROUND, 3))
    return Intent(face, Action.DRIBBLE, speed_limit=0.3, dribble=True)


_DRIBBLE_STEP = 1.2  # how far ahead the dribble's candidate spots lie [m]
_DRIBBLE_TURNS = (0.0, -0.5, 0.5, -1.0, 1.0, -1.6, 1.6, math.pi)  # their directions, off the line to the goal [rad]


def _dribble(state: TeamState, params: ControlParams, cp: ChanceParams,
             caught_at: tuple[float, float] | None = None) -> Intent:
    """Carry the ball to the nearby spot with the best shot, away from opponents (candidates all round, towards the
    goal preferred, inside the field and within ``carry_limit`` of where the ball was caught), facing where it goes:
    forwards the ball handler is fastest."""
    me, f, play = state.me.pose, state.field, params.play
    heading = math.atan2(-me.y * 0.3, f.half_length - me.x)
    spots = [(turn, me.x + _DRIBBLE_STEP * math.cos(heading + turn), me.y + _DRIBBLE_STEP * math.sin(heading + turn))
             for turn in _DRIBBLE_TURNS]
    spots = [s for s in spots if f.is_inside(s[1], s[2], -0.8) and
             (caught_at is None or math.hypot(s[1] - caught_at[0], s[2] - caught_at[1]) < play.carry_limit)]
    best, best_value = None, -math.inf
    shots = shot_chances([(x, y) for _, x, y in spots], state.opponents, f, play.shot_speed, cp) if spots else []
    for (turn, x, y), shot in zip(spots, shots):
        crowd = sum(max(0.0, 1.5 - math.hypot(ox - x, oy - y)) for ox, oy in state.opponents)
        value = shot.chance - 0.2 * crowd - 0.05 * abs(turn) + 0.02 * (x - me.x)
        if value > best_value:
            best, best_value = (x, y), value
    if best is None:
        return Intent(me, Action.DRIBBLE, speed_limit=params.motion.dribble_speed, dribble=True)
    heading = math.atan2(best[1] - me.y, best[0] - me.x)
    return Intent(Pose2D(best[0], best[1], heading), Action.DRIBBLE, speed_limit=params.motion.dribble_speed,
                  dribble=True)


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
    """Wait at the catch point facing the ball, dribbler on; once the ball rolls free (kicked: no teammate holds it)
    towards the receiver, go to meet it on its line (``_MEET_STEP`` ahead of the receiver's nearest point of it): the
    ball then has less way to go for an opponent to cut it off."""
    ball, me = state.ball, state.me.pose
    cx, cy = plan.catch_pt
    speed = math.hypot(ball.vx, ball.vy)
    if ball.known and speed > 0.5 and not any(m.holding for m in state.team):
        ux, uy = ball.vx / speed, ball.vy / speed
        ahead = (me.x - ball.x) * ux + (me.y - ball.y) * uy  # how far down the ball's line the receiver stands
        if ahead > 0.0 or plan.is_passout:
            t = max(0.0, ahead - _MEET_STEP)
            x, y = ball.x + ux * t, ball.y + uy * t
            return Intent(_facing(x, y, ball.x, ball.y), Action.CATCH, dribble=True)
    return Intent(_facing(cx, cy, ball.x, ball.y), Action.CATCH, dribble=True)


def opponent_has_ball(state: TeamState, radius: float = 0.6) -> tuple[float, float] | None:
    """The opponent at the ball (within ``radius`` of it, and nearer than any of us), if one: it plays the ball."""
    ball = state.ball
    if not ball.known or not state.opponents:
        return None
    ox, oy = min(state.opponents, key=lambda o: math.hypot(o[0] - ball.x, o[1] - ball.y))
    theirs = math.hypot(ox - ball.x, oy - ball.y)
    ours = min(math.hypot(m.pose.x - ball.x, m.pose.y - ball.y) for m in state.team)
    return (ox, oy) if theirs < radius and theirs < ours else None


def press(state: TeamState, params: ControlParams) -> Intent:
    """An opponent plays the ball: stand between the ball and our goal, close to it (the contact guard keeps the
    robot from charging), facing the ball: the shot's lane is shut and the carrier must pass or turn."""
    ball, f = state.ball, state.field
    dx, dy = -f.half_length - ball.x, -ball.y
    d = max(math.hypot(dx, dy), 1e-6)
    gap = params.play.press_distance
    return Intent(_facing(ball.x + dx / d * gap, ball.y + dy / d * gap, ball.x, ball.y), Action.DEFEND)


def block_lane(state: TeamState, params: ControlParams) -> Intent | None:
    """With the ball in our half within ``block_range`` of our goal: stand in the lane from the ball to the part of the
    goal our goalie leaves open (the far side from the ball, or from the goalie), ``block_distance`` from the ball;
    None farther away."""
    ball, f, play = state.ball, state.field, params.play
    gx = -f.half_length
    if not ball.known or math.hypot(ball.x - gx, ball.y) > play.block_range:
        return None
    keeper = next((m for m in state.team if m.agent_id == state.goalie_id), None)
    side = -1.0 if ball.y > 0.3 else 1.0 if ball.y < -0.3 else (-1.0 if keeper and keeper.pose.y > 0.0 else 1.0)
    aim = (gx, side * 0.35 * f.goal_width)
    dx, dy = aim[0] - ball.x, aim[1] - ball.y
    d = max(math.hypot(dx, dy), 1e-6)
    gap = min(play.block_distance, d - 0.5)
    return Intent(_facing(ball.x + dx / d * gap, ball.y + dy / d * gap, ball.x, ball.y), Action.DEFEND)


def support(state: TeamState, role: Role, params: ControlParams) -> Intent:
    """Hold the role's spot; with the ball lost, the spots stay where they were for its last position. The PASSIVE
    robot blocks a shot's lane when the ball is near our goal (``block_lane``)."""
    if role == Role.PASSIVE:
        blocking = block_lane(state, params)
        if blocking is not None:
            return blocking
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


def goalie_spot(ball: tuple[float, float], field: FieldGeometry, goalie_line: float) -> tuple[float, float]:
    """Where the goalie stands against a ball at ``ball`` (team frame, own goal at -x [m]): ``goalie_line`` [m] off
    the goal line, on the bisector of the angle the goal mouth makes at the ball (the two sides of the goal it leaves
    open look equally wide from the ball), at most 0.2 m inside a post."""
    bx, by = ball
    gx, half = -field.half_length, field.goal_width / 2.0
    inside = half - 0.2
    x = gx + goalie_line
    dx = dy = 0.0
    for post in (half, -half):  # the bisector's direction: the sum of the unit vectors to the posts
        d = max(math.hypot(gx - bx, post - by), 1e-6)
        dx, dy = dx + (gx - bx) / d, dy + (post - by) / d
    if bx - x < 0.1 or dx > -1e-6:  # the ball level with the guarded line: guard it on the ball's side
        return x, max(-inside, min(inside, by))
    return x, max(-inside, min(inside, by + (x - bx) / dx * dy))


def keep_goal(state: TeamState, params: ControlParams, cp: ChanceParams | None = None) -> Intent:
    """Guard the goal: meet a lob where it comes down into the goal (the RGB-D cameras' flight); against a shot (a
    ball at least ``goalie_shot_speed`` fast whose line crosses the goal mouth, half a metre either side) step to
    the nearest point of its line at once (``urgent``: no plan, the quickest way); else stand at ``goalie_spot`` (on
    the bisector of the angle the goal makes at the ball);
    take a slow ball in the goal area and clear it up the field, away from the opponents (``clear``); the goal's
    centre when the ball is lost."""
    f, ball, play, me = state.field, state.ball, params.play, state.me.pose
    cp = cp or ChanceParams()
    line_x = -f.half_length + play.goalie_line
    if state.me.holding:
        return clear(state, params, cp, Action.KEEP_GOAL)
    lob = _meet_lob(state, params)
    if lob is not None:
        return lob
    if not ball.known:
        return Intent(Pose2D(line_x, 0.0, 0.0), Action.KEEP_GOAL)
    in_area = ball.x < -f.half_length + f.penalty_area_length and abs(ball.y) < f.penalty_area_width / 2
    speed = math.hypot(ball.vx, ball.vy)
    if in_area and speed < 1.0:
        intent = chase_ball(state, params)
        return Intent(intent.target, Action.KEEP_GOAL, dribble=intent.dribble)
    if ball.vx < -0.5 and speed >= play.goalie_shot_speed:
        crossing = ball.y + ball.vy * (-f.half_length - ball.x) / ball.vx
        if abs(crossing) < f.goal_width / 2 + 0.5:  # a shot at the goal: across its line, the shortest way
            ux, uy = ball.vx / speed, ball.vy / speed
            ahead = max((me.x - ball.x) * ux + (me.y - ball.y) * uy, 0.0)
            x, y = ball.x + ux * ahead, ball.y + uy * ahead
            if x < -f.half_length:  # not behind the goal line: where the line crosses it
                x, y = -f.half_length, crossing
            return Intent(_facing(x, y, ball.x, ball.y), Action.KEEP_GOAL, urgent=True)
    x, y = goalie_spot((ball.x, ball.y), f, play.goalie_line)
    return Intent(_facing(x, y, ball.x, ball.y), Action.KEEP_GOAL)


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
