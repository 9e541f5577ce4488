"""nubot_match_v0: a refereed match in which any of the robots are agents (PettingZoo ``ParallelEnv``).

Requires: two team YAMLs (default the shipped 5 vs 5: nubot attacks +x, rival -x), the field, the half
length [s of game time] and number of halves. Provides: ``MatchParallelEnv`` and ``parallel_env(**kwargs)``.
The agents (``agents=("nubot2", "rival3", ...)``, default every robot) get their commands from ``step``;
the other robots play the built-in strategy. The match runs as the lockstep engine runs it: kick-off set-up,
restarts, half time (the ends change, and so does each team's frame). One step is one control period
(1/33 s; 35 ms in effect). Every agent's episode ends together: terminated at full time, truncated after
``max_cycles`` steps (None: no limit).

Observation of an agent (``Box`` float32, its team's frame: own goal at -x, attacked goal at +x; SI units;
true state; clipped to the bounds): ``observations.own_block`` (12: x, y, cos_theta, sin_theta, vx, vy, w,
ball_dx, ball_dy, ball_vx, ball_vy, holding); then each teammate, in name order, and each opponent, in
name order: ``mate<k>_x, _y, _vx, _vy`` / ``opp<k>_x, _y, _vx, _vy`` [m], [m/s] (k the robot's number);
then goal_difference (own minus the opponents' goals, clipped to +-20), running (1 while the ball is in
play), restart (1: own set piece being set up or not taken yet, -1: the opponents', 0: none or a dropped
ball), match_left (fraction of the match's game time left), cycles_left (fraction of ``max_cycles`` left;
1 without a limit). ``observation_layout(agent)`` gives the names. Action: ``actions.action_space``.
Reward: ``reward_fn(prev_obs, obs, info)``, default ``rewards.goal_difference_reward``. Info of an agent:
agent, team, goal (own goals minus conceded in this step), score (own, opponents'), time [s, sim time].
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path
from typing import Any

import numpy as np
from gymnasium import spaces
from gymnasium.utils import seeding
from pettingzoo import ParallelEnv

from nubot_common.naming import parse_robot_name
from nubot_common.team_frame import TeamFrame
from nubot_match import NubotMatchError
from nubot_match.config import TEAMS, match_config
from nubot_match.engine import LockstepMatch
from nubot_match.envs import match_adapter as adapter
from nubot_match.envs.actions import action_space, to_command
from nubot_match.envs.observations import OWN_NAMES, Layout, other_block, other_names, own_block
from nubot_match.envs.rewards import RewardFn, goal_difference_reward
from sim_visual.simulator import Simulator

ENGINE_SEEDS = 2**31 - 1  # engine seeds are drawn from [0, this)
GAME_NAMES = ("goal_difference", "running", "restart", "match_left", "cycles_left")


class MatchParallelEnv(ParallelEnv[str, np.ndarray, np.ndarray]):
    metadata: dict[str, Any] = {"name": "nubot_match_v0", "render_modes": [], "is_parallelizable": True,
                                "render_fps": 33}

    def __init__(self, agents: Sequence[str] | None = None, *, home: str | Path = TEAMS / "nubot.yaml",
                 away: str | Path = TEAMS / "rival.yaml", field: str | Path = "18x12", tracker: str = "",
                 half_seconds: float = 300.0, halves: int = 2, max_cycles: int | None = None,
                 reward_fn: RewardFn | None = None, render_mode: str | None = None):
        if render_mode is not None:
            raise NubotMatchError(f"render_mode must be None (no viewer yet), got {render_mode!r}")
        if max_cycles is not None and max_cycles < 1:
            raise NubotMatchError(f"max_cycles must be at least 1 (or None), got {max_cycles}")
        config = match_config(home, away, field, tracker, half_seconds=half_seconds, halves=halves)
        robots = config.robot_names
        chosen = list(robots if agents is None else agents)
        unknown = [a for a in chosen if a not in robots]
        if unknown or not chosen or len(set(chosen)) != len(chosen):
            raise NubotMatchError(f"agents must be distinct robots of this match ({', '.join(robots)}); got "
                                  f"{chosen}" + (f", unknown: {unknown}" if unknown else ""))
        self.possible_agents = chosen
        self.agents: list[str] = []
        self.render_mode = render_mode
        self.max_cycles = max_cycles
        self.reward_fn: RewardFn = goal_difference_reward
        if reward_fn is not None:
            self.reward_fn = reward_fn
        self.match = LockstepMatch(config, external=chosen)
        self.plugin = config.sim.sim.plugin
        self._team = {name: parse_robot_name(name).team for name in robots}
        self._members = {t.config.prefix: t.config.robot_names() for t in config.teams}
        self._layouts = {a: Layout(self._names(a), config.world.field, self.plugin) for a in chosen}
        self._action_spaces = {a: action_space(self.plugin) for a in chosen}
        self._np_random: np.random.Generator | None = None
        self._cycles = 0
        self._obs: dict[str, np.ndarray] = {}
        self._score: dict[str, int] = {}

    # --- spaces ---------------------------------------------------------------------------------------
    def _names(self, agent: str) -> tuple[str, ...]:
        team = self._team[agent]
        mates = [n for n in self._members[team] if n != agent]
        others = [n for t, names in self._members.items() if t != team for n in names]
        return (*OWN_NAMES, *(m for n in mates for m in other_names(f"mate{parse_robot_name(n).agent_id}")),
                *(m for n in others for m in other_names(f"opp{parse_robot_name(n).agent_id}")), *GAME_NAMES)

    def observation_layout(self, agent: str) -> tuple[str, ...]:
        return self._layout(agent).names

    def observation_space(self, agent: str) -> spaces.Space:
        """The same object at every call (built once per agent), as PettingZoo's seeding needs."""
        return self._layout(agent).space

    def action_space(self, agent: str) -> spaces.Space:
        """One ``Box`` per agent, built once: each agent's samples come from its own seeded generator."""
        self._layout(agent)
        return self._action_spaces[agent]

    def _layout(self, agent: str) -> Layout:
        try:
            return self._layouts[agent]
        except KeyError:
            raise NubotMatchError(f"unknown agent {agent!r}; agents: {', '.join(self.possible_agents)}") from None

    # --- the episode ------------------------------------------------------------------------------------
    def reset(self, seed: int | None = None,
              options: dict[str, Any] | None = None) -> tuple[dict[str, np.ndarray], dict[str, dict[str, Any]]]:
        """Seed the env's generator (``seed``, or keep it); the engine's seed is drawn from it. No options yet."""
        if seed is not None or self._np_random is None:
            generator: np.random.Generator = seeding.np_random(seed)[0]
            self._np_random = generator
        self.match.reset(int(self._np_random.integers(ENGINE_SEEDS)))
        self.agents = list(self.possible_agents)
        self._cycles = 0
        state = self.match.state()
        self._score = {t: adapter.score_of(state, t) for t in self._members}
        self._obs = {a: self._observe(a) for a in self.agents}
        return dict(self._obs), {a: self._info(a, 0) for a in self.agents}

    def step(self, actions: Mapping[str, np.ndarray]) -> tuple[
            dict[str, np.ndarray], dict[str, float], dict[str, bool], dict[str, bool], dict[str, dict[str, Any]]]:
        if not self.agents:
            raise NubotMatchError("the episode is over (or never began): call reset() first")
        stray = sorted(set(actions) - set(self.agents))
        missing = sorted(set(self.agents) - set(actions))
        if stray or missing:
            raise NubotMatchError(f"actions must name every agent ({', '.join(self.agents)})"
                                  + (f"; unknown: {stray}" if stray else "")
                                  + (f"; missing: {missing}" if missing else ""))
        commands = {a: to_command(actions[a], self._action_spaces[a], self.plugin, a) for a in self.agents}
        out = self.match.step(commands)
        self._cycles += 1
        state = self.match.state()
        score = {t: adapter.score_of(state, t) for t in self._members}
        gained = {t: score[t] - self._score[t] for t in score}
        self._score = score
        prev, self._obs = self._obs, {a: self._observe(a) for a in self.agents}
        infos = {a: self._info(a, gained[self._team[a]] - sum(g for t, g in gained.items() if t != self._team[a]))
                 for a in self.agents}
        rewards = {a: float(self.reward_fn(prev[a], self._obs[a], infos[a])) for a in self.agents}
        truncated = self.max_cycles is not None and self._cycles >= self.max_cycles and not out.done
        terminations = dict.fromkeys(self.agents, out.done)
        truncations = dict.fromkeys(self.agents, truncated)
        obs = dict(self._obs)
        if out.done or truncated:
            self.agents = []
        return obs, rewards, terminations, truncations, infos

    def render(self) -> None:
        return None

    def close(self) -> None:
        self.match.close()

    # --- helpers ------------------------------------------------------------------------------------------
    def _sim(self) -> Simulator:
        assert self.match.sim is not None, "reset() builds the simulator"
        return self.match.sim

    def _observe(self, agent: str) -> np.ndarray:
        sim, state = self._sim(), self.match.state()
        world, team = sim.world, self._team[agent]
        frame = TeamFrame(adapter.team_attack(state, team))
        values = own_block(frame, world.robot_state(agent), world.ball_state(), sim.holder == agent)
        for t in (team, *(t for t in self._members if t != team)):
            for name in self._members[t]:
                if name != agent:
                    values += other_block(frame, world.robot_state(name))
        k = state.teams.index(team)
        # After STARTROBOT the restart is still on until it is taken: the command before tells whose it is.
        mode = state.previous_mode[k] if self.match.referee.restart_pending else state.match_mode[k]
        restart = 1.0 if mode.is_ours else -1.0 if mode.is_theirs else 0.0
        own = self._score[team]
        against = sum(s for t, s in self._score.items() if t != team)
        cfg = self.match.config
        played = max(state.half - 1, 0) * cfg.half_duration + state.game_time
        match_left = 1.0 - played / (cfg.halves * cfg.half_duration) if not self.match.done else 0.0
        cycles_left = 1.0 - self._cycles / self.max_cycles if self.max_cycles is not None else 1.0
        values += [own - against, float(state.running), restart, match_left, cycles_left]
        return self._layouts[agent].vector(values)

    def _info(self, agent: str, goal: int) -> dict[str, Any]:
        team = self._team[agent]
        against = sum(s for t, s in self._score.items() if t != team)
        return {"agent": agent, "team": team, "goal": goal, "score": (self._score[team], against),
                "time": self._sim().time}


def parallel_env(**kwargs: Any) -> MatchParallelEnv:
    """PettingZoo's factory: ``MatchParallelEnv(**kwargs)``."""
    return MatchParallelEnv(**kwargs)
