"""What the benchmarks share: timing a method's calls in place (``timed``, ``CallTimer``), wall and CPU clocks of a
block (``Clock``), running a block on one core (``pinned``) and the machine's facts and load (``machine``,
``cpu_pressure``) that every benchmark's JSON records beside its figures."""

from __future__ import annotations

import math
import os
import platform
import time
from collections.abc import Callable, Iterator
from contextlib import contextmanager
from dataclasses import dataclass
from pathlib import Path
from typing import Any

LOAD_NOTE = ("Wall-clock figures: a loaded machine lowers them (see load_average and, per "
             "pinned measurement, cpu_share = process CPU time / wall time; *_per_cpu_second is less affected).")


class CallTimer:
    """Stands in for a bound method: calls it and adds up the calls and the wall time spent in them."""

    def __init__(self, call: Callable[..., Any]):
        self.call = call
        self.calls = 0
        self.seconds = 0.0

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        start = time.perf_counter()
        try:
            return self.call(*args, **kwargs)
        finally:
            self.seconds += time.perf_counter() - start
            self.calls += 1

    def clear(self) -> None:
        self.calls, self.seconds = 0, 0.0


def timed(owner: object, method: str) -> CallTimer:
    """Replace ``owner.method`` by a ``CallTimer`` of it (an instance attribute: the class is untouched)."""
    timer = CallTimer(getattr(owner, method))
    setattr(owner, method, timer)
    return timer


def _threads() -> list[int]:
    try:
        return [int(tid) for tid in os.listdir("/proc/self/task")]
    except OSError:
        return [0]


@contextmanager
def pinned(cpu: int | None) -> Iterator[None]:
    """Run the block with every thread of this process (numpy's BLAS threads too) on core ``cpu`` only (no
    pinning for None); restore the affinities after it. Threads and processes started inside inherit it."""
    if cpu is None:
        yield
        return
    before = {tid: os.sched_getaffinity(tid) for tid in _threads()}
    for tid in before:
        os.sched_setaffinity(tid, {cpu})
    try:
        yield
    finally:
        for tid, cpus in before.items():
            try:
                os.sched_setaffinity(tid, cpus)
            except OSError:  # the thread has ended
                pass


@dataclass
class Clock:
    """Wall and process CPU time of a measured stretch."""

    wall: float = 0.0
    cpu: float = 0.0

    @contextmanager
    def measure(self) -> Iterator[None]:
        wall, cpu = time.perf_counter(), time.process_time()
        try:
            yield
        finally:
            self.wall += time.perf_counter() - wall
            self.cpu += time.process_time() - cpu

    @property
    def cpu_share(self) -> float:
        return self.cpu / self.wall if self.wall > 0 else math.nan


def cpu_pressure() -> float | None:
    """The kernel's share of the last 60 s in which some runnable task waited for a CPU [%] (PSI), if known."""
    try:
        some = Path("/proc/pressure/cpu").read_text().splitlines()[0]
        return float(dict(f.split("=") for f in some.split()[1:])["avg60"])
    except (OSError, IndexError, KeyError, ValueError):
        return None


def machine(cpu: int | None) -> dict:
    model = ""
    try:
        model = next((line.split(":", 1)[1].strip() for line in Path("/proc/cpuinfo").read_text().splitlines()
                      if line.startswith("model name")), "")
    except OSError:
        pass
    return {"cpus": os.cpu_count(), "affinity": sorted(os.sched_getaffinity(0)), "pinned_cpu": cpu,
            "cpu_model": model, "python": platform.python_version(), "platform": platform.platform(),
            "load_average_start": [round(x, 2) for x in os.getloadavg()],
            "cpu_pressure_some_avg60_percent_start": cpu_pressure(), "note": LOAD_NOTE}
