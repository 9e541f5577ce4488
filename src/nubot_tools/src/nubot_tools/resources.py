"""Memory and CPU of every process of a match over time, and whether any of them grows (no rospy here).

Provides ``ResourceLog`` (sample the processes under some root pids: each ROS node by its full name,
RSS [MiB] and CPU [cores] since the previous sample), ``growth`` (each process's RSS slope [MiB per
minute] after a warm-up, by least squares) and ``plot_resources`` (RSS and CPU against sim time, one
line per node, the node kinds in one colour each). A leak shows as a slope that does not flatten.
"""

from __future__ import annotations

import json
from collections.abc import Callable, Iterable
from dataclasses import asdict, dataclass
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import psutil


@dataclass(frozen=True)
class Sample:
    wall: float  # [s] since the log started
    sim: float  # [s] sim time
    process: str  # the ROS node's full name (e.g. /nubot2/world_model), else the executable
    pid: int
    rss_mib: float
    cpu_cores: float  # since the previous sample of this process


def node_label(cmdline: list[str], environ: dict[str, str]) -> str:
    """``/<ns>/<name>`` of a ROS node from its command line (``__name:=``, ``__ns:=``) and ROS_NAMESPACE."""
    args = dict(a.split(":=", 1) for a in cmdline if a.startswith("__") and ":=" in a)
    name = args.get("__name")
    if name is None:
        return Path(cmdline[0]).name if cmdline else "?"
    ns = args.get("__ns", environ.get("ROS_NAMESPACE", "/")).strip("/")
    return f"/{ns}/{name}" if ns else f"/{name}"


class ResourceLog:
    """Samples every process below ``roots()`` (pids), e.g. each launch of a match."""

    def __init__(self, roots: Callable[[], Iterable[int]], clock: Callable[[], float]):
        self._psutil = psutil
        self.roots, self.clock = roots, clock
        self.samples: list[Sample] = []
        self._known: dict[int, object] = {}  # psutil measures CPU between two calls on the same object
        self._start: float | None = None

    def _processes(self) -> list:
        found = []
        for root in self.roots():
            try:
                proc = self._psutil.Process(root)
                found += [proc, *proc.children(recursive=True)]
            except self._psutil.NoSuchProcess:
                continue
        return [self._known.setdefault(p.pid, p) for p in found]

    def sample(self, wall: float) -> None:
        if self._start is None:
            self._start = wall
        sim = self.clock()
        for proc in self._processes():
            try:
                with proc.oneshot():
                    cpu = proc.cpu_percent(None) / 100.0
                    rss = proc.memory_info().rss / 2**20
                    label = node_label(proc.cmdline(), proc.environ())
            except (self._psutil.NoSuchProcess, self._psutil.AccessDenied, self._psutil.ZombieProcess):
                continue
            self.samples.append(Sample(round(wall - self._start, 2), round(sim, 2), label, proc.pid, round(rss, 2),
                                       round(cpu, 3)))

    def save(self, path: Path) -> None:
        path.parent.mkdir(parents=True, exist_ok=True)
        path.write_text(json.dumps([asdict(s) for s in self.samples]) + "\n")


def load(path: Path) -> list[Sample]:
    return [Sample(**s) for s in json.loads(path.read_text())]


def node_kind(process: str) -> str:
    """The kind of a node: its name without the robot or team namespace (``/nubot2/world_model`` -> world_model)."""
    return process.rstrip("/").rsplit("/", 1)[-1]


def _series(samples: list[Sample]) -> dict[tuple[str, int], list[Sample]]:
    series: dict[tuple[str, int], list[Sample]] = {}
    for s in samples:
        series.setdefault((s.process, s.pid), []).append(s)
    return series


def growth(samples: list[Sample], warmup: float) -> dict[str, dict[str, float]]:
    """Per process: RSS slope [MiB/min] over wall time after ``warmup`` [s], first and last RSS, mean CPU."""
    out: dict[str, dict[str, float]] = {}
    for (process, pid), rows in _series(samples).items():
        late = [r for r in rows if r.wall >= warmup]
        if len(late) < 3:
            continue
        t = np.array([r.wall for r in late]) / 60.0
        rss = np.array([r.rss_mib for r in late])
        slope = float(np.polyfit(t, rss, 1)[0])
        key = process if process not in out else f"{process} ({pid})"
        out[key] = {"slope_mib_per_min": round(slope, 4), "rss_first_mib": round(float(rss[0]), 1),
                    "rss_last_mib": round(float(rss[-1]), 1), "minutes": round(float(t[-1] - t[0]), 1),
                    "cpu_cores_mean": round(float(np.mean([r.cpu_cores for r in late[1:]] or [0.0])), 3)}
    return out


def plot_resources(samples: list[Sample], path: Path, warmup: float, title: str) -> None:
    kinds = sorted({node_kind(s.process) for s in samples})
    colours = {k: plt.get_cmap("tab10")(i % 10) for i, k in enumerate(kinds)}
    fig, (ax_rss, ax_cpu) = plt.subplots(2, 1, figsize=(11, 8), sharex=True)
    labelled: set[str] = set()
    for (process, _pid), rows in sorted(_series(samples).items()):
        kind = node_kind(process)
        minutes = [r.wall / 60.0 for r in rows]
        label = kind if kind not in labelled else None
        labelled.add(kind)
        ax_rss.plot(minutes, [r.rss_mib for r in rows], color=colours[kind], lw=1, label=label)
        ax_cpu.plot(minutes[1:], [r.cpu_cores for r in rows[1:]], color=colours[kind], lw=0.8)
    for ax in (ax_rss, ax_cpu):
        ax.axvline(warmup / 60.0, color="grey", ls="--", lw=0.8)
        ax.grid(alpha=0.3)
    ax_rss.set_ylabel("RSS [MiB]")
    ax_cpu.set_ylabel("CPU [cores]")
    ax_cpu.set_xlabel("wall time [min] (dashed: end of warm-up)")
    ax_rss.legend(fontsize=8, ncol=4)
    ax_rss.set_title(title)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)
