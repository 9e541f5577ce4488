"""The soak: a full-length match (2 x 15 min by default) with every process's memory and CPU sampled.

Runs ``match_runner`` with ``--resources-json``, then writes beside the match ``soak.json`` (each
process's RSS slope after the warm-up, in MiB per minute, and the verdict against ``--bound``) and
``soak.png`` (RSS and CPU of every node against time). Exit status 1 when a process grows faster than
the bound: a leak shows as a slope that does not flatten.

    make soak                      # HALF_SECONDS=900
    python scripts/soak.py --half-seconds 120 --bound 0.5
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

from nubot_tools import resources
from nubot_tools.ros import match_runner
from nubot_tools.workspace import WORKSPACE


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--half-seconds", type=float, default=900.0)
    parser.add_argument("--period", type=float, default=10.0, help="sample every this many wall seconds")
    parser.add_argument("--warmup", type=float, default=180.0, help="[s, wall] left out of the slopes")
    parser.add_argument("--bound", type=float, default=0.5, help="largest acceptable RSS slope [MiB/min]")
    parser.add_argument("--out", type=Path, default=WORKSPACE / "soak")
    parser.add_argument("--field", default="18x12")
    args = parser.parse_args(argv)
    if not (args.period > 0 and args.warmup >= 0 and args.bound > 0 and args.half_seconds > 0):
        parser.error("--period, --bound and --half-seconds must be positive, --warmup not negative")
    args.out.mkdir(parents=True, exist_ok=True)
    samples_file = args.out / "resources.json"
    status = match_runner.main(["--half-seconds", str(args.half_seconds), "--out", str(args.out), "--field",
                                args.field, "--resources-json", str(samples_file),
                                "--resources-period", str(args.period)])
    if not samples_file.exists():
        print(f"soak: the match wrote no samples (status {status})", file=sys.stderr)
        return status or 1
    samples = resources.load(samples_file)
    slopes = resources.growth(samples, args.warmup)
    worst = max(slopes.items(), key=lambda kv: kv[1]["slope_mib_per_min"], default=None)
    growing = {p: g for p, g in slopes.items() if g["slope_mib_per_min"] > args.bound}
    verdict = {"bound_mib_per_min": args.bound, "warmup_s": args.warmup, "period_s": args.period,
               "half_seconds": args.half_seconds, "match_status": status, "processes": len(slopes),
               "growing": sorted(growing), "worst": worst[0] if worst else None,
               "worst_slope_mib_per_min": worst[1]["slope_mib_per_min"] if worst else None, "slopes": slopes}
    (args.out / "soak.json").write_text(json.dumps(verdict, indent=2) + "\n")
    resources.plot_resources(samples, args.out / "soak.png", args.warmup,
                             f"Soak: {len(slopes)} processes, 2 x {args.half_seconds:.0f} s "
                             f"(worst slope {verdict['worst_slope_mib_per_min']} MiB/min)")
    kinds: dict[str, list[float]] = {}
    for process, g in slopes.items():
        kinds.setdefault(resources.node_kind(process.split(" ")[0]), []).append(g["slope_mib_per_min"])
    print("soak: RSS slope after the warm-up [MiB/min], largest per node kind:")
    for kind, values in sorted(kinds.items()):
        print(f"  {kind:24s} {max(values):+.3f}  ({len(values)} process(es))")
    if growing:
        print(f"soak: FAILED: {len(growing)} process(es) grow faster than {args.bound} MiB/min: "
              f"{', '.join(sorted(growing))}")
        return 1
    print(f"soak: no process grows faster than {args.bound} MiB/min; {args.out / 'soak.png'}")
    return 0 if status == 0 else status


if __name__ == "__main__":
    sys.exit(main())
