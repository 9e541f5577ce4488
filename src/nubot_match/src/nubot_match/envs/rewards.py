"""Rewards of the environments, replaceable: any ``RewardFn(prev_obs, obs, info) -> float`` will do.

Requires: the ``info`` of a step (see the environments: ``goal``, ``ball_progress`` [m], ...). Provides:
``RewardFn``; ``ScoreReward`` (NuBot/ScoreAgainstGoalie-v0's default: ``goal`` per goal scored, minus
per goal conceded, minus ``step_cost`` per step, plus ``progress`` per metre the ball came closer to the
centre of the attacked goal); ``goal_difference_reward`` (nubot_match_v0's default: goals scored minus
goals conceded by the agent's team in this step, so an episode's return is its goal difference).
"""

from __future__ import annotations

from collections.abc import Callable, Mapping
from dataclasses import dataclass
from typing import Any

import numpy as np

RewardFn = Callable[[np.ndarray, np.ndarray, Mapping[str, Any]], float]


@dataclass(frozen=True)
class ScoreReward:
    goal: float = 1.0  # per goal scored (and minus per own goal)
    step_cost: float = 0.001  # per control period: being quick pays
    progress: float = 0.05  # per metre the ball moved towards the attacked goal's centre [1/m]

    def __call__(self, prev_obs: np.ndarray, obs: np.ndarray, info: Mapping[str, Any]) -> float:
        return self.goal * float(info["goal"]) - self.step_cost + self.progress * float(info["ball_progress"])


def goal_difference_reward(prev_obs: np.ndarray, obs: np.ndarray, info: Mapping[str, Any]) -> float:
    return float(info["goal"])
