"""One control cycle of one robot: the team state in, velocity and ball commands out.

Requires: ``TeamState`` each cycle (33 Hz), ``ControlParams`` and the match's
``WorldDescription``. Provides: ``Strategy.step`` -> ``ControlOutput`` (body-frame velocity for
VelCmd, the dribbler wish for BallHandle, an optional Shoot request, and what goes into
StrategyInfo: role, action, target, static pass numbers, pass command). Game flow: STOPROBOT
stops; set pieces, drop ball and park move to their formation; STARTROBOT after our set piece
lets the taker pass to the receiver (the static pass), after theirs waits until the ball is in
play; then open play with roles from the ``RoleAllocator``. A ball the world model does not
know is searched for where it was last seen (``behaviours.search_ball``), never chased.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_common.commands import BodyVelocity, KickCommand
from nubot_common.match_mode import OUR_SET_PLAYS, THEIR_SET_PLAYS, MatchMode
from nubot_common.team_play import PassCommand, Role
from nubot_common.world_description import WorldDescription
from nubot_control import behaviours as bh
from nubot_control.motion import MotionController
from nubot_control.params import ControlParams
from nubot_control.role_allocation import RoleAllocator
from nubot_control.set_plays import Formation, formation
from nubot_control.team_state import TeamState

_BALL_IN_PLAY_DISTANCE = 0.5  # a restart is over once the ball moved this far [m]
_PASS_MEMORY = 3.0  # a pass command is kept this long after the kick [s]
_KICKED_BALL_SPEED = 1.0  # a ball this fast has been kicked [m/s]
_RESTARTS = OUR_SET_PLAYS | THEIR_SET_PLAYS


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
        self._restart_ball: tuple[float, float] | None = None
        self._restart_over = False
        self._mode_seen: tuple[MatchMode, float] | None = None
        self._my_pass: PassCommand | None = None
        self._pass_time = -math.inf
        self._frozen_roles: dict[int, Role] | None = None  # roles a formation was built with, per command
        self._kicked_since_start = False

    def step(self, state: TeamState) -> ControlOutput:
        dt = 1.0 / self.params.rate if self._last_time is None else min(max(state.time - self._last_time, 1e-3), 0.2)
        self._last_time = state.time
        if self._mode_seen != (state.mode, state.mode_since):
            self._mode_seen = (state.mode, state.mode_since)
            self._on_new_mode(state)
        intent, roles, static_pass = self._decide(state)
        role = roles.get(self.agent_id, Role.NOROLE)
        if role != self.role:
            self.role, self.role_since = role, state.time
        if intent.action == bh.Action.STOP:
            self.motion.reset()
            velocity = BodyVelocity()
        else:
            velocity = BodyVelocity(*self.motion.command(state.me.pose, intent.target, self._obstacles(state, intent),
                                                         dt, intent.speed_limit, holding=state.me.holding))
        kick = intent.kick if state.me.holding else None
        if kick is not None:
            self._my_pass, self._pass_time = intent.pass_cmd, state.time
            self._kicked_since_start = True
        plan = intent.pass_cmd or (self._my_pass if state.time - self._pass_time < _PASS_MEMORY else None)
        if plan is not None and kick is not None:
            plan = plan.kicked()
        return ControlOutput(velocity, intent.dribble, kick, role, intent.action, (intent.target.x, intent.target.y),
                             static_pass, plan, roles)

    # --- game flow ------------------------------------------------------------------------
    def _on_new_mode(self, state: TeamState) -> None:
        self._frozen_roles = None  # who stands where is decided once per command, so robots do not swap
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
            plan = formation(mode, state.ball, team, roles, state.field, self.params.play)
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
                return bh.attack(state, self.params), roles, static
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
            return bh.keep_goal(state, self.params), roles, (0, 0)
        if role == Role.ACTIVE:
            if state.me.holding:
                return bh.attack(state, self.params), roles, (0, 0)
            return bh.chase_ball(state, self.params), roles, (0, 0)
        if role == Role.MIDFIELD:
            threat = _most_dangerous_opponent(state)
            if threat is not None:
                return bh.mark(state, threat, self.params), roles, (0, 0)
        return bh.support(state, role, self.params), roles, (0, 0)

    def _obstacles(self, state: TeamState, intent: bh.Intent) -> list[tuple[float, ...]]:
        obstacles: list[tuple[float, ...]] = list(state.obstacles())
        if intent.action == bh.Action.POSITION and state.mode != MatchMode.STARTROBOT:
            # Walk around the placed ball, never push it; the taker may come to 0.55 m of it.
            keep = self.world.robot.radius + self.world.ball.radius + 0.1
            obstacles.append((state.ball.x, state.ball.y, keep))
        return obstacles


def _most_dangerous_opponent(state: TeamState) -> tuple[float, float] | None:
    """The opponent nearest the own goal inside the own half and away from the ball, if any."""
    candidates = [o for o in state.opponents
                  if o[0] < 0.0 and math.hypot(o[0] - state.ball.x, o[1] - state.ball.y) > 2.0]
    return min(candidates, key=lambda o: o[0]) if candidates else None
