"""Golden traces: what one numeric piece of the robot cycle was given and gave back, recorded over seeded lockstep
matches, kept as test data so that a new implementation of the piece can be held to the old one's answers.

``python -m nubot_tools.golden mpc --out FILE`` plays ``--seeds`` lockstep matches of the default teams (MPC
tracker) for ``--seconds`` of sim time each and records every ``LaguerreMpc.command`` call: its inputs (position,
previous command, reference, limits), its command and how it was found (``last_status``). Calls are kept per
status, at most ``--per-status`` of each (drawn with the seeded generator), so that the rare ones (the QP solved,
the fallback) are all there beside a sample of the common one. The file is numpy's compressed ``.npz``; its
``params`` entry is the controller's ``MpcParams`` as JSON.
"""

from __future__ import annotations

import argparse
import dataclasses
import json
import math
import sys
from pathlib import Path
from typing import Any

import numpy as np

from nubot_tools.workspace import TEAMS


def play(seeds: list[int], seconds: float) -> None:
    """Lockstep matches of the default teams with the MPC tracker, ``seconds`` of sim time each."""
    from nubot_match.config import match_config
    from nubot_match.engine import LockstepMatch

    for seed in seeds:
        config = match_config(TEAMS / "nubot.yaml", TEAMS / "rival.yaml", "18x12", "mpc", half_seconds=600.0,
                              halves=2, seed=seed)
        match = LockstepMatch(config, [])
        match.reset(seed)
        match.run(until=seconds)
        match.close()
        print(f"golden: seed {seed} played ({seconds:.0f} s)", file=sys.stderr)


def record_mpc(seeds: list[int], seconds: float, per_status: int) -> dict[str, np.ndarray]:
    from nubot_control.mpc import LaguerreMpc

    calls: list[tuple[Any, tuple, dict, Any]] = []
    statuses: list[str] = []

    def command(self: Any, *args: Any, **kwargs: Any) -> Any:
        result = original(self, *args, **kwargs)
        calls.append((self, args, kwargs, np.array(result, dtype=float)))
        statuses.append(self.last_status)
        return result

    original = LaguerreMpc.command
    LaguerreMpc.command = command  # type: ignore[assignment]
    try:
        play(seeds, seconds)
    finally:
        LaguerreMpc.command = original  # type: ignore[assignment]
    params = {json.dumps(dataclasses.asdict(mpc.params), sort_keys=True) for mpc, *_ in calls}
    if len(params) != 1:
        raise RuntimeError(f"the robots' controllers differ in their parameters: {sorted(params)}")
    rng = np.random.default_rng(0)
    kept: list[int] = []
    for status in sorted(set(statuses)):
        where = [i for i, s in enumerate(statuses) if s == status]
        chosen = rng.choice(where, size=min(per_status, len(where)), replace=False)
        kept.extend(sorted(int(i) for i in chosen))
        print(f"golden: {status}: {len(where)} calls, {len(chosen)} kept", file=sys.stderr)
    kept.sort()

    def argument(i: int, name: str, position: int, default: Any = None) -> Any:
        _, args, kwargs, _ = calls[i]
        return args[position] if position < len(args) else kwargs.get(name, default)

    names = ("position", "previous", "ref_positions", "ref_velocities")
    trace = {name: np.array([np.asarray(argument(i, name, n), dtype=float) for i in kept])
             for n, name in enumerate(names)}
    def limit(i: int, name: str, position: int) -> float:
        value = argument(i, name, position)
        return math.nan if value is None else float(value)  # NaN: none given (the controller's own)

    limits = {name: np.array([limit(i, name, n) for i in kept]) for n, name in ((4, "max_speed"), (5, "max_accel"))}
    return {**trace, **limits, "command": np.array([calls[i][3] for i in kept]),
            "status": np.array([statuses[i] for i in kept]), "params": np.array(params.pop())}


def main(argv: list[str] | None = None) -> int:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("piece", choices=("mpc",))
    ap.add_argument("--out", type=Path, required=True)
    ap.add_argument("--seeds", type=int, default=3, help="matches, seeds 0 .. N-1")
    ap.add_argument("--seconds", type=float, default=60.0, help="sim time per match [s]")
    ap.add_argument("--per-status", type=int, default=500)
    args = ap.parse_args(argv)
    if args.seeds < 1 or not args.seconds > 0 or args.per_status < 1:
        ap.error("--seeds, --seconds and --per-status must be positive")
    trace = record_mpc(list(range(args.seeds)), args.seconds, args.per_status)
    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(args.out, **trace)
    print(f"golden: {len(trace['status'])} calls written to {args.out}", file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main())
