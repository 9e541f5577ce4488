"""Gymnasium and PettingZoo environments over the lockstep engine (pure Python, no rospy).

Requires: ``gymnasium`` and ``pettingzoo`` (requirements.txt). Provides, on import: the Gymnasium id
``NuBot/ScoreAgainstGoalie-v0`` (``score_env.ScoreAgainstGoalieEnv``: one learning attacker against the
built-in goalie) and ``parallel_env(**kwargs)`` (``match_env.MatchParallelEnv``, PettingZoo
``nubot_match_v0``: any robots of a match as agents, the others on the built-in strategy). The action
layout is ``actions``', the observation blocks ``observations``', the default rewards ``rewards``'.
"""

import gymnasium

from nubot_match.envs.match_env import MatchParallelEnv, parallel_env
from nubot_match.envs.score_env import ScoreAgainstGoalieEnv

SCORE_AGAINST_GOALIE = "NuBot/ScoreAgainstGoalie-v0"

if SCORE_AGAINST_GOALIE not in gymnasium.registry:  # a second import must not warn of a re-registration
    gymnasium.register(id=SCORE_AGAINST_GOALIE, entry_point="nubot_match.envs.score_env:ScoreAgainstGoalieEnv")

__all__ = ["SCORE_AGAINST_GOALIE", "MatchParallelEnv", "ScoreAgainstGoalieEnv", "parallel_env"]
