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
from gymnasium import spaces
from gymnasium.wrappers import RescaleAction, RescaleObservation

from nubot_common.packages import package_path
from nubot_common.policy import ACTION_NAMES, DERIVED, DERIVED_BOUNDS, policy_input
from nubot_match import NubotMatchError
from nubot_match.envs import SCORE_AGAINST_GOALIE
from nubot_match.envs.match_env import MatchParallelEnv
from nubot_match.envs.rewards import ScoreReward

CONFIG = package_path("nubot_match") / "config"
TEAM_ENV_ID = "nubot_match_v0"


# a striker drives forwards, to the ball and with it (the ball handler is at its front): backwards at most 0.5 m/s
STRIKER_ACTIONS = {"vx": (-0.5, 3.0), "vy": (-1.5, 1.5), "w": (-4.0, 4.0)}  # [m/s], [rad/s]
FACING_RANGE = 2.0  # [m] the facing term of TrainingReward grows from this distance to the ball
NEAR_BALL_STARTS = 0.3  # share of training episodes that start with the ball just in front of the learner


@dataclass(frozen=True)
class TrainingReward:
    """``ScoreReward`` without its cost per step (the discount already pays for being quick, and a cost per step
    would pay for ending an episode by putting the ball out) and with twice its pay per metre the ball moved to
    the goal, plus a potential-based term that leads a beginner to the ball (it keeps the best policy: Ng,
    Harada and Russell 1999). The potential: ``possession`` while holding the ball; otherwise minus ``approach``
    per metre to the ball, plus ``facing`` times the cosine of the ball's bearing, growing from 0 at
    ``FACING_RANGE`` to its whole at the ball (the ball handler takes a ball only within 15 deg of the front)."""

    score: ScoreReward = field(default_factory=lambda: ScoreReward(step_cost=0.0, progress=0.1))
    approach: float = 0.1  # [1/m]
    facing: float = 0.3  # potential: the cosine of the ball's bearing, within FACING_RANGE of the ball
    possession: float = 0.5

    def potential(self, obs: np.ndarray) -> float:
        # indices of observations.own_block: cos_theta 2, sin_theta 3, ball_dx 7, ball_dy 8, holding 11
        if obs[11] > 0.5:
            return self.possession
        distance = math.hypot(obs[7], obs[8])
        bearing_cos = (obs[2] * obs[7] + obs[3] * obs[8]) / distance if distance > 1e-6 else 1.0
        near = max(0.0, 1.0 - distance / FACING_RANGE)
        return -self.approach * distance + self.facing * near * bearing_cos

    def __call__(self, prev_obs: np.ndarray, obs: np.ndarray, info: Mapping[str, Any]) -> float:
        if info.get("end") in ("dropped ball",):  # the referee moved the ball: no potential to gain or lose
            return self.score(prev_obs, obs, info)
        return self.score(prev_obs, obs, info) + self.potential(obs) - self.potential(prev_obs)


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


class ActionRange(gymnasium.ActionWrapper):
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


