"""Throttled reports of refused inputs: a flood of bad commands must not flood the log.

Requires: a clock in seconds (the node passes the wall clock). Provides: ``RejectionReporter``,
which counts refusals per source (a robot) and kind (``velocity command rejected``) and says
when to report them: at the first one, then at most once every ``interval`` seconds, each line
carrying the count since the previous line of that source and kind and the latest detail; and ``RefusalLog``, the
same for a node: its refusals straight into its log. Every node reports what a peer may flood it with this way.
"""

from __future__ import annotations

import math
import threading
import time
from collections.abc import Callable
from dataclasses import dataclass


@dataclass
class _Tally:
    count: int = 0  # refusals since the last report
    detail: str = ""  # the latest refusal's reason
    reported_at: float = -math.inf  # [s]


class RejectionReporter:
    def __init__(self, interval: float):
        if not interval > 0.0:
            raise ValueError(f"interval must be positive, got {interval}")
        self.interval = interval  # [s] between two reports of one source and kind
        self._tallies: dict[tuple[str, str], _Tally] = {}

    def count(self, source: str, kind: str, detail: str, now: float) -> str | None:
        """Count one refusal at ``now`` [s]; return the line to log now, or None while throttled."""
        key = (source, kind)
        tally = self._tallies.setdefault(key, _Tally())
        tally.count += 1
        tally.detail = detail
        return self._report(key, tally, now) if now - tally.reported_at >= self.interval else None

    def due(self, now: float) -> list[str]:
        """Lines for counts held back longer than ``interval`` (call it regularly: a flood's tail is reported too)."""
        lines = []
        for key, tally in list(self._tallies.items()):
            if now - tally.reported_at < self.interval:
                continue
            if tally.count:
                lines.append(self._report(key, tally, now))
            else:
                del self._tallies[key]  # quiet for a whole interval: its next refusal is reported at once
        return lines

    def _report(self, key: tuple[str, str], tally: _Tally, now: float) -> str:
        source, kind = key
        line = (f"{source}: {kind} {tally.count} time(s) since the last report (at most one every "
                f"{self.interval:g} s); latest: {tally.detail}")
        tally.count, tally.reported_at = 0, now
        return line


class RefusalLog:
    """A node's refused inputs into its log through a ``RejectionReporter``: the first of a kind at once, then a line
    every ``interval`` seconds with the count and the latest reason; thread-safe."""

    def __init__(self, source: str, log: Callable[[str], None], interval: float = 5.0,
                 clock: Callable[[], float] = time.monotonic):
        self.source, self._log, self._clock = source, log, clock
        self._reporter = RejectionReporter(interval)
        self._lock = threading.Lock()

    def refused(self, kind: str, detail: str) -> None:
        """One refused input of ``kind`` (``image refused``) for ``detail`` (why)."""
        with self._lock:
            line = self._reporter.count(self.source, kind, detail, self._clock())
        if line is not None:
            self._log(line)

    def flush(self) -> None:
        """Report the counts held back longer than the interval (call it now and then: a flood's tail)."""
        with self._lock:
            lines = self._reporter.due(self._clock())
        for line in lines:
            self._log(line)
