"""One robot's whole decision pipeline, pure: percepts, teammates' packets and coach commands in, commands out.

Requires: the robot's name (``RobotName``), the match's ``WorldDescription``, ``WorldModelParams`` and
``ControlParams``; then, at their times [s] (sim time), its own percepts (``RobotView``; a front camera's
ball, a goalie's 3-D ball), teammates' packets (``RobotView``) and strategies (``StrategyReport``), coach
commands (MatchMode, MatchType, extras). Provides: ``RobotAgent.step(t)`` -> ``AgentStep`` (the
``RobotCommand`` for the base, the ball handler and the kicker; the ``StrategyReport`` for the teammates;
the ``WorldState`` the world model decided; the packet this robot shares) and its two stages:

- ``WorldModel`` (``world_model`` package): fuses what the robot knows into a ``WorldState``;
- ``Controller``: acts on that decision with the ``Strategy`` (roles, set plays, behaviours,
  motion) and turns its wishes into the calls the robot interface takes: a ``BallHandle`` request
  when the wish changes, and again every ``dribble_retry`` while the ball is wanted and not yet held;
  a ``Shoot`` request only while the ball is held.

The ROS nodes run the stages apart (``world_model`` node, ``nubot_control`` node: the same objects,
with ``WorldModelInfo`` between them, which carries the whole decision); the in-process match and
the lockstep engine run the agent in one piece.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from nubot_common.commands import RobotCommand
from nubot_common.naming import RobotName
from nubot_common.percepts import Ball3dPercept, RobotView
from nubot_common.records import fast_init
from nubot_common.team_play import Point, Role, StrategyReport
from nubot_common.world_description import WorldDescription
from nubot_common.world_state import CoachExtras, GameState, WorldState
from nubot_control.params import ControlParams
from nubot_control.plugins import StrategyFactory, StrategyPlugin, strategy_class
from nubot_control.policy_player import player_or_strategy
from nubot_control.strategy import ControlOutput, Strategy
from nubot_control.team_state import team_state
from world_model.params import WorldModelParams
from world_model.world_model import WorldModel

DRIBBLE_RETRY = 0.2  # ask again for the ball this often while wanting it and not holding it [s]


@fast_init
@dataclass(frozen=True)
class ControlStep:
    command: RobotCommand
    report: StrategyReport
    output: ControlOutput | None  # the strategy's full output; None while the robot is not valid
    stale: bool = False  # the world model is older than ``world_model_timeout``: standing still, out of play


class Controller:
    """The control stage: a ``WorldState`` and the control time in, the robot's commands and report out."""

    def __init__(self, params: ControlParams, world: WorldDescription, agent_id: int):
        self.params = params
        self.world = world
        self.agent_id = agent_id
        cls: StrategyFactory = strategy_class(params.strategy) if params.strategy else Strategy
        self.strategy: StrategyPlugin = player_or_strategy(cls(params, world, agent_id), params)
        self._dribble_on = False
        self._last_request = -math.inf

    def step(self, t: float, world: WorldState) -> ControlStep:
        """One control cycle at ``t`` [s] on the world model's decision ``world``.

        A decision older than ``world_model_timeout`` (the world model stopped) is not acted on: the robot
        stands still, and the caller should stop announcing it to the team until a fresh one arrives.
        """
        if not t - world.stamp <= self.params.world_model_timeout:
            self._dribble_on = False
            return ControlStep(RobotCommand(), StrategyReport(t, self.agent_id, self.strategy.role), None, stale=True)
        state = team_state(world, t, self.params.play.goalie_id, self.world.field)
        if state is None:  # the robot does not know where it is (or is off the field): stand still
            self._dribble_on = False
            return ControlStep(RobotCommand(), StrategyReport(t, self.agent_id, self.strategy.role), None)
        out = self.strategy.step(state)
        holding = state.me.holding
        request = None
        if out.dribble and not holding and (not self._dribble_on or t - self._last_request > DRIBBLE_RETRY):
            request, self._dribble_on, self._last_request = 1, True, t
        elif not out.dribble and self._dribble_on:
            request, self._dribble_on = 0, False
        if out.kick is not None:
            self._dribble_on = False  # a kick releases the ball
        command = RobotCommand(out.velocity, out.dribble, request, out.kick)
        return ControlStep(command, self._report(t, out, holding), out)

    def _report(self, t: float, out: ControlOutput, holding: bool) -> StrategyReport:
        by_role = {role: aid for aid, role in (out.role_of or {}).items()}
        nums = (by_role.get(Role.ACTIVE, 0), by_role.get(Role.PASSIVE, 0), by_role.get(Role.ASSISTANT, 0),
                by_role.get(Role.MIDFIELD, 0))
        taker, receiver = out.static_pass
        return StrategyReport(t, self.agent_id, out.role, int(out.action), t - self.strategy.role_since, nums,
                              taker, receiver, holding, taker == self.agent_id, out.pass_cmd, out.target)


@fast_init
@dataclass(frozen=True)
class AgentStep:
    command: RobotCommand
    report: StrategyReport
    world: WorldState
    packet: RobotView | None  # what this robot shares with its teammates now (None before its first percepts)
    output: ControlOutput | None = None  # the strategy's full output; None while the robot is not valid
    stale: bool = False  # the world model was too old to play on (``ControlStep.stale``)


class RobotAgent:
    """One robot: feed it with the ``on_*`` methods as things arrive, call ``step`` once per control cycle."""

    def __init__(self, name: RobotName, world: WorldDescription, model: WorldModelParams | None = None,
                 control: ControlParams | None = None):
        self.name = name
        self.world_model = WorldModel(model or WorldModelParams(), name.agent_id, world)
        self.controller = Controller(control or ControlParams(), world, name.agent_id)

    @classmethod
    def around(cls, name: RobotName, world_model: WorldModel, controller: Controller) -> RobotAgent:
        """The agent of a world model and a controller made elsewhere (the robot node's two halves)."""
        agent = cls.__new__(cls)
        agent.name, agent.world_model, agent.controller = name, world_model, controller
        return agent

    @property
    def agent_id(self) -> int:
        return self.name.agent_id

    def on_vision(self, frame: RobotView) -> None:
        self.world_model.on_vision(frame)

    def on_front_ball(self, stamp: float, relative: Point | None) -> None:
        self.world_model.on_front_ball(stamp, relative)

    def on_ball3d(self, ball: Ball3dPercept | None) -> None:
        self.world_model.on_ball3d(ball)

    def on_teammate(self, t: float, packet: RobotView) -> bool:
        return self.world_model.on_teammate(t, packet)

    def on_teammate_strategy(self, t: float, report: StrategyReport) -> bool:
        return self.world_model.on_teammate_strategy(t, report)

    def on_coach(self, t: float, mode: int | str | bytes, match_type: int | str | bytes = 0,
                 extras: CoachExtras | None = None) -> GameState:
        """Apply a game command; an unknown MatchMode raises (``WorldModelError``) and changes nothing."""
        return self.world_model.on_coach(t, mode, match_type, extras)

    def step(self, t: float) -> AgentStep:
        world = self.world_model.snapshot(t)
        control = self.controller.step(t, world)
        if not control.stale:  # a robot on a stale world model stands out of play: no decision to take back
            self.world_model.on_strategy(t, control.report)
        return AgentStep(control.command, control.report, world, self.world_model.own_view(t), control.output,
                         control.stale)
