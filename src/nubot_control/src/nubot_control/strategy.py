"""One control cycle of one robot: the team state in, velocity and ball commands out.

Requires: ``TeamState`` each cycle (33 Hz), ``ControlParams`` and the match's
``WorldDescription``. Provides: ``Strategy.step`` -> ``ControlOutput`` (body-frame velocity for
VelCmd, the dribbler wish for BallHandle, an optional Shoot request, and what goes into
StrategyInfo: role, action, target, static pass numbers, pass command). Game flow: STOPROBOT
stops; set pieces, drop ball and park move to their formation; STARTROBOT after our set piece
lets the taker pass to the receiver (the static pass), after theirs waits until the ball is in
play; then open play with roles from the ``RoleAllocator``. Every target keeps to the areas the rules
allow (``areas``): the goal areas are the goalie's, the penalty areas the goalie's and the robot's
playing the ball. A ball the world model does not
know is searched for where it was last seen (``behaviours.search_ball``), never chased.
"""

from __future__ import annotations

import math
from dataclasses import dataclass, replace

from nubot_common.commands import BodyVelocity, KickCommand
from nubot_common.field import FieldGeometry
from nubot_common.geometry import Pose2D
from nubot_common.match_mode import OUR_SET_PLAYS, THEIR_SET_PLAYS, MatchMode
from nubot_common.records import fast_init
from nubot_common.team_play import PassCommand, Role
from nubot_common.world_description import WorldDescription
from nubot_control import behaviours as bh
from nubot_control.areas import Rect, in_area, keep_out, no_go
from nubot_control.chances import ChanceParams
from nubot_control.motion import MotionController
from nubot_control.params import ControlParams
from nubot_control.role_allocation import RoleAllocator
from nubot_control.set_plays import Formation, KeptFormation
from nubot_control.team_state import TeamState

_BALL_IN_PLAY_DISTANCE = 0.5  # a restart is over once the ball moved this far [m]
_PASS_MEMORY = 3.0  # a pass command is kept this long after the kick [s]
_KICKED_BALL_SPEED = 1.0  # a ball this fast has been kicked [m/s]
_RELEASED = 0.7  # a ball this far from the robot's centre has been let go for all to see (the referee's) [m]
_RESTARTS = OUR_SET_PLAYS | THEIR_SET_PLAYS


@fast_init
@dataclass(frozen=True)
class ControlOutput:
    velocity: BodyVelocity  # body frame
    dribble: bool
    kick: KickCommand | None  # only while holding the ball
    role: Role
    action: bh.Action
    target: tuple[float, float]  # team frame [m]
    static_pass: tuple[int, int] = (0, 0)  # (staticpassNum, staticcatchNum)
    pass_cmd: PassCommand | None = None
    role_of: dict[int, Role] | None = None  # the team assignment this robot computed


