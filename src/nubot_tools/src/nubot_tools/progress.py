"""Whether a simulation still advances: a runner waits on a match or a demo for as long as its sim time moves, however
slowly (a loaded machine, every robot on its rendered camera), and gives up only on one whose sim time has stopped.

``SimProgress(patience)``: fed the sim time now and then (``stalled(sim_time)``); stalled once the sim time has not
moved for ``patience`` seconds of the wall clock.
"""

from __future__ import annotations

import time
from collections.abc import Callable


class SimProgress:
    def __init__(self, patience: float, wall: Callable[[], float] = time.monotonic):
        if not patience > 0.0:
            raise ValueError(f"patience must be positive, got {patience}")
        self.patience, self._wall = patience, wall
        self._sim: float | None = None
        self._since = wall()  # when the sim time last moved (or watching began) [s, wall]

    def stalled(self, sim_time: float) -> bool:
        """Whether the sim time has stood still for ``patience`` wall seconds, ``sim_time`` being its value now."""
        now = self._wall()
        if self._sim is None or sim_time != self._sim:
            self._sim, self._since = sim_time, now
        return now - self._since >= self.patience

    def describe(self) -> str:
        return (f"the simulation stopped advancing (sim time at {self._sim or 0.0:.1f} s for "
                f"{self._wall() - self._since:.0f} s of wall time)")
