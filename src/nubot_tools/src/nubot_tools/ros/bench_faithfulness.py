"""Benchmark the lockstep engine's faithfulness: the same seeded matches in lockstep and over ROS, compared.

    python scripts/bench_faithfulness.py [--seeds 4] [--half-seconds 90] [--out bench/results] [--quick]
                                         [--real-time-factor 1] [--skip-ros | --skip-lockstep]

Requires: the shipped teams (nubot against rival, the configured tracker, the 18 x 12 m field); for the ROS
part the whole stack (``scripts/run_match.py``: roscore, simulator, 20 nodes, referee, rosbag, at real
time: about 2 x ``--half-seconds`` plus stoppages and start-up per seed, on every core). For seeds
0..N-1 it plays a lockstep match (``nubot_match``: ``match_config(..., half_seconds=H, halves=2,
seed=s)``, ``MatchLogRecorder``, ``nubot_match.match_analysis.analyse``) and a ROS match
(``run_match.py --half-seconds H --halves 2 --seed s``, its ``report.json``), and compares per match:

- goals per minute of running time (both teams);
- shots per minute of running time (both teams, ``match_shots``);
- passes completed (both teams), and their share of the passes tried;
- possession share of the home team (nubot) of running time;
- robot-robot collisions per minute of running time;
- fouls per minute of running time (both teams, ``match_analysis.FOUL_KINDS``);
- the share of the match the ball is in play (running time over running and stopped time within the halves).

Provides: ``<out>/faithfulness.json`` (per metric the mean and 95 % Student-t interval,
``nubot_match.statistics.mean_interval``, for lockstep and ROS and whether the two intervals overlap; for the
figures per minute (goals, shots, collisions, fouls) the interval is at least as wide as the exact Poisson one
of all the matches' events in all their running time, ``rate_interval``: four matches with a goal each have the
same rate, and a t interval of zero width would call any other count apart; every
match's figures; ROS matches cut short are listed but left out of the intervals; the share of the ROS robots'
control cycles missed, ``run_match.py --perf-json``: a busy machine's cycles come late or not at all, which
lockstep never has) and
``<out>/faithfulness.png`` (per metric both means with their intervals). The ROS matches' folders are kept
in ``<out>/faithfulness/ros/seed-<s>/``. Not part of ``make bench``: run
``make bench-faithfulness SEEDS=4 HALF_SECONDS=90``.
"""

from __future__ import annotations

import argparse
import json
import math
import subprocess
import sys
import time
from dataclasses import asdict
from pathlib import Path
from typing import TYPE_CHECKING

import matplotlib.pyplot as plt

from nubot_common.json_text import strict_json
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_match.match_analysis import FOUL_KINDS, analyse
from nubot_match.match_shots import explain
from nubot_match.record import MatchLogRecorder
from nubot_match.statistics import Interval, mean_interval, rate_interval
from nubot_tools.workspace import BENCH_RESULTS

if TYPE_CHECKING:
    from nubot_match.statistics import Interval

METRICS = {"goals_per_minute": "goals per minute of running time",
           "shots_per_minute": "shots per minute of running time",
           "passes_completed": "passes completed per match",
           "pass_completion": "share of passes completed",
           "possession_share": "home team's possession share",
           "collisions_per_minute": "robot-robot collisions per minute",
           "fouls_per_minute": "fouls per minute of running time",
           "running_share": "share of the match in play"}
# The figures per minute of running time, with the count behind each (see compare).
RATES = {"goals_per_minute": "goals", "shots_per_minute": "shots", "collisions_per_minute": "collisions",
         "fouls_per_minute": "fouls"}
HOME_TEAM = "nubot"  # the first team of run_match.py and of match_config, kicking off at -x
QUICK_SEEDS, QUICK_HALF_SECONDS = 2, 10.0


def figures(report: dict, home: str = HOME_TEAM) -> dict[str, float]:
    """The compared metrics of one match from its report (``MatchSummary.to_json()`` with the ``ShotReport`` under
    "shot_report", or a match_report's report.json)."""
    minutes = report["running_time_s"] / 60.0

    def per_minute(n: float) -> float:
        return round(n / minutes, 4) if minutes > 0 else 0.0

    goals = sum(report["score"].values())
    shots = sum(c["shots"] for c in report["shot_report"]["counts"].values())
    tried = sum(p["tried"] for p in report["passes"].values())
    completed = sum(p["completed"] for p in report["passes"].values())
    fouls = sum(n for team in report["fouls"].values() for kind, n in team.items() if kind in FOUL_KINDS)
    played = report["running_time_s"] + report.get("stopped_time_s", 0.0)
    return {"goals_per_minute": per_minute(goals), "shots_per_minute": per_minute(shots),
            "passes_completed": float(completed), "pass_completion": round(completed / tried, 4) if tried else 0.0,
            "possession_share": float(report["possession"].get(home, {}).get("share", 0.0)),
            "collisions_per_minute": float(report["collisions"]["per_minute"]),
            "fouls_per_minute": per_minute(fouls),
            "running_share": round(report["running_time_s"] / played, 4) if played > 0 else 0.0,
            "running_time_s": float(report["running_time_s"]), "goals": float(goals), "shots": float(shots),
            "collisions": float(report["collisions"]["total"]), "fouls": float(fouls)}