class NearBallStarts(gymnasium.Wrapper):
    """Training starts: ``share`` of the episodes begin with the ball 0.6 to 1.5 m in front of the learner (within
    17 deg), the robot where the environment puts it; the others as the environment draws them. A beginner then
    meets a ball it can take before it can reach one."""

    def __init__(self, env: gymnasium.Env, share: float):
        super().__init__(env)
        self.share = share
        self._rng = np.random.default_rng()

    def reset(self, *, seed: int | None = None, options: dict[str, Any] | None = None) -> Any:
        if seed is not None:
            self._rng = np.random.default_rng(seed)
        if options or self._rng.random() >= self.share:
            return self.env.reset(seed=seed, options=options)
        field_ = self.env.unwrapped.field
        while True:
            x = self._rng.uniform(0.0, field_.half_length - 3.0)
            y = self._rng.uniform(-(field_.half_width - 1.0), field_.half_width - 1.0)
            theta = self._rng.uniform(-math.pi, math.pi)
            distance, aside = self._rng.uniform(0.6, 1.5), self._rng.uniform(-0.3, 0.3)
            ball = (x + distance * math.cos(theta + aside), y + distance * math.sin(theta + aside))
            if abs(ball[0]) < field_.half_length - 1.0 and abs(ball[1]) < field_.half_width - 1.0:
                return self.env.reset(seed=seed, options={"robot": (x, y, theta), "ball": ball})


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
        env = normalized(NearBallStarts(env, NEAR_BALL_STARTS), self.action_limits)
        if seed is not None:
            env.reset(seed=seed)
            env.action_space.seed(seed)
        return env

    def raw(self) -> gymnasium.Env:
        """The environment with its own spaces and default reward: what a policy is evaluated on."""
        return gymnasium.make(self.env_id, max_steps=self.episode_steps, **self.kwargs)

    def policy_spaces(self) -> tuple[tuple[str, ...], spaces.Box, spaces.Box, float]:
        """The names of a policy's input, its box, the learner's action box, the kick's top speed."""
        env = self.raw()
        try:
            view = PolicyView(ActionRange(env, self.action_limits))
            assert isinstance(view.observation_space, spaces.Box) and isinstance(view.action_space, spaces.Box)
            return view.names, view.observation_space, view.action_space, \
                float(env.unwrapped.plugin.kick_max_speed)
        finally:
            env.close()

    def make_vec(self, workers: int, seed: int) -> Any:
        """The learner's vectorized environment (SB3): ``workers`` environments, each in a process of its own
        (in this one for a single worker)."""
        from stable_baselines3.common.env_util import make_vec_env
        from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

        if workers > 1:
            return make_vec_env(self.make, n_envs=workers, seed=seed, vec_env_cls=SubprocVecEnv,
                                vec_env_kwargs={"start_method": "forkserver"})
        return make_vec_env(self.make, n_envs=1, seed=seed, vec_env_cls=DummyVecEnv)


@dataclass(frozen=True)
class TeamReward:
    """Per agent: the goals its team scored minus those it conceded in the step, plus the score task's two
    potential-based terms on the agent's own block (``approach`` per metre it came closer to the ball while not
    holding it, ``possession`` on taking the ball, minus it on losing it)."""

    approach: float = 0.1  # [1/m]
    possession: float = 0.2

    def __call__(self, prev_obs: np.ndarray, obs: np.ndarray, info: Mapping[str, Any]) -> float:
        before, after = math.hypot(prev_obs[7], prev_obs[8]), math.hypot(obs[7], obs[8])
        shaping = self.approach * (before - after) if prev_obs[11] < 0.5 and obs[11] < 0.5 else 0.0
        return float(info["goal"]) + shaping + self.possession * (float(obs[11]) - float(prev_obs[11]))


def _seeded_vec_env() -> type:
    from supersuit.vector.sb3_vector_wrapper import SB3VecEnvWrapper

    class SeededVecEnv(SB3VecEnvWrapper):
        """SuperSuit's SB3 adapter with the ``seed`` SB3 calls (its own forwards it to a vector env without one):
        the next reset seeds the matches with ``seed``, ``seed + 1``, ..."""

        def __init__(self, venv: Any, seed: int) -> None:
            super().__init__(venv)
            self._next_seed: int | None = seed

        def seed(self, seed: int | None = None) -> list[int | None]:
            self._next_seed = seed
            return [seed]

        def reset(self, seed: int | None = None, options: Any = None) -> Any:
            observations, self.reset_infos = self.venv.reset(seed=seed if seed is not None else self._next_seed)
            self._next_seed = None
            return observations

    return SeededVecEnv


def _SeededVecEnv(venv: Any, seed: int) -> Any:  # noqa: N802 - a class made when SuperSuit is there
    return _seeded_vec_env()(venv, seed)