class Strategy:
    def __init__(self, params: ControlParams, world: WorldDescription, agent_id: int):
        self.params = params
        self.world = world
        self.agent_id = agent_id
        self.motion = MotionController(params.motion, world, 1.0 / params.rate)
        self.allocator = RoleAllocator(params.play, params.motion, world.field)
        self.role = Role.NOROLE
        self.role_since = 0.0
        self._last_time: float | None = None
        self._restart: Formation | None = None  # the formation of the set piece being restarted
        self._formation = KeptFormation()  # the formation of the command in force
        self._restart_ball: tuple[float, float] | None = None
        self._restart_over = False
        self._mode_seen: tuple[MatchMode, float] | None = None
        self._my_pass: PassCommand | None = None
        self._pass_time = -math.inf
        self._frozen_roles: dict[int, Role] | None = None  # roles a formation was built with, per command
        self._kicked_since_start = False
        self._caught_at: tuple[float, float] | None = None  # where this robot last caught the ball (team frame)
        self._caught_time = 0.0  # ... and when [s]
        self._in_area_since: dict[bool, float] = {}  # own (True) / the opponents' (False) penalty area: inside since
        self._no_go_areas: tuple[FieldGeometry, list[Rect], list[Rect]] | None = None  # (field, penalty, goal areas)
        body = world.robot
        m = params.motion
        self.chances = ChanceParams(kick_direction_std=math.radians(params.play.kick_spread),
                                    opponent_speed=m.max_speed, opponent_accel=m.max_accel, robot_radius=body.radius,
                                    ball_radius=world.ball.radius, rolling_decel=world.ball.rolling_friction * 9.8,
                                    goal_height=world.field.goal_height, robot_height=body.height)

    def step(self, state: TeamState) -> ControlOutput:
        dt = 1.0 / self.params.rate if self._last_time is None else min(max(state.time - self._last_time, 1e-3), 0.2)
        self._last_time = state.time
        if self._mode_seen != (state.mode, state.mode_since):
            self._mode_seen = (state.mode, state.mode_since)
            self._on_new_mode(state)
        self._track_carry(state)
        self._track_areas(state)
        intent, roles, static_pass = self._decide(state)
        role = roles.get(self.agent_id, Role.NOROLE)
        intent = self._within_the_rules(intent, role, state)
        if role != self.role:
            self.role, self.role_since = role, state.time
        if intent.action == bh.Action.STOP:
            self.motion.reset()
            velocity = BodyVelocity()
        else:
            velocity = BodyVelocity(*self.motion.command(state.me.pose, intent.target, self._obstacles(state, intent),
                                                         dt, intent.speed_limit, holding=state.me.holding,
                                                         no_go=self._no_go(role, state), urgent=intent.urgent))
        kick = intent.kick if state.me.holding else None
        if kick is not None:
            self._my_pass, self._pass_time = intent.pass_cmd, state.time
            self._kicked_since_start = True
        plan = intent.pass_cmd or (self._my_pass if state.time - self._pass_time < _PASS_MEMORY else None)
        if plan is not None and kick is not None:
            plan = plan.kicked()
        return ControlOutput(velocity, intent.dribble, kick, role, intent.action, (intent.target.x, intent.target.y),
                             static_pass, plan, roles)

    def in_open_play(self, state: TeamState) -> bool:
        """Whether the ball is in open play at ``state`` (START given and any restart taken), as of the last step."""
        return state.mode == MatchMode.STARTROBOT and self._restart_over

    def _track_carry(self, state: TeamState) -> None:
        """Where this robot caught the ball it holds; forgotten once the ball is away from it (released for all to
        see), as the referee does (RC-12.0.1)."""
        me, ball = state.me, state.ball
        if me.holding:
            if self._caught_at is None:
                self._caught_at, self._caught_time = (ball.x, ball.y), state.time
        elif self._caught_at is not None and math.hypot(ball.x - me.pose.x, ball.y - me.pose.y) > _RELEASED:
            self._caught_at = None

    def held(self, state: TeamState) -> float:
        """How long [s] this robot has held the ball since it caught it (0 when it does not hold it)."""
        return state.time - self._caught_time if self._caught_at is not None and state.me.holding else 0.0

    def carried(self, state: TeamState) -> float:
        """How far [m] the ball is from where this robot caught it (0 when it does not hold it)."""
        if self._caught_at is None or not state.me.holding:
            return 0.0
        return math.hypot(state.ball.x - self._caught_at[0], state.ball.y - self._caught_at[1])

    def _track_areas(self, state: TeamState) -> None:
        me, field = state.me.pose, state.field
        if abs(me.x) < field.half_length - field.penalty_area_length:  # short of both penalty areas
            self._in_area_since.clear()
            return
        for own in (True, False):
            if in_area(me.x, me.y, state.field, own):
                self._in_area_since.setdefault(own, state.time)
            else:
                self._in_area_since.pop(own, None)

    def _no_go(self, role: Role, state: TeamState) -> list[Rect]:
        """The areas this robot must not enter now: none for the goalie, the goal areas for the robot playing the
        ball (and a penalty area it has been in for ``area_time``), the penalty areas for the others (``areas``)."""
        if self.agent_id == state.goalie_id:
            return []
        penalty, goal = self._areas(state.field)
        if role not in (Role.ACTIVE, Role.PASSOFPASS):
            return list(penalty)
        overstayed = [own for own, since in self._in_area_since.items()
                      if state.time - since > self.params.play.area_time]
        return goal + [penalty[0 if own else 1] for own in overstayed]  # a new list; the penalty areas: own first

    def _areas(self, field: FieldGeometry) -> tuple[list[Rect], list[Rect]]:
        """``no_go``'s penalty areas and goal areas of ``field``, made once (read-only: copied before they go out)."""
        if self._no_go_areas is None or self._no_go_areas[0] is not field:
            self._no_go_areas = (field, no_go(field, penalty_areas=True), no_go(field, penalty_areas=False))
        return self._no_go_areas[1], self._no_go_areas[2]

    def _within_the_rules(self, intent: bh.Intent, role: Role, state: TeamState) -> bh.Intent:
        """The intent with its target out of the areas the rules keep this robot out of (``areas``): the goalie
        anywhere, the robot playing the ball (ACTIVE, or the taker of a set piece) out of the goal areas, the others
        out of the penalty areas too."""
        if self.agent_id == state.goalie_id or intent.action == bh.Action.STOP:
            return intent
        playing = role in (Role.ACTIVE, Role.PASSOFPASS)
        x, y = keep_out(intent.target.x, intent.target.y, state.field, penalty_areas=not playing)
        if (x, y) == (intent.target.x, intent.target.y):
            return intent
        return replace(intent, target=Pose2D(x, y, intent.target.theta))

    # --- game flow ------------------------------------------------------------------------
    def _on_new_mode(self, state: TeamState) -> None:
        self._frozen_roles = None  # who stands where is decided once per command, so robots do not swap
        self._formation.clear()
        if state.mode == MatchMode.STARTROBOT:
            self._restart_ball = (state.ball.x, state.ball.y)
            self._restart_over = state.previous_mode not in _RESTARTS
            self._kicked_since_start = False
        elif state.mode != MatchMode.STOPROBOT:
            self._restart = None

    def _decide(self, state: TeamState) -> tuple[bh.Intent, dict[int, Role], tuple[int, int]]:
        mode = state.mode
        team = list(state.team)
        if mode in (MatchMode.STOPROBOT, MatchMode.TEST):
            return bh.Intent(state.me.pose, bh.Action.STOP), {m.agent_id: self.role for m in team}, (0, 0)
        if mode != MatchMode.STARTROBOT:
            if self._frozen_roles is None or not set(self._frozen_roles) >= {m.agent_id for m in team}:
                self._frozen_roles = self.allocator.assign(state)
            roles = dict(self._frozen_roles)
            plan = self._formation.formation(mode, state.ball, team, roles, state.field, self.params.play)
            self._restart = plan if mode in _RESTARTS else None
            if plan.taker:
                roles = {**roles, plan.taker: Role.PASSOFPASS}
            if plan.receiver:
                roles = {**roles, plan.receiver: Role.CATCHOFPASS}
            target = plan.targets.get(self.agent_id, state.me.pose)
            return bh.Intent(target, bh.Action.POSITION), roles, (plan.taker, plan.receiver)
        if not self._restart_over and self._restart_in_play(state):
            self._restart_over = True
        if not self._restart_over and self._restart is not None:
            return self._restart_play(state)
        return self._open_play(state)

    def _restart_in_play(self, state: TeamState) -> bool:
        """Ours: once the ball was kicked; theirs: once the ball moved; either: after the timeout."""
        late = state.time - state.mode_since > self.params.play.set_play_timeout
        moved = self._restart_ball is not None and math.hypot(state.ball.x - self._restart_ball[0],
                                                               state.ball.y - self._restart_ball[1])
        if state.previous_mode in OUR_SET_PLAYS:
            held = any(m.holding for m in state.team)  # a held ball moves with its robot: not kicked yet
            rolling = not held and math.hypot(state.ball.vx, state.ball.vy) > _KICKED_BALL_SPEED
            kicked = self._kicked_since_start or (state.pass_cmd is not None and state.pass_cmd.is_passout)
            return late or kicked or bool(rolling and moved and moved > _BALL_IN_PLAY_DISTANCE)
        return late or bool(moved and moved > _BALL_IN_PLAY_DISTANCE)

    def _restart_play(self, state: TeamState) -> tuple[bh.Intent, dict[int, Role], tuple[int, int]]:
        plan = self._restart
        assert plan is not None
        roles = {m.agent_id: Role.NOROLE for m in state.team}
        static = (plan.taker, plan.receiver)
        if state.previous_mode in OUR_SET_PLAYS and self.agent_id == plan.taker:
            roles[plan.taker] = Role.PASSOFPASS
            if state.me.holding:
                receiver = next((m for m in state.mates if m.agent_id == plan.receiver), None)
                if receiver is not None:
                    return bh.pass_to(state, receiver, self.params, static=True), roles, static
                return bh.attack(state, self.params, self.chances, self.carried(state),
                                 caught_at=self._caught_at, held=self.held(state)), roles, static
            return bh.chase_ball(state, self.params), roles, static
        if state.previous_mode in OUR_SET_PLAYS and self.agent_id == plan.receiver:
            roles[plan.receiver] = Role.CATCHOFPASS
            target = plan.targets.get(self.agent_id, state.me.pose)
            catch = PassCommand(plan.taker, plan.receiver, catch_pt=(target.x, target.y), is_passout=True,
                                is_static_pass=True)
            return bh.catch_pass(state, catch, self.params), roles, static
        target = plan.targets.get(self.agent_id, state.me.pose)
        return bh.Intent(target, bh.Action.POSITION), roles, static

    def _open_play(self, state: TeamState) -> tuple[bh.Intent, dict[int, Role], tuple[int, int]]:
        roles = self.allocator.assign(state)
        role = roles.get(self.agent_id, Role.NOROLE)
        plan = state.pass_cmd
        if plan is not None and plan.catch_id == self.agent_id and not state.me.holding:
            roles[self.agent_id] = Role.CATCHOFPASS
            return bh.catch_pass(state, plan, self.params), roles, (0, 0)
        if role == Role.GOALIE:
            return bh.keep_goal(state, self.params, self.chances), roles, (0, 0)
        carrier = bh.opponent_has_ball(state)
        if role == Role.ACTIVE:
            if state.me.holding:
                return bh.attack(state, self.params, self.chances, self.carried(state),
                                 caught_at=self._caught_at, held=self.held(state)), roles, (0, 0)
            if carrier is not None:
                return bh.press(state, self.params), roles, (0, 0)
            return bh.chase_ball(state, self.params), roles, (0, 0)
        if role == Role.MIDFIELD or (role == Role.ASSISTANT and carrier is not None):
            threats = _dangerous_opponents(state, carrier)
            pick = 0 if role == Role.MIDFIELD else 1
            if len(threats) > pick:
                return bh.mark(state, threats[pick], self.params), roles, (0, 0)
        return bh.support(state, role, self.params), roles, (0, 0)

    def _obstacles(self, state: TeamState, intent: bh.Intent) -> list[tuple[float, ...]]:
        obstacles: list[tuple[float, ...]] = list(state.obstacles())
        if intent.action == bh.Action.POSITION and state.mode != MatchMode.STARTROBOT:
            # Walk around the placed ball, never push it; the taker may come to 0.55 m of it.
            keep = self.world.robot.radius + self.world.ball.radius + 0.1
            obstacles.append((state.ball.x, state.ball.y, keep))
        return obstacles


def _dangerous_opponents(state: TeamState, carrier: tuple[float, float] | None) -> list[tuple[float, float]]:
    """The opponents who could receive a pass and shoot, most dangerous first: those away from the ball (not the
    carrier) in our half, nearest our goal first."""
    gx = -state.field.half_length
    candidates = [o for o in state.opponents if o != carrier and o[0] < 1.0
                  and math.hypot(o[0] - state.ball.x, o[1] - state.ball.y) > 2.0]
    return sorted(candidates, key=lambda o: math.hypot(o[0] - gx, o[1]))
