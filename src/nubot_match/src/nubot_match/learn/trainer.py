"""Train a robot on a task with Stable-Baselines3 (``make train``, ``scripts/train.py``).

    python scripts/train.py [--task score|duo] [--algorithm ppo] [--steps 2000000] [--workers N] [--seed 0]
                            [--out DIR [--resume]] [--checkpoint-every 100000] [--eval-episodes 50]

Requires: ``requirements-train.txt`` (PyTorch's CPU build, Stable-Baselines3, TensorBoard; ``make train``
installs them on its first use) and the task's environment (``tasks``). The environments run in ``--workers``
processes (default: two per core, so the cores stay busy while the learner picks the next actions), each seeded
from ``--seed``; the learner's own randomness too, and PyTorch runs on one thread, so the same seed and options
give the same learning curve on the same machine.
Provides, in ``--out`` (default ``runs/<task>-<time>/``):

- ``run.json``: the options, the environment's id and options, the versions of Python and the libraries, the
  commit, and after the run the steps per second;
- ``tensorboard/``: the learner's own figures, and ``eval/success_rate`` (``tensorboard --logdir DIR``);
- ``checkpoints/<algorithm>_<steps>.zip``: the learner at each checkpoint (``--resume`` goes on from the last);
- ``policies/policy_<steps>.npz`` and ``policy.npz`` (the last): the policy as a file a robot plays with numpy
  alone (``nubot_common.policy.PolicyNet``), for a match (``make match POLICY=...``) or ``make evaluate``;
- ``curve.csv`` and ``learning_curve.png``: at each checkpoint the success rate of that policy file over the
  same ``--eval-episodes`` seeded episodes (deterministic, with its Wilson 95 % interval), and the share of the
  training episodes since the last checkpoint that scored.

A progress bar on stderr shows the steps, steps per second and the time left. Exit status 0; 2 for bad
options (an unknown task or algorithm, a step count below one, a run folder that is not this run's), with a
clear message and no traceback.
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import platform
import subprocess
import sys
import time
from dataclasses import asdict, dataclass, replace
from datetime import datetime
from importlib import metadata
from pathlib import Path
from typing import Any

import numpy as np

from nubot_common.json_text import strict_json
from nubot_common.policy import PolicyNet
from nubot_match import NubotMatchError
from nubot_match.learn.episodes import play, play_team, player
from nubot_match.learn.tasks import TASKS, Task, TeamTask, episode_success, task

ALGORITHMS = ("ppo",)
EVAL_SEEDS = 1_000_000  # checkpoint evaluations play seeds EVAL_SEEDS, EVAL_SEEDS + 1, ... (not the training ones)
LIBRARIES = ("numpy", "gymnasium", "pettingzoo", "torch", "stable-baselines3", "tensorboard")
CURVE_FIELDS = ("steps", "success", "low", "high", "episodes", "train_success", "train_episodes", "wall_seconds")
# PPO's options: a rollout of 512 steps per worker, 5 passes over it in batches of 512; a discount with a horizon
# of 100 steps (3.5 s); the first actions spread by exp(-0.5) = 0.6 of the action's half range
PPO_OPTIONS: dict[str, Any] = {"n_steps": 512, "batch_size": 512, "n_epochs": 5, "learning_rate": 3e-4,
                               "gamma": 0.99, "gae_lambda": 0.95, "clip_range": 0.2, "ent_coef": 0.0,
                               "policy_kwargs": {"log_std_init": -0.5}}


@dataclass(frozen=True)
class TrainOptions:
    task: str = "score"
    algorithm: str = "ppo"
    steps: int = 2_000_000
    workers: int = 2 * (os.cpu_count() or 1)  # two environments per core keep the cores busy beside the learner
    seed: int = 0
    out: str = ""
    resume: bool = False
    checkpoint_every: int = 100_000
    eval_episodes: int = 50

    def check(self) -> Task | TeamTask:
        """The task; ``NubotMatchError`` for options that cannot train."""
        the_task = task(self.task)
        if self.algorithm not in ALGORITHMS:
            raise NubotMatchError(f"unknown algorithm {self.algorithm!r}; known: {', '.join(ALGORITHMS)}")
        for name in ("steps", "workers", "checkpoint_every"):
            if getattr(self, name) < 1:
                raise NubotMatchError(f"--{name.replace('_', '-')} must be at least 1, got {getattr(self, name)}")
        if self.eval_episodes < 0:
            raise NubotMatchError(f"--eval-episodes must be at least 0, got {self.eval_episodes}")
        if self.resume and not self.out:
            raise NubotMatchError("--resume needs the --out of the run to go on with")
        return the_task


def versions() -> dict[str, str]:
    found = {"python": platform.python_version()}
    for name in LIBRARIES:
        try:
            found[name] = metadata.version(name)
        except metadata.PackageNotFoundError:
            found[name] = "absent"
    return found


def commit() -> str:
    try:
        out = subprocess.run(["git", "rev-parse", "HEAD"], cwd=Path(__file__).resolve().parent, capture_output=True,
                             text=True, timeout=10, check=True)
        return out.stdout.strip()
    except (OSError, subprocess.SubprocessError):
        return "unknown"


# --- the policy file -------------------------------------------------------------------------------------
def export_policy(model: Any, the_task: Task | TeamTask, meta: dict[str, Any]) -> PolicyNet:
    """The deterministic actor of an SB3 ``ActorCriticPolicy`` (its MLP to the Gaussian's mean) as a
    ``PolicyNet`` over the task's raw spaces."""
    import torch

    policy = model.policy
    layers = [m for m in policy.mlp_extractor.policy_net if isinstance(m, torch.nn.Linear)] + [policy.action_net]
    activations = {type(m).__name__ for m in policy.mlp_extractor.policy_net if not isinstance(m, torch.nn.Linear)}
    activation = {"Tanh": "tanh", "ReLU": "relu"}.get(activations.pop() if activations else "Tanh")
    if activation is None or activations:
        raise NubotMatchError(f"the policy's activations {activations} have no numpy twin")
    names, obs_space, act_space, kick_max_speed = the_task.policy_spaces()
    with torch.no_grad():
        weights = [m.weight.detach().cpu().numpy().astype(np.float64) for m in layers]
        biases = [m.bias.detach().cpu().numpy().astype(np.float64) for m in layers]
    return PolicyNet(names, obs_space.low, obs_space.high, act_space.low, act_space.high,
                     weights, biases, activation,
                     meta={**meta, "env_id": the_task.env_id, "task": the_task.name, "kick_max_speed": kick_max_speed,
                           "episode_steps": the_task.episode_steps})


# --- the run folder -------------------------------------------------------------------------------------
class RunFolder:
    def __init__(self, path: Path):
        self.path = path
        self.checkpoints = path / "checkpoints"
        self.policies = path / "policies"
        self.curve = path / "curve.csv"
        self.manifest = path / "run.json"

    def prepare(self, options: TrainOptions, the_task: Task | TeamTask) -> list[dict[str, float]]:
        """Create the folder (or check it is this run's, to resume); the curve so far."""
        if options.resume:
            if not self.manifest.is_file():
                raise NubotMatchError(f"--resume: {self.path} holds no run (no run.json)")
            before = json.loads(self.manifest.read_text())["options"]
            changed = [k for k in ("task", "algorithm", "seed", "workers") if before.get(k) != getattr(options, k)]
            if changed:
                raise NubotMatchError(f"--resume: {self.path} was trained with other {', '.join(changed)} "
                                      f"({', '.join(f'{k}={before.get(k)!r}' for k in changed)})")
            rows = self.read_curve()
        else:
            if self.manifest.exists():
                raise NubotMatchError(f"{self.path} already holds a run: --resume goes on with it, or give "
                                      "another --out")
            rows = []
        for folder in (self.path, self.checkpoints, self.policies):
            folder.mkdir(parents=True, exist_ok=True)
        self.write_manifest({"options": asdict(options), "task": the_task.summary, "env_id": the_task.env_id,
                             "env_options": {**{k: str(v) if isinstance(v, Path) else v
                                                for k, v in the_task.kwargs.items()},
                                             "max_steps": the_task.episode_steps},
                             "reward": "nubot_match.learn.tasks.TrainingReward", "algorithm_options": PPO_OPTIONS,
                             "action_limits": the_task.action_limits,
                             "versions": versions(), "commit": commit(), "cores": os.cpu_count(),
                             "started": datetime.now().isoformat(timespec="seconds")})
        return rows

    def write_manifest(self, data: dict[str, Any]) -> None:
        old = json.loads(self.manifest.read_text()) if self.manifest.is_file() else {}
        self.manifest.write_text(strict_json({**old, **data}, indent=2) + "\n")

    def latest_checkpoint(self) -> tuple[Path, int] | None:
        found = []
        for path in self.checkpoints.glob("*_*.zip"):
            tail = path.stem.rsplit("_", 1)[-1]
            if tail.isdigit():
                found.append((int(tail), path))
        if not found:
            return None
        steps, latest = max(found)
        return latest, steps

    def read_curve(self) -> list[dict[str, float]]:
        if not self.curve.is_file():
            return []
        with open(self.curve, newline="") as handle:
            return [{k: float(v) for k, v in row.items()} for row in csv.DictReader(handle)]

    def write_curve(self, rows: list[dict[str, float]]) -> None:
        partial = self.curve.with_suffix(".partial")
        with open(partial, "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=CURVE_FIELDS)
            writer.writeheader()
            writer.writerows(rows)
        os.replace(partial, self.curve)
        plot_curve(rows, self.path / "learning_curve.png", self.path.name)


def plot_curve(rows: list[dict[str, float]], path: Path, title: str) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    fig, ax = plt.subplots(figsize=(7, 4))
    if rows:
        steps = np.array([r["steps"] for r in rows]) / 1e6
        if any(r["episodes"] > 0 for r in rows):
            ax.plot(steps, [r["success"] for r in rows], "o-", color="tab:blue",
                    label=f"policy file, {int(rows[-1]['episodes'])} seeded episodes (95 % CI)")
            ax.fill_between(steps, [r["low"] for r in rows], [r["high"] for r in rows], color="tab:blue", alpha=0.2)
        ax.plot(steps, [r["train_success"] for r in rows], "--", color="tab:orange",
                label="training episodes (exploring)")
    ax.set_xlabel("environment steps [millions]")
    ax.set_ylabel("episodes with a goal")
    ax.set_ylim(-0.02, 1.02)
    ax.grid(alpha=0.3)
    ax.legend(loc="lower right", fontsize=8)
    ax.set_title(title, fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


# --- training ---------------------------------------------------------------------------------------------
def train(options: TrainOptions) -> Path:
    """Train as ``options`` say; the run folder."""
    the_task = options.check()
    out = Path(options.out) if options.out else \
        Path("runs") / f"{options.task}-{datetime.now().strftime('%Y%m%d-%H%M%S')}"
    run = RunFolder(out)
    rows = run.prepare(options, the_task)
    # the learning libraries load only now: a bad option is answered without them
    import torch
    from stable_baselines3 import PPO
    from stable_baselines3.common.callbacks import BaseCallback
    from stable_baselines3.common.utils import set_random_seed
    from tqdm import tqdm

    torch.set_num_threads(1)  # the workers have the cores; one thread also makes the updates repeatable
    set_random_seed(options.seed)
    env = the_task.make_vec(options.workers, options.seed)
    seeds = list(range(EVAL_SEEDS, EVAL_SEEDS + options.eval_episodes))
    meta = {"algorithm": options.algorithm, "seed": options.seed, "run": str(out.resolve())}

    class Report(BaseCallback):
        """The progress bar; at each checkpoint the learner, its policy file and a point of the curve."""

        def __init__(self, start: int) -> None:
            super().__init__()
            self.start, self.next_checkpoint = start, (start // options.checkpoint_every + 1) * options.checkpoint_every
            self.scored = self.episodes = 0
            self.goal_seen = np.zeros(env.num_envs, dtype=bool)  # per environment: a goal in its episode so far
            self.wall = time.monotonic() - (rows[-1]["wall_seconds"] if rows else 0.0)
            self.bar = tqdm(total=options.steps, initial=start, unit="step", unit_scale=True, file=sys.stderr,
                            dynamic_ncols=True, mininterval=2.0, desc=f"train {options.task}")

        def _on_step(self) -> bool:
            for k, (done, info) in enumerate(zip(self.locals["dones"], self.locals["infos"])):
                self.goal_seen[k] |= episode_success(info)
                if done:
                    self.episodes += 1
                    self.scored += bool(self.goal_seen[k])
                    self.goal_seen[k] = False
            self.bar.update(self.model.num_timesteps - self.bar.n)
            if self.model.num_timesteps >= self.next_checkpoint:
                self.checkpoint()
                self.next_checkpoint += options.checkpoint_every
            return True

        def checkpoint(self) -> None:
            steps = int(self.model.num_timesteps)
            self.model.save(run.checkpoints / f"{options.algorithm}_{steps}.zip")
            net = export_policy(self.model, the_task, {**meta, "trained_steps": steps})
            net.save(run.policies / f"policy_{steps}.npz")
            row = {"steps": float(steps), "success": float("nan"), "low": float("nan"), "high": float("nan"),
                   "episodes": float(len(seeds)),
                   "train_success": self.scored / self.episodes if self.episodes else float("nan"),
                   "train_episodes": float(self.episodes), "wall_seconds": time.monotonic() - self.wall}
            if seeds:
                from nubot_match.learn.episodes import success

                played = play(the_task, player(str(run.policies / f"policy_{steps}.npz"), the_task), seeds) \
                    if isinstance(the_task, Task) else play_team(the_task, net, seeds)
                rate = success(played)
                row.update(success=rate.mean, low=rate.low, high=rate.high)
                self.logger.record("eval/success_rate", rate.mean)
            self.logger.record("rollout/train_success_rate", row["train_success"])
            rows[:] = [r for r in rows if r["steps"] < steps] + [row]
            run.write_curve(rows)
            self.bar.write(f"  {steps:>9,} steps: policy file scores in {row['success']:.0%} of {len(seeds)} seeded "
                           f"episodes; training episodes since the last checkpoint {row['train_success']:.0%} "
                           f"of {self.episodes}")
            self.scored = self.episodes = 0

    tensorboard = str(out / "tensorboard")
    latest = run.latest_checkpoint() if options.resume else None
    if latest is not None:
        model = PPO.load(latest[0], env=env, tensorboard_log=tensorboard, device="cpu")
        start = latest[1]
        rows[:] = [r for r in rows if r["steps"] <= start]
    else:
        model = PPO("MlpPolicy", env, seed=options.seed, verbose=0, tensorboard_log=tensorboard, device="cpu",
                    **PPO_OPTIONS)
        start = 0
    report = Report(start)
    began = time.monotonic()
    try:
        if options.steps > start:
            model.learn(options.steps - start, callback=report, reset_num_timesteps=latest is None,
                        tb_log_name=options.algorithm)
        if not rows or rows[-1]["steps"] < model.num_timesteps:
            report.checkpoint()
    finally:
        report.bar.close()
        env.close()
    steps_done = int(model.num_timesteps) - start
    seconds = time.monotonic() - began
    final = run.policies / f"policy_{int(model.num_timesteps)}.npz"
    (out / "policy.npz").write_bytes(final.read_bytes())
    run.write_manifest({"finished": datetime.now().isoformat(timespec="seconds"), "steps": int(model.num_timesteps),
                        "this_session": {"steps": steps_done, "seconds": round(seconds, 1),
                                         "steps_per_second": round(steps_done / seconds, 1) if seconds else None}})
    return out


def main(argv: list[str] | None = None) -> int:
    defaults = TrainOptions()
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--task", default=defaults.task, help=f"one of: {', '.join(sorted(TASKS))}")
    parser.add_argument("--algorithm", default=defaults.algorithm, help=f"one of: {', '.join(ALGORITHMS)}")
    parser.add_argument("--steps", type=int, default=defaults.steps, help="environment steps to train in all")
    parser.add_argument("--workers", type=int, default=defaults.workers, help="environment processes (default: two "
                        "per core)")
    parser.add_argument("--seed", type=int, default=defaults.seed)
    parser.add_argument("--out", default="", help="the run folder (default runs/<task>-<time>)")
    parser.add_argument("--resume", action="store_true", help="go on from the last checkpoint in --out")
    parser.add_argument("--checkpoint-every", type=int, default=defaults.checkpoint_every, help="[steps]")
    parser.add_argument("--eval-episodes", type=int, default=defaults.eval_episodes,
                        help="seeded episodes that score each checkpoint's policy file (0: none)")
    args = parser.parse_args(argv)
    options = replace(defaults, **vars(args))
    try:
        out = train(options)
    except NubotMatchError as exc:
        print(f"train: {exc}", file=sys.stderr)
        return 2
    manifest = json.loads((out / "run.json").read_text())
    rate = manifest["this_session"]["steps_per_second"]
    play = f"play it: make match POLICY={out / 'policy.npz'}" if isinstance(task(options.task), Task) else \
        "it plays in the PettingZoo environment (nubot_match.learn.episodes.play_team)"
    print(f"train: {manifest['steps']:,} steps ({rate} steps/s); the policy file {out / 'policy.npz'}, the learning "
          f"curve {out / 'learning_curve.png'}; {play}", flush=True)
    return 0
