"""What a robot can be trained to do: the tasks of ``make train`` (pure Python: gymnasium, no learning library).

Requires: the environments (``nubot_match.envs``). Provides: ``TASKS`` (name -> ``Task``), ``task(name)``
(``NubotMatchError`` naming the known ones), ``TrainingReward`` (the score task's reward while training),
``PolicyView`` (the observation with the robot's own view added, ``nubot_common.policy.DERIVED``),
``normalized(env)`` (that view, and the action, mapped onto [-1, 1], the way ``PolicyNet`` plays them) and
``episode_success(info)``.

A task makes one environment per worker (``make(seed)``), says what counts as a success (a goal scored by
the learner) and which observation entries a robot in a match can fill (``observations``).
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field
from typing import Any

import gymnasium
import numpy as np
from gymnasium.wrappers import RescaleAction, RescaleObservation

from nubot_common.policy import ACTION_NAMES, DERIVED, DERIVED_BOUNDS, policy_input
from nubot_match import NubotMatchError
from nubot_match.envs import SCORE_AGAINST_GOALIE
from nubot_match.envs.rewards import ScoreReward


STRIKER_ACTIONS = {"vx": (-3.0, 3.0), "vy": (-3.0, 3.0), "w": (-4.0, 4.0)}  # [m/s], [rad/s]


@dataclass(frozen=True)
class TrainingReward:
    """``ScoreReward`` without its cost per step (the discount already pays for being quick, and a cost per step
    would pay for ending an episode by putting the ball out) and with twice its pay per metre the ball moved to
    the goal, plus two potential-based terms that lead a beginner to the ball (they keep the best policy: Ng,
    Harada and Russell 1999): ``approach`` per metre the learner came closer to the ball while it did not hold
    it, and ``possession`` on taking the ball (minus it on losing it)."""

    score: ScoreReward = field(default_factory=lambda: ScoreReward(step_cost=0.0, progress=0.1))
    approach: float = 0.1  # [1/m]
    possession: float = 0.2

    def __call__(self, prev_obs: np.ndarray, obs: np.ndarray, info: Mapping[str, Any]) -> float:
        # indices of observations.own_block: ball_dx 7, ball_dy 8, holding 11
        before, after = math.hypot(prev_obs[7], prev_obs[8]), math.hypot(obs[7], obs[8])
        shaping = self.approach * (before - after) if prev_obs[11] < 0.5 and obs[11] < 0.5 else 0.0
        shaping += self.possession * (float(obs[11]) - float(prev_obs[11]))
        return self.score(prev_obs, obs, info) + shaping


class PolicyView(gymnasium.ObservationWrapper):
    """The environment's observation with the entries in the robot's own frame added (``policy.DERIVED``): what a
    policy reads, in a learner and on a robot in a match (``nubot_control.policy_player``) alike."""

    def __init__(self, env: gymnasium.Env):
        super().__init__(env)
        raw = env.observation_space
        assert isinstance(raw, gymnasium.spaces.Box)
        self.raw_names: tuple[str, ...] = env.unwrapped.layout.names
        self.half_length = float(env.unwrapped.field.half_length)
        self.names = (*self.raw_names, *DERIVED)
        bounds = np.array([DERIVED_BOUNDS[n] for n in DERIVED], dtype=np.float32)
        low = np.concatenate([raw.low, [0.0 if n.endswith("distance") else -b for n, b in zip(DERIVED, bounds)]])
        self.observation_space = gymnasium.spaces.Box(low.astype(np.float32),
                                                      np.concatenate([raw.high, bounds]).astype(np.float32))

    def observation(self, observation: np.ndarray) -> np.ndarray:
        values = dict(zip(self.raw_names, map(float, observation)))
        out = policy_input(values, self.names, self.half_length).astype(np.float32)
        return np.clip(out, self.observation_space.low, self.observation_space.high)


class ActionRange(gymnasium.ActionWrapper):  # type: ignore[type-arg]
    """The environment's actions within a narrower box: a learner explores over the speeds a striker uses rather
    than the robot's limits (a turn rate drawn from +-12 rad/s makes every beginner spin on the spot)."""

    def __init__(self, env: gymnasium.Env, limits: Mapping[str, tuple[float, float]]):
        super().__init__(env)
        full = env.action_space
        assert isinstance(full, gymnasium.spaces.Box)
        low, high = full.low.copy(), full.high.copy()
        for k, name in enumerate(ACTION_NAMES):
            if name in limits:
                low[k], high[k] = max(low[k], limits[name][0]), min(high[k], limits[name][1])
        self.action_space = gymnasium.spaces.Box(low, high, dtype=np.float32)

    def action(self, action: np.ndarray) -> np.ndarray:
        return action


def normalized(env: gymnasium.Env, limits: Mapping[str, tuple[float, float]] | None = None) -> gymnasium.Env:
    """``env`` seen by a policy (``PolicyView``) through [-1, 1] observations and actions (over ``limits``, by
    action name): what a learner sees, and what ``PolicyNet`` undoes."""
    env = PolicyView(ActionRange(env, limits or {}))
    box = env.observation_space
    assert isinstance(box, gymnasium.spaces.Box)
    ones = np.ones(box.shape, dtype=np.float32)
    act_ones = np.ones(env.action_space.shape, dtype=np.float32)
    return RescaleAction(RescaleObservation(env, -ones, ones), -act_ones, act_ones)


def episode_success(info: Mapping[str, Any]) -> bool:
    """The last step of a score episode: did the learner score?"""
    return int(info.get("goal", 0)) > 0


@dataclass(frozen=True)
class Task:
    name: str
    env_id: str
    summary: str
    kwargs: dict[str, Any] = field(default_factory=dict)  # the environment's options while training
    episode_steps: int = 300  # the longest episode [steps]
    # the learner's actions, by name, within these bounds (the others over the environment's own)
    action_limits: dict[str, tuple[float, float]] = field(default_factory=lambda: dict(STRIKER_ACTIONS))

    def make(self, seed: int | None = None, reward: Callable[..., float] | None = None) -> gymnasium.Env:
        """One environment of this task, as a learner sees it (normalized), seeded with ``seed``."""
        env = gymnasium.make(self.env_id, max_steps=self.episode_steps,
                             reward_fn=TrainingReward() if reward is None else reward, **self.kwargs)
        env = normalized(env, self.action_limits)
        if seed is not None:
            env.reset(seed=seed)
            env.action_space.seed(seed)
        return env

    def raw(self) -> gymnasium.Env:
        """The environment with its own spaces and default reward: what a policy is evaluated on."""
        return gymnasium.make(self.env_id, max_steps=self.episode_steps, **self.kwargs)


TASKS: dict[str, Task] = {
    "score": Task("score", SCORE_AGAINST_GOALIE,
                  "one attacker, from a random start in the attacking half, scores against the built-in goalie"),
}


def task(name: str) -> Task:
    found = TASKS.get(name)
    if found is None:
        raise NubotMatchError(f"unknown task {name!r}; known: {', '.join(sorted(TASKS))}")
    return found
