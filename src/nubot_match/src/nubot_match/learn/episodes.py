"""Seeded episodes of a task played by a policy file or by the scripted striker, and their success rates.

Requires: a task (``tasks``), a ``PolicyNet`` file or the scripted striker (``envs.example.ScriptedAttacker``).
Provides: ``Episode`` (seed, scored, return, steps, how it ended), ``player(name)`` (``"scripted"`` or a policy
file's path -> a function of the raw observation), ``play(task, player, seeds)``, ``play_parallel`` (the seeds
split over worker processes; same results as ``play``), and ``success(episodes)`` (the share of episodes with
a goal, with its Wilson 95 % interval). Both players see the environment's own observation and act on its
own action space; the return is the environment's default reward (``rewards.ScoreReward``).
"""

from __future__ import annotations

import multiprocessing
from collections.abc import Callable, Sequence
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np

from nubot_common.policy import PolicyError, PolicyNet, policy_input
from nubot_match import NubotMatchError
from nubot_match.envs.example import ScriptedAttacker
from nubot_match.learn.tasks import Episode, Task, TeamTask, episode_success, single_task
from nubot_match.statistics import Interval, share_interval

SCRIPTED = "scripted"
CHUNK = 10  # episodes a worker plays at a time
Player = Callable[[np.ndarray], np.ndarray]


def load_policy(path: str | Path, env_id: str) -> PolicyNet:
    """The policy file ``path``, checked to be trained on ``env_id``; ``NubotMatchError`` saying why not."""
    try:
        net = PolicyNet.load(path)
    except PolicyError as exc:
        raise NubotMatchError(str(exc)) from None
    trained_on = net.meta.get("env_id")
    if trained_on != env_id:
        raise NubotMatchError(f"{path} was trained on {trained_on!r}, not on {env_id!r}")
    return net


def player(name: str, the_task: Task) -> Player:
    """``"scripted"``: the scripted striker; else a policy file trained on ``the_task``."""
    if name == SCRIPTED:
        env = the_task.raw()
        half_length = env.unwrapped.field.half_length
        env.close()
        return ScriptedAttacker(half_length)
    net = load_policy(name, the_task.env_id)
    env = the_task.raw()
    names, half_length = env.unwrapped.layout.names, env.unwrapped.field.half_length
    env.close()

    def act(obs: np.ndarray) -> np.ndarray:
        return net.act(policy_input(dict(zip(names, map(float, obs))), net.observations, half_length)) \
            .astype(np.float32)
    return act


def play(the_task: Task, who: Player, seeds: Sequence[int]) -> list[Episode]:
    env = the_task.raw()
    episodes = []
    try:
        for seed in seeds:
            obs, info = env.reset(seed=int(seed))
            total, steps, done = 0.0, 0, False
            while not done:
                obs, reward, terminated, truncated, info = env.step(who(obs))
                total += float(reward)
                steps += 1
                done = terminated or truncated
            episodes.append(Episode(int(seed), episode_success(info), total, steps, str(info["end"])))
    finally:
        env.close()
    return episodes


def _play_named(task_name: str, name: str, seeds: Sequence[int]) -> list[Episode]:
    the_task = single_task(task_name)
    return play(the_task, player(name, the_task), seeds)


def play_parallel(task_name: str, name: str, seeds: Sequence[int], jobs: int,
                  done: Callable[[int], None] | None = None) -> list[Episode]:
    """``play`` of the player ``name`` over ``seeds`` in ``jobs`` worker processes, in seed order; ``done(n)``
    after each ``CHUNK`` of n episodes."""
    player(name, single_task(task_name))  # refuse a bad file here, before any worker starts
    chunks = [list(map(int, seeds[k:k + CHUNK])) for k in range(0, len(seeds), CHUNK)]
    episodes: list[Episode] = []
    if jobs <= 1:
        for chunk in chunks:
            episodes += _play_named(task_name, name, chunk)
            if done is not None:
                done(len(chunk))
        return episodes
    with ProcessPoolExecutor(jobs, mp_context=multiprocessing.get_context("forkserver")) as pool:
        for part in pool.map(_play_named, [task_name] * len(chunks), [name] * len(chunks), chunks):
            episodes += part
            if done is not None:
                done(len(part))
    return episodes


def success(episodes: Sequence[Episode]) -> Interval:
    return share_interval(sum(e.scored for e in episodes), len(episodes))


def play_team(task: TeamTask, net: PolicyNet, seeds: Sequence[int]) -> list[Episode]:
    """Seeded episodes with ``net`` on every agent; an episode scores when the agents' team scored in it."""
    env = task.raw()
    names = env.observation_layout(task.agents[0])
    episodes = []
    try:
        for seed in seeds:
            obs, _info = env.reset(seed=int(seed))
            goals, steps = 0.0, 0
            scored = False
            while env.agents:
                actions = {a: net.act(policy_input(dict(zip(names, map(float, obs[a]))), net.observations, 0.0))
                           .astype(np.float32) for a in env.agents}
                obs, _rewards, _terms, _truncs, infos = env.step(actions)
                steps += 1
                goal = float(next(iter(infos.values()))["goal"]) if infos else 0.0
                goals += goal
                scored = scored or goal > 0
            episodes.append(Episode(int(seed), scored, goals, steps, "goal" if scored else "time"))
    finally:
        env.close()
    return episodes
