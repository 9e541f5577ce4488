"""A robot that plays a trained policy file in open play and the team's strategy otherwise.

Requires: a strategy (the built-in ``Strategy`` or one of the user's own, ``plugins``) and a ``PolicyNet``
(``nubot_common.policy``) whose observation names are among ``OBSERVABLE``. Provides: ``PolicyPlayer``, a
strategy plug-in wrapping the two, ``player_or_strategy(inner, params)`` (the player when ``params.policy``
names a file), ``playable(net)`` and ``observation(names, state, time_left)``.

Each cycle the strategy decides first (its roles, formations and set plays go on as they would). While the
ball is in open play (START given and any restart taken: ``Strategy.in_open_play``; a strategy without that
method: START alone), the policy's action replaces the strategy's velocity, dribbler wish and kick; the
role and target reported to the teammates stay the strategy's. The policy sees what this robot's world
model believes, in the team frame, with the names of the training environment (``nubot_match.envs``):
x, y, cos_theta, sin_theta, vx, vy, w, ball_dx, ball_dy, ball_vx, ball_vy (0 until the world model knows the
ball's velocity), holding; goalie_x, goalie_y (the opponent nearest the centre of the attacked goal; the
goal line's centre when no opponent is seen); time_left (an episode's clock: 1 when open play begins,
falling to 0 over ``episode_steps`` cycles of the policy's file, then starting again); and what the robot sees
in its own frame, derived from those (``nubot_common.policy.DERIVED``).
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray

from nubot_common.match_mode import MatchMode
from nubot_common.policy import DERIVED, PolicyError, PolicyNet, command_from_action, policy_input
from nubot_common.team_play import Role
from nubot_control.params import ControlParams
from nubot_control.plugins import StrategyPlugin
from nubot_control.strategy import ControlOutput
from nubot_control.team_state import TeamState

OBSERVABLE = ("x", "y", "cos_theta", "sin_theta", "vx", "vy", "w", "ball_dx", "ball_dy", "ball_vx", "ball_vy",
              "holding", "goalie_x", "goalie_y", "time_left", *DERIVED)
DEFAULT_EPISODE_STEPS = 300


def playable(net: PolicyNet) -> PolicyNet:
    """``net``, checked to read only what a robot in a match knows; ``PolicyError`` naming the rest."""
    unknown = [n for n in net.observations if n not in OBSERVABLE]
    if unknown:
        raise PolicyError(f"the policy reads {', '.join(unknown)}, which a robot in a match does not know "
                          f"(it knows {', '.join(OBSERVABLE)})")
    return net


def observation(names: Sequence[str], state: TeamState, time_left: float) -> NDArray[np.float64]:
    """The observation ``names`` of the robot of ``state`` (team frame, SI units)."""
    me, ball, field = state.me, state.ball, state.field
    x, y, theta = me.pose.x, me.pose.y, me.pose.theta
    goal = (field.half_length, 0.0)
    goalie = min(state.opponents, key=lambda o: math.dist(o, goal), default=goal)
    moving = ball.velocity_known and ball.known
    values = {"x": x, "y": y, "cos_theta": math.cos(theta), "sin_theta": math.sin(theta), "vx": me.vx, "vy": me.vy,
              "w": me.w, "ball_dx": ball.x - x, "ball_dy": ball.y - y, "ball_vx": ball.vx if moving else 0.0,
              "ball_vy": ball.vy if moving else 0.0, "holding": float(me.holding), "goalie_x": goalie[0],
              "goalie_y": goalie[1], "time_left": time_left}
    return policy_input(values, names, field.half_length)


class PolicyPlayer:
    """``inner``'s decisions, with ``net``'s action in open play."""

    def __init__(self, inner: StrategyPlugin, net: PolicyNet):
        self.inner, self.net = inner, playable(net)
        self.episode_steps = int(net.meta.get("episode_steps", DEFAULT_EPISODE_STEPS))
        self.kick_max_speed = float(net.meta.get("kick_max_speed", 12.0))
        self.cycles = 0  # of open play since it began
        self.playing = False  # whether the last cycle was the policy's

    @classmethod
    def wrapping(cls, inner: StrategyPlugin, path: str) -> PolicyPlayer:
        return cls(inner, PolicyNet.load(path))

    @property
    def role(self) -> Role:
        return self.inner.role

    @role.setter
    def role(self, role: Role) -> None:
        self.inner.role = role

    @property
    def role_since(self) -> float:
        return self.inner.role_since

    @role_since.setter
    def role_since(self, since: float) -> None:
        self.inner.role_since = since

    @property
    def motion(self) -> object:
        """The inner strategy's motion layer while it drives the robot (its path is then the one followed)."""
        return None if self.playing else getattr(self.inner, "motion", None)

    def step(self, state: TeamState) -> ControlOutput:
        out = self.inner.step(state)
        in_play = getattr(self.inner, "in_open_play", None)
        if not (in_play(state) if in_play is not None else state.mode == MatchMode.STARTROBOT):
            self.playing, self.cycles = False, 0
            return out
        self.playing = True
        time_left = 1.0 - (self.cycles % self.episode_steps) / self.episode_steps
        self.cycles += 1
        command = command_from_action(self.net.act(observation(self.net.observations, state, time_left)),
                                      self.kick_max_speed)
        return replace(out, velocity=command.velocity, dribble=command.dribble,
                       kick=command.kick if state.me.holding else None)


def player_or_strategy(inner: StrategyPlugin, params: ControlParams) -> StrategyPlugin:
    """``inner`` wrapped in a ``PolicyPlayer`` when ``params.policy`` names a file."""
    if not params.policy:
        return inner
    return PolicyPlayer.wrapping(inner, params.policy)

