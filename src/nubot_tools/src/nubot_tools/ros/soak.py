"""The soak: a full-length match (2 x 15 min by default) with every process's memory and CPU sampled.

Runs ``match_runner`` with ``--resources-json``, then writes beside the match ``soak.json`` (each
process's RSS slope after the warm-up, in MiB per minute, and the verdict against ``--bound``) and
``soak.png`` (RSS and CPU of every node against time). Exit status 1 when a process grows faster than
the bound: a leak shows as a slope that does not flatten.

The recorder is held to another bound: ``rosbag record`` keeps the bag's index (one entry per message,
written at the end of the bag) in memory, so it grows with the messages it records, by design; its
growth per recorded message must stay under ``--recorder-bytes``. ``--analyse FOLDER`` redoes the
verdict from a soak's saved ``resources.json`` without playing again.

    make soak                      # HALF_SECONDS=900
    python scripts/soak.py --half-seconds 120 --bound 0.5
"""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

from rosbags.rosbag1 import Reader

from nubot_common.json_text import strict_json
from nubot_tools import resources
from nubot_tools.ros import match_runner
from nubot_tools.workspace import SOAK

RECORDER = "match_recorder"


def _recorded_messages(out: Path) -> int:
    """Messages in the soak's bag (from its index: quick even for gigabytes)."""
    bags = sorted(out.glob("match-*/match.bag"))
    if not bags:
        return 0
    with Reader(bags[-1]) as reader:
        return reader.message_count


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--half-seconds", type=float, default=900.0)
    parser.add_argument("--period", type=float, default=10.0, help="sample every this many wall seconds")
    parser.add_argument("--warmup", type=float, default=180.0, help="[s, wall] left out of the slopes")
    parser.add_argument("--bound", type=float, default=0.5, help="largest acceptable RSS slope [MiB/min]")
    parser.add_argument("--recorder-bytes", type=float, default=32.0,
                        help="largest acceptable growth of the recorder per recorded message [bytes]")
    parser.add_argument("--out", type=Path, default=SOAK)
    parser.add_argument("--field", default="18x12")
    parser.add_argument("--analyse", action="store_true", help="judge the soak already in --out, do not play")
    args = parser.parse_args(argv)
    if not (args.period > 0 and args.warmup >= 0 and args.bound > 0 and args.half_seconds > 0
            and args.recorder_bytes > 0):
        parser.error("--period, --bound, --recorder-bytes and --half-seconds must be positive, --warmup not negative")
    args.out.mkdir(parents=True, exist_ok=True)
    samples_file = args.out / "resources.json"
    status = 0
    if not args.analyse:
        status = match_runner.main(["--half-seconds", str(args.half_seconds), "--out", str(args.out), "--field",
                                    args.field, "--resources-json", str(samples_file),
                                    "--resources-period", str(args.period)])
    if not samples_file.exists():
        print(f"soak: the match wrote no samples (status {status})", file=sys.stderr)
        return status or 1
    samples = resources.load(samples_file)
    slopes = resources.growth(samples, args.warmup)
    recorder = {p: g for p, g in slopes.items() if resources.node_kind(p.split(" ")[0]) == RECORDER}
    nodes = {p: g for p, g in slopes.items() if p not in recorder}
    worst = max(nodes.items(), key=lambda kv: kv[1]["slope_mib_per_min"], default=None)
    growing = {p: g for p, g in nodes.items() if g["slope_mib_per_min"] > args.bound}
    messages = _recorded_messages(args.out)
    index_growth = max((g["rss_last_mib"] - g["rss_first_mib"] for g in recorder.values()), default=0.0)
    per_message = round(index_growth * 2**20 / messages, 1) if messages else None
    if per_message is not None and per_message > args.recorder_bytes:
        growing |= recorder
    verdict = {"bound_mib_per_min": args.bound, "warmup_s": args.warmup, "period_s": args.period,
               "half_seconds": args.half_seconds, "match_status": status, "processes": len(slopes),
               "growing": sorted(growing), "worst": worst[0] if worst else None,
               "worst_slope_mib_per_min": worst[1]["slope_mib_per_min"] if worst else None,
               "recorder": {"messages": messages, "rss_growth_mib": round(index_growth, 1),
                            "bytes_per_message": per_message, "bound_bytes_per_message": args.recorder_bytes},
               "slopes": slopes}
    (args.out / "soak.json").write_text(strict_json(verdict, indent=2))
    resources.plot_resources(samples, args.out / "soak.png", args.warmup,
                             f"Soak: {len(slopes)} processes, 2 x {args.half_seconds:.0f} s "
                             f"(worst slope {verdict['worst_slope_mib_per_min']} MiB/min)")
    kinds: dict[str, list[float]] = {}
    for process, g in slopes.items():
        kinds.setdefault(resources.node_kind(process.split(" ")[0]), []).append(g["slope_mib_per_min"])
    print(f"soak: the recorder grew {index_growth:.1f} MiB for {messages} messages ({per_message} bytes each, "
          f"bound {args.recorder_bytes:g}): the bag's index")
    print("soak: RSS slope after the warm-up [MiB/min], largest per node kind:")
    for kind, values in sorted(kinds.items()):
        print(f"  {kind:24s} {max(values):+.3f}  ({len(values)} process(es))")
    if growing:
        print(f"soak: FAILED: {len(growing)} process(es) grow faster than {args.bound} MiB/min: "
              f"{', '.join(sorted(growing))}")
        return 1
    print(f"soak: no node grows faster than {args.bound} MiB/min (the recorder by its index only); "
          f"{args.out / 'soak.png'}")
    return 0 if status == 0 else status


if __name__ == "__main__":
    sys.exit(main())
