"""Benchmark full matches: 5 vs 5 over ROS at real time, and statistics over seeded short matches.

For each tracker of the motion layer (mpc, then baseline) and each seed it runs ``run_match.py``
(the whole stack: simulator, 10 robots' world model and nubot_control, one node each, two relays, the
automatic referee, rosbag) with performance monitoring, then reads the match report. Writes
``<out>/match.json`` with, per match, the achieved real-time factor, the control loops' rates and
missed cycles, CPU (cores, per node kind) and memory, goals, passes, running share, robot-robot
collisions and the time to reach a free ball; and their means per tracker over the seeds (the
same seeds for both trackers: the effect of the motion layer on play).
"""

from __future__ import annotations

import argparse
import json
import re
import statistics
import subprocess
import sys
from pathlib import Path

import rosbag

from nubot_common.json_text import strict_json
from nubot_tools.workspace import BENCH_RESULTS

PLAY = ("goals", "passes_completed", "passes_tried", "shots", "running_share", "collisions_per_minute",
        "collisions", "ball_reach_median_s", "ball_reach_mean_s")
PERFORMANCE = ("achieved_real_time_factor", "control_rate_min_hz", "missed_cycle_share", "cpu_cores_total",
               "cpu_core_seconds_per_sim_second", "rss_mib_total")
TRAFFIC = ("messages_per_second", "deliveries_per_second")


def play_match(tracker: str, seed: int, half_seconds: float, out: Path, extra: tuple[str, ...] = (),
               label: str = "") -> dict:
    """One half of a match with ``run_match.py`` (``extra`` arguments added), its figures and report's."""
    perf_file = out / f"match_perf_{label or tracker}_seed{seed}.json"
    folder = out / "matches"
    status = subprocess.run([sys.executable, "-m", "nubot_tools.ros.match_runner", "--half-seconds",
                             str(half_seconds), "--halves", "1", "--seed", str(seed), "--out", str(folder),
                             "--tracker", tracker, "--perf-json", str(perf_file), *extra]).returncode
    latest = max(folder.iterdir(), key=lambda p: p.stat().st_mtime)
    report = json.loads((latest / "report.json").read_text())
    perf = json.loads(perf_file.read_text())
    perf["messages"] = message_traffic(latest / "match.bag", perf.pop("subscribers", {}))
    return {
        "tracker": tracker, "seed": seed, "status": status, "folder": str(latest), "performance": perf,
        "goals": sum(report["score"].values()),
        "passes_completed": sum(t["completed"] for t in report["passes"].values()),
        "passes_tried": sum(t["tried"] for t in report["passes"].values()),
        "shots": sum(report["shots"].values()),
        "running_share": round(report["running_time_s"] / report["duration_s"], 3),
        "collisions": report["collisions"]["total"],
        "collisions_per_minute": report["collisions"]["per_minute"],
        "ball_reach_median_s": report["ball_reach"]["median_s"],
        "ball_reach_mean_s": report["ball_reach"]["mean_s"],
    }


def message_traffic(bag_path: Path, subscribers: dict[str, int]) -> dict:
    """Messages per second (from the bag's index) and deliveries per second (each message times the nodes that
    subscribe to its topic, the recorder included), the ten largest streams with robot and team names folded."""
    with rosbag.Bag(str(bag_path)) as bag:
        seconds = max(bag.get_end_time() - bag.get_start_time(), 1e-9)
        counts = {topic: info.message_count for topic, info in bag.get_type_and_topic_info().topics.items()}
    streams: dict[str, dict[str, float]] = {}
    for topic, count in counts.items():
        kind = re.sub(r"^/(nubot|rival)\d+/", "/<robot>/", topic)
        kind = re.sub(r"^/(nubot|rival)/", "/<team>/", kind)
        stream = streams.setdefault(kind, {"messages_per_second": 0.0, "deliveries_per_second": 0.0})
        stream["messages_per_second"] += count / seconds
        stream["deliveries_per_second"] += count / seconds * subscribers.get(topic, 0)
    top = sorted(streams.items(), key=lambda kv: -kv[1]["deliveries_per_second"])[:10]
    return {"seconds": round(seconds, 1),
            "messages_per_second": round(sum(s["messages_per_second"] for s in streams.values()), 1),
            "deliveries_per_second": round(sum(s["deliveries_per_second"] for s in streams.values()), 1),
            "largest": {k: {n: round(v, 1) for n, v in s.items()} for k, s in top}}


def mean_of(matches: list[dict], key: str, performance: bool = False) -> float | None:
    values = [m["performance"][key] if performance else m[key] for m in matches]
    values = [v for v in values if v is not None]
    return round(statistics.mean(values), 3) if values else None


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--half-seconds", type=float, default=60.0)
    parser.add_argument("--trackers", nargs="+", choices=("mpc", "baseline"), default=["mpc", "baseline"])
    args = parser.parse_args(argv)
    args.out.mkdir(parents=True, exist_ok=True)
    by_tracker = {}
    for tracker in args.trackers:
        matches = []
        for seed in args.seeds:
            print(f"[bench] match with the {tracker} tracker, seed {seed}: 1 x {args.half_seconds:.0f} s at real "
                  "time", flush=True)
            matches.append(play_match(tracker, seed, args.half_seconds, args.out))
        summary = {k: mean_of(matches, k) for k in PLAY}
        summary.update({k: mean_of(matches, k, performance=True) for k in PERFORMANCE})
        summary.update({k: round(statistics.mean(m["performance"]["messages"][k] for m in matches), 1)
                        for k in TRAFFIC})
        by_tracker[tracker] = {"matches": matches, "mean": summary}
        print(f"[bench] {tracker}: {json.dumps(summary)}", flush=True)
    result = {"half_seconds": args.half_seconds, "seeds": args.seeds, "by_tracker": by_tracker}
    (args.out / "match.json").write_text(strict_json(result, indent=2))
    print(f"figures: {args.out / 'match.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
