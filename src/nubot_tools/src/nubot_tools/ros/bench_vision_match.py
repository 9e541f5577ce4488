"""Benchmark a 2 vs 2 match with every robot seeing through its camera against the same match on the truth.

    python scripts/bench_vision_match.py --out bench/results [--seeds 1 2] [--half-seconds 60]

For each seed it plays one half of a 2 vs 2 match (a goalie and a field player per team, the MPC tracker) twice
with ``run_match.py``: on the simulator's percepts (``truth``) and with ``--vision all`` (every robot's
OmniVisionInfo from its omni_vision node, on camera images, odometry and its inertial heading). Writes
``<out>/vision_match.json``: per match the real-time factor, the control loops' rates, CPU, goals, passes,
shots and collisions; per mode their means over the seeds.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import yaml

from nubot_common.json_text import strict_json
from nubot_tools.ros.bench_match import PERFORMANCE, PLAY, mean_of, play_match
from nubot_tools.workspace import BENCH_RESULTS

MODES = {"truth": (), "vision": ("--vision", "all")}


def two_vs_two_teams(folder: Path) -> tuple[str, ...]:
    """``--team`` arguments for nubot and rival, a goalie and one field player each."""
    folder.mkdir(parents=True, exist_ok=True)
    args: list[str] = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = folder / f"{prefix}_2v2.yaml"
        path.write_text(yaml.safe_dump({"name": prefix.title(), "prefix": prefix, "attack": attack, "goalie": 1,
                                        "robots": [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}]}))
        args += ["--team", str(path)]
    return tuple(args)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seeds", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--half-seconds", type=float, default=60.0)
    args = parser.parse_args(argv)
    out = args.out / "vision_match"
    teams = two_vs_two_teams(out / "teams")
    matches: dict[str, list[dict]] = {mode: [] for mode in MODES}
    for seed in args.seeds:
        for mode, extra in MODES.items():
            print(f"[bench] vision match: seed {seed}, {mode}", flush=True)
            result = play_match("mpc", seed, args.half_seconds, out, (*teams, *extra), label=mode)
            matches[mode].append({"mode": mode, **result})
    means = {mode: {**{k: mean_of(ms, k) for k in PLAY}, **{k: mean_of(ms, k, performance=True) for k in PERFORMANCE}}
             for mode, ms in matches.items()}
    result = {"seeds": args.seeds, "half_seconds": args.half_seconds, "teams": "2 vs 2", "means": means,
              "matches": matches}
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "vision_match.json").write_text(strict_json(result, indent=2))
    for mode, m in means.items():
        print(f"{mode}: goals {m['goals']}, passes {m['passes_completed']}/{m['passes_tried']}, shots {m['shots']}, "
              f"real-time factor {m['achieved_real_time_factor']}, slowest loop {m['control_rate_min_hz']} Hz, "
              f"CPU {m['cpu_cores_total']} cores")
    print(f"figures: {args.out / 'vision_match.json'}")
    return 0
