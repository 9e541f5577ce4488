"""How fast a robot trains, and how well a trained one scores (make bench; a run of make train).

    python scripts/bench_train.py [--out bench/results] [--workers 1,2,4] [--steps 16384]
                                  [--run runs/score-<time> [--episodes 200]]

Requires: make train's libraries (scripts/setup_train.sh). Measures, for each worker count, environment steps
per second of the score task's environments alone (Stable-Baselines3's vectorized environment stepping random
actions: one process per worker, or in this process for one) and of PPO training (the same environments with
the learner choosing the actions and updating, as ``make train`` runs it), after the workers started.
With ``--run``: that run's learning curve (``curve.csv``) and its training budget (steps, wall time), and its
policy file against the scripted striker over ``--episodes`` paired seeded episodes (``learn.compare``).
Provides: ``<out>/train.json`` and ``<out>/train_speed.png`` (and with ``--run``, ``<out>/learning_curve.png``).
"""

from __future__ import annotations

import argparse
import csv
import json
import os
import shutil
import sys
import tempfile
import time
from dataclasses import asdict
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import numpy as np

from nubot_common.json_text import strict_json
from nubot_match.learn.compare import summary
from nubot_match.learn.episodes import SCRIPTED, play_parallel
from nubot_match.learn.tasks import single_task
from nubot_match.learn.trainer import TrainOptions, train
from nubot_tools.workspace import BENCH_RESULTS


def environment_rate(workers: int, steps: int) -> float:
    """Steps per second of ``workers`` score environments stepping random actions (SB3's vectorized env)."""
    from stable_baselines3.common.env_util import make_vec_env
    from stable_baselines3.common.vec_env import DummyVecEnv, SubprocVecEnv

    the_task = single_task("score")
    vec_cls = SubprocVecEnv if workers > 1 else DummyVecEnv
    env = make_vec_env(the_task.make, n_envs=workers, seed=0, vec_env_cls=vec_cls,
                       vec_env_kwargs={"start_method": "forkserver"} if workers > 1 else None)
    try:
        env.reset()
        rng = np.random.default_rng(0)
        actions = rng.uniform(-1.0, 1.0, size=(steps // workers, workers, 5)).astype(np.float32)
        start = time.perf_counter()
        for action in actions:
            env.step(action)
        return len(actions) * workers / (time.perf_counter() - start)
    finally:
        env.close()


def training_rate(workers: int, steps: int) -> float:
    """Steps per second of ``make train`` (PPO) with ``workers`` environment processes."""
    with tempfile.TemporaryDirectory() as folder:
        out = Path(folder) / "run"
        train(TrainOptions(steps=steps, workers=workers, out=str(out), checkpoint_every=10 * steps, eval_episodes=0))
        return float(json.loads((out / "run.json").read_text())["this_session"]["steps_per_second"])


def run_figures(run: Path, episodes: int, jobs: int, out: Path) -> dict[str, Any]:
    manifest = json.loads((run / "run.json").read_text())
    with open(run / "curve.csv", newline="") as handle:
        curve = [{k: float(v) for k, v in row.items()} for row in csv.DictReader(handle)]
    shutil.copyfile(run / "learning_curve.png", out / "learning_curve.png")
    policy = str(run / "policy.npz")
    seeds = list(range(episodes))
    print(f"bench_train: {policy} and the scripted striker, {episodes} seeded episodes each", flush=True)
    played = {name: play_parallel("score", name, seeds, jobs) for name in (policy, SCRIPTED)}
    rates = summary(played)
    gap = [float(a.scored) - float(b.scored) for a, b in zip(played[policy], played[SCRIPTED])]
    return {"run": str(run), "steps": manifest.get("steps"), "options": manifest.get("options"),
            "wall_seconds": curve[-1]["wall_seconds"] if curve else None, "versions": manifest.get("versions"),
            "curve": curve, "episodes": episodes,
            "policy": {k: asdict(v) for k, v in rates[policy].items()},
            "scripted": {k: asdict(v) for k, v in rates[SCRIPTED].items()},
            "success_difference_mean": float(np.mean(gap))}


def plot_speed(rates: dict[str, dict[int, float]], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    workers = sorted(next(iter(rates.values())))
    width = 0.38
    for k, (label, by_workers) in enumerate(rates.items()):
        xs = np.arange(len(workers)) + (k - 0.5) * width
        ax.bar(xs, [by_workers[w] for w in workers], width, label=label)
        for x, w in zip(xs, workers):
            ax.text(x, by_workers[w], f"{by_workers[w]:.0f}", ha="center", va="bottom", fontsize=8)
    ax.set_xticks(np.arange(len(workers)), [f"{w} worker{'s' if w > 1 else ''}" for w in workers])
    ax.set_ylabel("environment steps per second")
    ax.set_title(f"score task on {os.cpu_count()} cores (one step: 35 ms of play)", fontsize=9)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--workers", default="1,2,4", help="worker counts to measure")
    parser.add_argument("--steps", type=int, default=16384, help="steps per measurement")
    parser.add_argument("--run", type=Path, help="a make train run folder: its curve, and its policy against the "
                        "scripted striker")
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args(argv)
    workers = [int(w) for w in args.workers.split(",")]
    args.out.mkdir(parents=True, exist_ok=True)
    rates: dict[str, dict[int, float]] = {"environments alone": {}, "training (PPO)": {}}
    for n in workers:
        rates["environments alone"][n] = environment_rate(n, args.steps)
        rates["training (PPO)"][n] = training_rate(n, args.steps)
        print(f"bench_train: {n} workers: environments {rates['environments alone'][n]:.0f} steps/s, training "
              f"{rates['training (PPO)'][n]:.0f} steps/s", flush=True)
    plot_speed(rates, args.out / "train_speed.png")
    result: dict[str, Any] = {"cores": os.cpu_count(), "steps_per_measurement": args.steps,
                              "steps_per_second": {k: {str(w): round(v, 1) for w, v in r.items()}
                                                   for k, r in rates.items()}}
    if args.run is not None:
        result["trained"] = run_figures(args.run, args.episodes, args.jobs, args.out)
        policy, scripted = result["trained"]["policy"]["success"], result["trained"]["scripted"]["success"]
        print(f"bench_train: episodes with a goal: policy {policy['mean']:.2f} [{policy['low']:.2f}, "
              f"{policy['high']:.2f}], scripted striker {scripted['mean']:.2f} [{scripted['low']:.2f}, "
              f"{scripted['high']:.2f}]", flush=True)
    (args.out / "train.json").write_text(strict_json(result, indent=2) + "\n")
    print(f"bench_train: {args.out / 'train.json'}", file=sys.stderr, flush=True)
    return 0