def play_lockstep(seed: int, half_seconds: float) -> dict:
    config = match_config(half_seconds=half_seconds, halves=2, seed=seed)
    recorder = MatchLogRecorder()
    match = LockstepMatch(config, [recorder])
    match.reset(seed)
    start = time.perf_counter()
    match.run()
    wall = time.perf_counter() - start
    home = config.teams[0].config
    log = recorder.finish()
    summary = analyse(log, config.world, (home.prefix, home.attack))
    report = {**summary.to_json(), "shot_report": explain(summary, log).to_json()}
    return {"seed": seed, "sim_seconds": round(match.time, 2), "wall_seconds": round(wall, 2),
            **figures(report, home.prefix)}


def new_report(folder: Path, earlier: set[Path]) -> Path | None:
    """The newest ``match-*/report.json`` in ``folder`` that is not one of ``earlier`` (None: the run made none; a
    report an earlier run left there is never taken for this one's)."""
    made = [p for p in folder.glob("match-*/report.json") if p not in earlier]
    return max(made, key=lambda p: p.stat().st_mtime) if made else None


def play_ros(seed: int, half_seconds: float, folder: Path, real_time_factor: float = 1.0) -> dict:
    folder.mkdir(parents=True, exist_ok=True)
    earlier = set(folder.glob("match-*/report.json"))  # an earlier run's, kept in the seed's folder
    start = time.monotonic()
    perf_file = folder / f"perf-{time.strftime('%Y%m%d-%H%M%S')}.json"
    status = subprocess.run([sys.executable, "-m", "nubot_tools.ros.match_runner", "--half-seconds",
                             str(half_seconds), "--halves", "2", "--seed", str(seed), "--out", str(folder),
                             "--perf-json", str(perf_file), "--real-time-factor", str(real_time_factor)],
                            check=False).returncode
    wall = time.monotonic() - start
    made = new_report(folder, earlier)
    if made is None:
        raise RuntimeError(f"the ROS match of seed {seed} left no report in {folder} (status {status})")
    report = json.loads(made.read_text())
    run_file = made.parent / "run.json"
    run = json.loads(run_file.read_text()) if run_file.exists() else {}
    perf = json.loads(perf_file.read_text()) if perf_file.exists() else {}
    return {"seed": seed, "status": status, "ended": run.get("ended", "unknown"), "folder": str(made.parent),
            "sim_seconds": run.get("sim_time"), "wall_seconds": round(wall, 1),
            "missed_cycle_share": perf.get("missed_cycle_share"),
            "real_time_factor": perf.get("achieved_real_time_factor"), **figures(report)}


def _plain(x: float) -> float | None:
    return None if math.isnan(x) else round(x, 4)


def compare(lockstep: list[dict], ros: list[dict]) -> dict:
    """Per metric: mean and 95 % interval of each kind of match and whether the two intervals overlap."""
    out = {}
    for metric, words in METRICS.items():
        a, b = interval(lockstep, metric), interval(ros, metric)
        known = not any(math.isnan(x) for x in (a.low, a.high, b.low, b.high))
        out[metric] = {"description": words,
                       "lockstep": {k: _plain(v) for k, v in asdict(a).items()},
                       "ros": {k: _plain(v) for k, v in asdict(b).items()},
                       "intervals_overlap": (a.low <= b.high and b.low <= a.high) if known else None}
    return out


def interval(matches: list[dict], metric: str) -> Interval:
    """The mean of ``metric`` over ``matches`` with its 95 % interval: Student t over the matches; a figure per
    minute takes in the exact Poisson interval of the matches' pooled count as well (the wider bounds of the two)."""
    t = mean_interval([m[metric] for m in matches])
    count = RATES.get(metric)
    minutes = sum(m["running_time_s"] for m in matches) / 60.0
    if count is None or not minutes > 0.0:
        return t
    pooled = rate_interval(round(sum(m[count] for m in matches)), minutes)
    low = pooled.low if math.isnan(t.low) else max(0.0, min(t.low, pooled.low))  # a rate is never below 0
    high = pooled.high if math.isnan(t.high) else max(t.high, pooled.high)
    return Interval(t.mean, low, high)


