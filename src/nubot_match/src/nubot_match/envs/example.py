"""A random and a scripted policy on NuBot/ScoreAgainstGoalie-v0, episode returns printed (scripts/env_example.py).

Requires: the environment's observation layout (``score_env``) and action layout (``actions``). Provides:
``ScriptedAttacker`` (drive to the ball facing it, take it with the ball handler, turn to the goal, kick
from within ``shot_range`` [m] once facing the open side of the goal), ``run_episodes`` (returns and
goals of a policy over seeded episodes) and ``main`` (both policies over ``--episodes`` seeds).
"""

from __future__ import annotations

import argparse
import math
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass

import gymnasium
import numpy as np

from nubot_common.geometry import wrap_angle
from nubot_match.envs import SCORE_AGAINST_GOALIE
from nubot_match.envs.observations import OWN_NAMES

Policy = Callable[[np.ndarray], np.ndarray]
_I = {name: k for k, name in enumerate((*OWN_NAMES, "goalie_x", "goalie_y", "time_left"))}


@dataclass(frozen=True)
class ScriptedAttacker:
    half_length: float  # of the field [m]: the attacked goal's centre is at (half_length, 0)
    speed: float = 2.5  # cruise speed [m/s]
    carry_speed: float = 1.5  # speed with the ball [m/s]
    turn_gain: float = 4.0  # turn rate per radian of heading error [1/s]
    carry_turn: float = 2.5  # turn rate limit with the ball: the ball handler keeps it only so far [rad/s]
    position_gain: float = 2.0  # speed per metre to the ball when close [1/s]
    take_distance: float = 1.0  # ball handler on within this distance of the ball [m]
    shot_range: float = 4.5  # kick from this close to the goal [m]
    aim_offset: float = 0.6  # aim this far from the goal's centre, away from the goalie [m]
    aim_tolerance: float = 0.08  # kick when the heading is this close to the aim [rad]

    def __call__(self, obs: np.ndarray) -> np.ndarray:
        x, y = float(obs[_I["x"]]), float(obs[_I["y"]])
        theta = math.atan2(float(obs[_I["sin_theta"]]), float(obs[_I["cos_theta"]]))
        if obs[_I["holding"]] > 0.5:
            side = -1.0 if obs[_I["goalie_y"]] > 0.0 else 1.0  # the side of the goal the goalie leaves open
            tx, ty = self.half_length, side * self.aim_offset
            error = wrap_angle(math.atan2(ty - y, tx - x) - theta)
            distance = math.hypot(tx - x, ty - y)
            kick = distance < self.shot_range and abs(error) < self.aim_tolerance
            vx = self.carry_speed if distance >= self.shot_range and abs(error) < 0.5 else 0.0
            turn = max(-self.carry_turn, min(self.carry_turn, self.turn_gain * error))
            return self._action(vx, 0.0, turn, 1.0, 1.0 if kick else 0.0)
        dx, dy = float(obs[_I["ball_dx"]]), float(obs[_I["ball_dy"]])
        distance = math.hypot(dx, dy)
        error = wrap_angle(math.atan2(dy, dx) - theta)
        speed = min(self.speed, self.position_gain * distance) * max(0.0, math.cos(error))
        return self._action(speed, 0.0, self.turn_gain * error, float(distance < self.take_distance), 0.0)

    @staticmethod
    def _action(vx: float, vy: float, w: float, dribble: float, kick: float) -> np.ndarray:
        return np.array([vx, vy, max(-12.0, min(12.0, w)), dribble, kick], dtype=np.float32)


@dataclass
class Outcome:
    returns: list[float]
    goals: int
    touched: int  # episodes in which the learner held the ball at some time


def run_episodes(env: gymnasium.Env, policy: Policy, seeds: Sequence[int]) -> Outcome:
    out = Outcome([], 0, 0)
    for seed in seeds:
        obs, _info = env.reset(seed=seed)
        total, touched, done = 0.0, False, False
        while not done:
            obs, reward, terminated, truncated, info = env.step(policy(obs))
            total += float(reward)
            touched = touched or bool(info["holding"])
            out.goals += max(int(info["goal"]), 0)
            done = terminated or truncated
        out.returns.append(total)
        out.touched += touched
    return out


def random_policy(space: gymnasium.spaces.Space, seed: int) -> Policy:
    space.seed(seed)
    return lambda _obs: np.asarray(space.sample())


def main(argv: Sequence[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--episodes", type=int, default=5, help="episodes per policy (seeds 0, 1, ...)")
    parser.add_argument("--max-steps", type=int, default=300, help="steps per episode (35 ms each)")
    args = parser.parse_args(argv)
    env = gymnasium.make(SCORE_AGAINST_GOALIE, max_steps=args.max_steps)
    seeds = range(args.episodes)
    field = env.unwrapped.field
    policies: dict[str, Policy] = {"random": random_policy(env.action_space, 0),
                                   "scripted": ScriptedAttacker(field.half_length)}
    for name, policy in policies.items():
        start = time.perf_counter()
        out = run_episodes(env, policy, seeds)
        returns = " ".join(f"{r:+.3f}" for r in out.returns)
        print(f"{name:8s} returns [{returns}]  mean {np.mean(out.returns):+.3f}  goals {out.goals}/{len(seeds)}  "
              f"held the ball in {out.touched}/{len(seeds)}  ({time.perf_counter() - start:.1f} s)")
    env.close()
    return 0
