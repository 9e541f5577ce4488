"""A trained policy file against the scripted striker on the same task and the same seeded episodes
(``make evaluate POLICY=<file> [TASK=score] [EPISODES=200]``).

    python scripts/evaluate.py --policy runs/score-.../policy.npz [--task score] [--episodes 200] [--seed 0]
                               [--jobs N] [--out DIR]

Requires: a policy file trained on the task (``nubot_common.policy``, written by ``make train``); numpy only, no
learning library. Provides, in ``--out`` (default ``evaluations/<task>-<time>/``): ``results.json`` (the options,
every episode of both players: seed, scored, return, steps, how it ended; the summary), ``table.md`` and
``success.png``. Episode k of both players starts from the same seeded start (seed ``--seed + k``), so the
comparison is paired: the table gives each player's share of episodes with a goal (Wilson 95 % interval), its
mean return (Student t 95 %), and the mean per-episode difference (policy minus scripted) with its paired t
interval. A progress bar on stderr; exit status 0, or 2 with a clear message for bad options.
"""

from __future__ import annotations

import argparse
import os
import sys
from dataclasses import asdict
from datetime import datetime
from pathlib import Path

from nubot_common.json_text import strict_json
from nubot_match import NubotMatchError
from nubot_match.learn.episodes import SCRIPTED, Episode, play_parallel, player, success
from nubot_match.learn.tasks import TASKS, single_task
from nubot_match.statistics import Interval, mean_interval


def summary(episodes: dict[str, list[Episode]]) -> dict[str, dict[str, Interval]]:
    out = {}
    for name, eps in episodes.items():
        out[name] = {"success": success(eps), "return": mean_interval([e.reward for e in eps]),
                     "steps_to_goal": mean_interval([e.steps for e in eps if e.scored])}
    return out


def table(names: dict[str, str], episodes: dict[str, list[Episode]], task_name: str) -> str:
    s = summary(episodes)
    lines = [f"| {task_name}: {len(next(iter(episodes.values())))} seeded episodes | episodes with a goal (95 % CI) "
             "| mean return (95 % CI) | steps to the goal (35 ms each) |", "| --- | --- | --- | --- |"]
    for key, label in names.items():
        row = s[key]
        lines.append(f"| {label} | {row['success'].text()} | {row['return'].text(3)} | "
                     f"{row['steps_to_goal'].text(0)} |")
    keys = list(names)
    if len(keys) == 2:
        a, b = (episodes[k] for k in keys)
        goal_gap = mean_interval([float(x.scored) - float(y.scored) for x, y in zip(a, b)])
        return_gap = mean_interval([x.reward - y.reward for x, y in zip(a, b)])
        lines.append(f"| difference (paired by seed) | {goal_gap.text()} | {return_gap.text(3)} | |")
    return "\n".join(lines) + "\n"


def plot(names: dict[str, str], episodes: dict[str, list[Episode]], path: Path) -> None:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    s = summary(episodes)
    fig, ax = plt.subplots(figsize=(5, 3.2))
    for k, key in enumerate(names):
        rate = s[key]["success"]
        ax.bar(k, rate.mean, color=("tab:blue", "tab:gray")[k % 2])
        ax.errorbar(k, rate.mean, yerr=[[rate.mean - rate.low], [rate.high - rate.mean]], color="black", capsize=6)
        ax.text(k, rate.high + 0.02, f"{rate.mean:.0%}", ha="center")
    ax.set_xticks(range(len(names)), [label for label in names.values()], fontsize=8)
    ax.set_ylabel("episodes with a goal (95 % CI)")
    ax.set_ylim(0, 1.1)
    ax.set_title(f"{len(next(iter(episodes.values())))} seeded episodes each", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--policy", required=True, help="a policy file written by make train (policy.npz)")
    parser.add_argument("--task", default="score", help=f"one of: {', '.join(sorted(TASKS))}")
    parser.add_argument("--episodes", type=int, default=200)
    parser.add_argument("--seed", type=int, default=0, help="seed of the first episode")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1, help="worker processes")
    parser.add_argument("--out", type=Path, help="folder of the results (default evaluations/<task>-<time>)")
    args = parser.parse_args(argv)
    try:
        the_task = single_task(args.task)
        if args.episodes < 1 or args.jobs < 1:
            raise NubotMatchError(f"--episodes and --jobs must be at least 1, got {args.episodes} and {args.jobs}")
        policy = str(Path(args.policy).expanduser())
        player(policy, the_task)  # a missing or foreign file is refused before any episode
    except NubotMatchError as exc:
        print(f"evaluate: {exc}", file=sys.stderr)
        return 2
    out = args.out or Path("evaluations") / f"{args.task}-{datetime.now().strftime('%Y%m%d-%H%M%S')}"
    out.mkdir(parents=True, exist_ok=True)
    seeds = list(range(args.seed, args.seed + args.episodes))
    names = {policy: f"policy {Path(policy).name}", SCRIPTED: "scripted striker"}
    print(f"evaluate: {names[policy]} against the scripted striker on {args.task} ({the_task.summary}), "
          f"{args.episodes} episodes each, seeds {seeds[0]}..{seeds[-1]}, {args.jobs} workers; results in {out}",
          flush=True)
    from tqdm import tqdm

    episodes: dict[str, list[Episode]] = {}
    with tqdm(total=2 * len(seeds), unit="episode", file=sys.stderr, dynamic_ncols=True, mininterval=1.0) as bar:
        for name in names:
            episodes[name] = play_parallel(args.task, name, seeds, args.jobs, bar.update)
    text = table(names, episodes, args.task)
    s = summary(episodes)
    (out / "table.md").write_text(text)
    (out / "results.json").write_text(strict_json({
        "options": {k: str(v) if isinstance(v, Path) else v for k, v in vars(args).items()},
        "env_id": the_task.env_id, "players": names,
        "summary": {names[k]: {m: asdict(v) for m, v in row.items()} for k, row in s.items()},
        "episodes": {names[k]: [asdict(e) for e in eps] for k, eps in episodes.items()}}, indent=2) + "\n")
    plot(names, episodes, out / "success.png")
    print(text, end="", flush=True)
    return 0