def plot(comparison: dict, path: Path, title: str) -> None:
    fig, axes = plt.subplots(1, len(comparison), figsize=(3.2 * len(comparison), 3.8))
    for ax, row in zip(axes, comparison.values()):
        for x, kind, colour in ((0, "lockstep", "tab:blue"), (1, "ros", "tab:orange")):
            mean, low, high = (row[kind][k] for k in ("mean", "low", "high"))
            if mean is None:
                continue
            err = [[mean - low], [high - mean]] if low is not None and high is not None else None
            ax.errorbar([x], [mean], yerr=err, fmt="o", color=colour, capsize=6)
        ax.set_xticks([0, 1], ["lockstep", "ROS"])
        ax.set_xlim(-0.6, 1.6)
        overlap = row["intervals_overlap"]
        ax.set_title(f"{row['description']}\n" + ("" if overlap is None else
                                                  "intervals overlap" if overlap else "intervals apart"), fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seeds", type=int, default=4, help="seeds 0..N-1, one match of each kind per seed")
    parser.add_argument("--half-seconds", type=float, default=90.0, help="[s of game time]; two halves")
    parser.add_argument("--quick", action="store_true",
                        help=f"{QUICK_SEEDS} seeds of 2 x {QUICK_HALF_SECONDS:g} s (a smoke run)")
    parser.add_argument("--real-time-factor", type=float, default=1.0,
                        help="the ROS matches' pace (below 1 on a machine too busy to run them at real time)")
    skip = parser.add_mutually_exclusive_group()
    skip.add_argument("--skip-ros", action="store_true", help="lockstep matches only")
    skip.add_argument("--skip-lockstep", action="store_true", help="ROS matches only")
    args = parser.parse_args(argv)
    seeds, half = (QUICK_SEEDS, QUICK_HALF_SECONDS) if args.quick else (args.seeds, args.half_seconds)
    if seeds < 1 or not half > 0 or not args.real_time_factor > 0:
        parser.error("--seeds must be at least 1, --half-seconds and --real-time-factor positive")
    args.out.mkdir(parents=True, exist_ok=True)
    lockstep: list[dict] = []
    ros: list[dict] = []
    for seed in range(seeds):
        if not args.skip_lockstep:
            print(f"[bench] faithfulness: lockstep match, seed {seed}, 2 x {half:g} s ...", flush=True)
            lockstep.append(play_lockstep(seed, half))
        if not args.skip_ros:
            print(f"[bench] faithfulness: ROS match, seed {seed}, 2 x {half:g} s at {args.real_time_factor:g} x real "
                  "time ...", flush=True)
            ros.append(play_ros(seed, half, args.out / "faithfulness" / "ros" / f"seed-{seed}", args.real_time_factor))
    complete = [m for m in ros if m["ended"] != "cut short"]  # a match cut short has other running time
    comparison = compare(lockstep, complete)
    result = {"seeds": list(range(seeds)), "half_seconds": half, "halves": 2, "quick": args.quick,
              "real_time_factor": args.real_time_factor,
              "confidence": 0.95,
              "interval": "Student t over the per-match values; per minute also the exact Poisson interval of the "
                          "pooled count, the wider bounds (nubot_match.statistics)",
              "comparison": comparison, "lockstep_matches": lockstep, "ros_matches": ros,
              "ros_seeds_cut_short": [m["seed"] for m in ros if m["ended"] == "cut short"]}
    timing = [m for m in complete if m.get("missed_cycle_share") is not None]
    if timing:  # lockstep misses none: each robot's cycle comes at its time
        result["ros_missed_cycle_share"] = round(sum(m["missed_cycle_share"] for m in timing) / len(timing), 4)
    (args.out / "faithfulness.json").write_text(strict_json(result, indent=2))
    plot(comparison, args.out / "faithfulness.png",
         f"lockstep ({len(lockstep)}) vs ROS ({len(complete)}) matches of 2 x {half:g} s, mean and 95 % CI")
    for row in comparison.values():
        print(f"{row['description']:<40} lockstep {row['lockstep']['mean']}  ROS {row['ros']['mean']}  "
              f"overlap: {row['intervals_overlap']}")
    if timing:
        print(f"ROS robots' control cycles missed: {100 * result['ros_missed_cycle_share']:.1f} % (lockstep: none), "
              f"real-time factor {min(m['real_time_factor'] for m in timing)}-"
              f"{max(m['real_time_factor'] for m in timing)}")
    print(f"figures: {args.out / 'faithfulness.json'}, {args.out / 'faithfulness.png'}")
    return 0
