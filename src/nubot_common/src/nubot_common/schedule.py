"""Periodic tasks in sim time: a simulator steps in whole physics steps, and a task is due at the first step at
or after each of its due times (0, period, 2 period, ...), never drifting however the steps and the period fall.

Used by the simulator node (its /clock and sensor rates) and the lockstep engine (its whole schedule).
"""

from __future__ import annotations

import math

from nubot_common import NubotCommonError

EPS = 1e-9  # [s] a time this close below a due time counts as reaching it (sums of steps drift)


class Periodic:
    """Due times of one periodic task in sim time: due at ``start``, then every ``period`` [s], never drifting."""

    def __init__(self, period: float, start: float = 0.0):
        if not period > 0.0:
            raise NubotCommonError(f"a period must be positive, got {period}")
        self.period = period
        self.count = 0
        self.start = start

    @property
    def next(self) -> float:
        return self.start + self.count * self.period

    def due(self, t: float) -> bool:
        """True (and advance) when ``t`` reached the next due time; one call fires at most once."""
        if t + EPS >= self.next:
            self.count = max(self.count + 1, math.floor((t + EPS - self.start) / self.period) + 1)
            return True
        return False
