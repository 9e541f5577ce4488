#!/usr/bin/env python3
"""Benchmark full matches: 5 vs 5 over ROS at real time, and statistics over seeded short matches.

For each seed it runs ``run_match.py`` (the whole stack: simulator, 10 robots' world_model and
nubot_control, two relays, the automatic referee, rosbag) with performance monitoring, then
reads the match report. Writes ``<out>/match.json`` with, per match, the achieved real-time
factor, the control loops' rates and missed cycles, CPU (cores, per node kind) and memory,
and goals, passes and running share; and their means over the seeds.
"""

from __future__ import annotations

import argparse
import json
import statistics
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=ROOT / "bench" / "results")
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2, 3])
    parser.add_argument("--half-seconds", type=float, default=60.0)
    args = parser.parse_args(argv)
    matches = []
    for seed in args.seeds:
        print(f"[bench] match with seed {seed}: 1 x {args.half_seconds:.0f} s at real time", flush=True)
        perf_file = args.out / f"match_perf_seed{seed}.json"
        folder = args.out / "matches"
        status = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds",
                                 str(args.half_seconds), "--halves", "1", "--seed", str(seed), "--out", str(folder),
                                 "--perf-json", str(perf_file)]).returncode
        latest = max(folder.iterdir(), key=lambda p: p.stat().st_mtime)
        report = json.loads((latest / "report.json").read_text())
        perf = json.loads(perf_file.read_text())
        matches.append({
            "seed": seed, "status": status, "folder": str(latest), "performance": perf,
            "goals": sum(report["score"].values()),
            "passes_completed": sum(t["completed"] for t in report["passes"].values()),
            "passes_tried": sum(t["tried"] for t in report["passes"].values()),
            "shots": sum(report["shots"].values()),
            "running_share": round(report["running_time_s"] / report["duration_s"], 3),
        })
    keys = ("goals", "passes_completed", "passes_tried", "shots", "running_share")
    summary = {k: round(statistics.mean(m[k] for m in matches), 3) for k in keys}
    for k in ("achieved_real_time_factor", "control_rate_min_hz", "missed_cycle_share", "cpu_cores_total",
              "rss_mib_total"):
        summary[k] = round(statistics.mean(m["performance"][k] for m in matches), 3)
    result = {"half_seconds": args.half_seconds, "matches": matches, "mean": summary}
    (args.out / "match.json").write_text(json.dumps(result, indent=2))
    print(json.dumps(summary, indent=2))
    print(f"figures: {args.out / 'match.json'}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