@dataclass(frozen=True)
class TeamTask:
    name: str
    summary: str
    agents: tuple[str, ...]
    kwargs: dict[str, Any] = field(default_factory=dict)
    episode_steps: int = 600
    action_limits: dict[str, tuple[float, float]] = field(default_factory=lambda: dict(STRIKER_ACTIONS))
    env_id: str = TEAM_ENV_ID

    def raw(self, reward: Any = None) -> MatchParallelEnv:
        return MatchParallelEnv(self.agents, max_cycles=self.episode_steps, reward_fn=reward, **self.kwargs)

    def policy_spaces(self) -> tuple[tuple[str, ...], spaces.Box, spaces.Box, float]:
        """The observation names, the observation box, the learner's action box, the kick's top speed."""
        env = self.raw()
        try:
            agent = self.agents[0]
            obs, full = env.observation_space(agent), env.action_space(agent)
            assert isinstance(obs, spaces.Box) and isinstance(full, spaces.Box)
            low, high = full.low.copy(), full.high.copy()
            for k, name in enumerate(ACTION_NAMES):
                if name in self.action_limits:
                    low[k], high[k] = self.action_limits[name]
            return env.observation_layout(agent), obs, spaces.Box(low, high, dtype=np.float32), \
                env.plugin.kick_max_speed
        finally:
            env.close()

    def make_vec(self, workers: int, seed: int) -> Any:
        """The learner's vectorized environment (SB3): each agent of each of ``workers`` matches is one of its
        environments, in [-1, 1] observations and actions."""
        import supersuit as ss
        from stable_baselines3.common.vec_env import VecMonitor

        _names, obs_box, act_box, _kick = self.policy_spaces()
        env = self.raw(TeamReward())
        o_low, o_high = obs_box.low.astype(np.float64), obs_box.high.astype(np.float64)
        a_low, a_high = act_box.low.astype(np.float64), act_box.high.astype(np.float64)
        unit_obs = spaces.Box(-1.0, 1.0, obs_box.shape, dtype=np.float32)
        unit_act = spaces.Box(-1.0, 1.0, act_box.shape, dtype=np.float32)
        env = ss.observation_lambda_v0(
            env, lambda obs, _space: (2.0 * (obs - o_low) / (o_high - o_low) - 1.0).astype(np.float32),
            lambda _space: unit_obs)
        env = ss.action_lambda_v1(env, lambda action, _space: (a_low + (np.clip(action, -1.0, 1.0) + 1.0) / 2.0
                                                               * (a_high - a_low)).astype(np.float32),
                                  lambda _space: unit_act)
        vec = ss.pettingzoo_env_to_vec_env_v1(env)
        # the matches run in the learner's process: SuperSuit's process pool (num_cpus > 0) forks after PyTorch
        # started its threads, and its workers hung here
        vec = ss.concat_vec_envs_v1(vec, workers, num_cpus=0)
        return VecMonitor(_SeededVecEnv(vec, seed))


TASKS: dict[str, Task | TeamTask] = {
    "score": Task("score", SCORE_AGAINST_GOALIE,
                  "one attacker, from a random start in the attacking half, scores against the built-in goalie"),
    "duo": TeamTask("duo", "two attackers sharing one policy score against the built-in goalie and two defenders",
                    ("nubot2", "nubot3"),
                    {"home": CONFIG / "duo_attackers.yaml", "away": CONFIG / "duo_defence.yaml",
                     "half_seconds": 3600.0, "halves": 1}),
}


@dataclass(frozen=True)
class Episode:
    seed: int
    scored: bool  # the learner (its team) scored
    reward: float  # the episode's return, the environment's default reward
    steps: int
    end: str  # "goal", "out", "dropped ball" or "time"


def task(name: str) -> Task | TeamTask:
    found = TASKS.get(name)
    if found is None:
        raise NubotMatchError(f"unknown task {name!r}; known: {', '.join(sorted(TASKS))}")
    return found


def single_task(name: str) -> Task:
    """The one-robot task ``name`` (the one a scripted striker and a match robot can play)."""
    found = task(name)
    if not isinstance(found, Task):
        raise NubotMatchError(f"task {name!r} trains a team in the PettingZoo environment; here only a one-robot "
                              f"task will do ({', '.join(k for k, t in TASKS.items() if isinstance(t, Task))})")
    return found
