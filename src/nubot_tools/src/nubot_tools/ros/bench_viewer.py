"""Benchmark the live match page: what the viewer node, and a browser watching it, cost a 5 vs 5 match.

    python scripts/bench_viewer.py [--out bench/results] [--half-seconds 60] [--screenshot docs/viewer_live.png]

Requires: the whole match stack (``nubot_tools.ros.match_runner``, run as a child in its own process group),
Debian's chromium and chromium-driver (``nubot_tools.browser.Page``), psutil, matplotlib and Pillow.
Plays two refereed 5 vs 5 matches of the default teams at real time, the live viewer running in both: one with no
page open, then one with a headless Chromium page (--width x --height) open on the viewer from before kick-off to
full time. The page is sampled every --sample-period s between kick-off and full time.
Provides: ``<out>/viewer.json``: per match the achieved real-time factor (``--perf-json``), the viewer node's CPU
[cores] (mean and max of the ``--resources-json`` samples) and the whole match's, the load average before and after
and how many processes of other matches or tests ran meanwhile; with the page, Chromium's CPU [cores] (all its
processes, psutil), the page's update rate as the page counts it: its own ``window.viewerStats.fps`` (frames per
second over its ~1 s timer's last interval) and its ``frames`` counter over each sample period [frames/s],
median and min of each; and the frames it received against the viewer's rate (the missing ones skipped by the
server or lost to a late tick); the machine's cores and load average.
``<out>/viewer.png``: the figures as bars. With ``--screenshot PATH``: the page mid-match, a PNG of at most
--screenshot-bytes (quantised to a palette when larger).
Parameters: --half-seconds [s of game time] (60), --halves (2), --sample-period [s, wall] (5), --width, --height
[px] (1280 x 720), --screenshot, --screenshot-bytes (200000), --out.
"""

from __future__ import annotations

import argparse
import contextlib
import json
import os
import re
import signal
import statistics
import subprocess
import sys
import threading
import time
from collections.abc import Iterable
from pathlib import Path
from typing import Any

import matplotlib.pyplot as plt
import psutil
from PIL import Image

from nubot_common.json_text import strict_json
from nubot_tools.browser import Page
from nubot_tools.workspace import BENCH_RESULTS

VIEWER_RATE_HZ = 25.0  # the viewer node's ~rate default, which run_match.py keeps
VIEWER_NODE = "/viewer"  # its name in run_match.py's resource samples
SCREENSHOT_AT = 0.4  # [share of the game time after kick-off]: in the first half, play under way
URL_TIMEOUT = 180.0  # [s, wall] until the runner prints the page's address
KICKOFF_TIMEOUT = 300.0  # [s, wall] until the robots are up and the referee kicks off


# ---- summaries (pure) ------------------------------------------------------------------------------------------

def spread(values: Iterable[float]) -> dict[str, Any]:
    """Mean and max of samples (None when there are none), and how many there were."""
    values = list(values)
    if not values:
        return {"mean": None, "max": None, "samples": 0}
    return {"mean": round(statistics.mean(values), 3), "max": round(max(values), 3), "samples": len(values)}


def rate_summary(values: Iterable[float]) -> dict[str, Any]:
    """Median and min of rate samples [Hz] (None when there are none), and how many there were."""
    values = list(values)
    if not values:
        return {"median": None, "min": None, "samples": 0}
    return {"median": round(statistics.median(values), 2), "min": round(min(values), 2), "samples": len(values)}


def node_cpu(samples: Iterable[dict[str, Any]], process: str) -> list[float]:
    """A node's CPU [cores] per sampling instant of a ``ResourceLog`` file (its processes summed), in time order.

    Each process's first sample is dropped: psutil has nothing to measure against then and says 0."""
    seen: set[int] = set()
    by_wall: dict[float, float] = {}
    for row in samples:
        if row["process"] != process:
            continue
        if row["pid"] not in seen:
            seen.add(row["pid"])
            continue
        by_wall[row["wall"]] = by_wall.get(row["wall"], 0.0) + row["cpu_cores"]
    return [by_wall[w] for w in sorted(by_wall)]


def counter_rates(points: list[tuple[float, int]]) -> list[float]:
    """Rates [1/s] of a counter between successive (wall time [s], count) samples."""
    return [(c1 - c0) / (t1 - t0) for (t0, c0), (t1, c1) in zip(points, points[1:]) if t1 > t0]


def frame_budget(frames_start: int, frames_end: int, wall_seconds: float, rate: float) -> dict[str, Any]:
    """The frames a page received over ``wall_seconds`` against the ``rate`` [Hz] the server sends at: the
    missing ones were skipped by the server (the page still busy with the last) or lost to a late tick."""
    if wall_seconds <= 0 or frames_end < frames_start:
        raise ValueError(f"a frame count needs a positive span and growing counters, got {wall_seconds} s, "
                         f"{frames_start} -> {frames_end}")
    received = frames_end - frames_start
    at_rate = round(rate * wall_seconds)
    missing = max(0, at_rate - received)
    return {"received": received, "at_server_rate": at_rate, "missing": missing,
            "missing_share": round(missing / at_rate, 4) if at_rate else 0.0, "wall_seconds": round(wall_seconds, 1)}


def match_figures(perf: dict[str, Any], resources: list[dict[str, Any]]) -> dict[str, Any]:
    """The figures of one match from run_match.py's --perf-json and --resources-json files."""
    return {
        "achieved_real_time_factor": perf.get("achieved_real_time_factor"),
        "wall_seconds": perf.get("wall_seconds"), "sim_seconds": perf.get("sim_seconds"),
        "control_rate_min_hz": perf.get("control_rate_min_hz"), "missed_cycle_share": perf.get("missed_cycle_share"),
        "viewer_cpu_cores": spread(node_cpu(resources, VIEWER_NODE)),
        "match_cpu_cores_total": perf.get("cpu_cores_total"),
        "cpu_cores_by_kind": perf.get("cpu_cores_by_kind", {}),
    }


def page_cost(without: dict[str, Any], with_page: dict[str, Any]) -> dict[str, Any]:
    """What opening the page changed: real-time factor, the viewer's CPU, and the viewer's plus Chromium's."""
    def diff(a: float | None, b: float | None) -> float | None:
        return None if a is None or b is None else round(b - a, 3)

    viewer = diff(without["viewer_cpu_cores"]["mean"], with_page["viewer_cpu_cores"]["mean"])
    chromium = with_page.get("chromium_cpu_cores", {}).get("mean")
    both = None if viewer is None or chromium is None else round(viewer + chromium, 3)
    return {"real_time_factor_change": diff(without["achieved_real_time_factor"],
                                            with_page["achieved_real_time_factor"]),
            "viewer_cpu_cores_change": viewer,
            "viewer_and_chromium_cpu_cores": both}


# ---- the PNGs --------------------------------------------------------------------------------------------------

def shrink_png(path: Path, limit_bytes: int) -> int:
    """Make a PNG at most ``limit_bytes`` if it can be: quantise it to ever fewer colours; return its size."""
    size = path.stat().st_size
    if size <= limit_bytes:
        return size
    with Image.open(path) as image:
        rgb = image.convert("RGB")
    for colours in (256, 128, 64, 32):
        rgb.quantize(colors=colours, method=Image.Quantize.MEDIANCUT).save(path, optimize=True)
        size = path.stat().st_size
        if size <= limit_bytes:
            break
    return size


def plot(result: dict[str, Any], path: Path) -> None:
    runs = result["matches"]
    labels = ["no page", "page open"]
    fig, (ax_rtf, ax_cpu) = plt.subplots(1, 2, figsize=(8, 3.2), gridspec_kw={"width_ratios": [1, 2]})
    rtf = [runs[k]["achieved_real_time_factor"] or 0.0 for k in ("no_page", "page")]
    ax_rtf.bar(labels, rtf, color=["tab:grey", "tab:blue"])
    for x, value in enumerate(rtf):
        ax_rtf.text(x, value, f"{value:.3f}", ha="center", va="bottom", fontsize=8)
    ax_rtf.set_ylim(0, max(1.1, max(rtf) * 1.1))
    ax_rtf.axhline(1.0, color="black", lw=0.6, ls="--")
    ax_rtf.set_ylabel("achieved real-time factor")
    bars = [("viewer\nno page", runs["no_page"]["viewer_cpu_cores"], "tab:grey"),
            ("viewer\npage open", runs["page"]["viewer_cpu_cores"], "tab:blue"),
            ("Chromium\npage open", runs["page"].get("chromium_cpu_cores", spread([])), "tab:orange")]
    for x, (_label, cpu, colour) in enumerate(bars):
        mean, peak = cpu["mean"] or 0.0, cpu["max"] or 0.0
        ax_cpu.bar(x, mean, color=colour)
        ax_cpu.plot([x - 0.3, x + 0.3], [peak, peak], color="black", lw=1.2)
        ax_cpu.text(x, peak, f"mean {mean:.2f}\nmax {peak:.2f}", ha="center", va="bottom", fontsize=7)
    ax_cpu.set_xticks(range(len(bars)), [b[0] for b in bars], fontsize=8)
    ax_cpu.set_ylabel("CPU [cores] (bar: mean, line: max)")
    ax_cpu.set_ylim(0, max([b[1]["max"] or 0.0 for b in bars] + [0.1]) * 1.35)
    fps = runs["page"].get("page_frame_rate", rate_summary([]))
    fig.suptitle(f"live viewer, 5 vs 5 at real time on {result['machine']['cpus']} cores: the page drew median "
                 f"{fps['median']} / min {fps['min']} frames/s (server {VIEWER_RATE_HZ:g})", fontsize=9)
    fig.tight_layout()
    fig.savefig(path, dpi=90)
    plt.close(fig)


# ---- the matches -----------------------------------------------------------------------------------------------

class RunnerOutput:
    """The runner's stdout, echoed as it comes and kept for searching."""

    def __init__(self, process: subprocess.Popen):
        self.process = process
        self.lines: list[str] = []
        self.thread = threading.Thread(target=self._read, daemon=True)
        self.thread.start()

    def _read(self) -> None:
        assert self.process.stdout is not None
        for line in self.process.stdout:
            self.lines.append(line)
            print(f"    | {line.rstrip()}", flush=True)

    def search(self, pattern: str) -> re.Match | None:
        for line in list(self.lines):
            if (m := re.search(pattern, line)) is not None:
                return m
        return None

    def wait_for(self, pattern: str, timeout: float) -> re.Match:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            if (m := self.search(pattern)) is not None:
                return m
            if self.process.poll() is not None:
                self.thread.join(timeout=5)
                if (m := self.search(pattern)) is not None:
                    return m
                break
            time.sleep(0.2)
        raise RuntimeError(f"the match runner printed no line matching {pattern!r} (status {self.process.poll()}):\n"
                           + "".join(self.lines[-20:]))


class ChromiumMeter:
    """CPU [cores] of every process under chromedriver (Chromium's browser, renderer, GPU and utility processes)."""

    def __init__(self, driver_pid: int):
        self._psutil = psutil
        self.root = psutil.Process(driver_pid)
        self._known: dict[int, Any] = {}  # psutil measures CPU between two calls on the same Process object
        self.sample()

    def sample(self) -> float:
        total = 0.0
        for proc in self.root.children(recursive=True):
            known = self._known.setdefault(proc.pid, proc)
            try:
                total += known.cpu_percent(None) / 100.0
            except (self._psutil.NoSuchProcess, self._psutil.ZombieProcess):
                continue
        return total


class RunnerWatch:
    """Remembers every process the runner started (to end any it leaves behind) and notices other matches and
    tests on the machine (processes matching OTHERS outside the runner's tree), which bias the figures."""

    OTHERS = re.compile(r"sim_visual_node|pytest")
    PERIOD = 5.0  # [s, wall] between looks at the whole process table

    def __init__(self, runner_pid: int):
        self._psutil = psutil
        self.runner_pid = runner_pid
        self.started: dict[int, Any] = {}
        self.others_max = 0
        self._next_look = 0.0

    def tick(self) -> None:
        try:
            self.started.update({p.pid: p for p in self._psutil.Process(self.runner_pid).children(recursive=True)})
        except self._psutil.NoSuchProcess:
            return
        if time.monotonic() < self._next_look:
            return
        self._next_look = time.monotonic() + self.PERIOD
        ours = {self.runner_pid, os.getpid(), *self.started}
        others = 0
        for proc in self._psutil.process_iter(["pid", "cmdline"]):
            if proc.info["pid"] not in ours and self.OTHERS.search(" ".join(proc.info["cmdline"] or [])):
                others += 1
        if others > self.others_max:
            print(f"[bench] another match or test is running ({others} process(es)): the figures are biased",
                  flush=True)
        self.others_max = max(self.others_max, others)


def stop_group(process: subprocess.Popen, started: dict[int, Any]) -> None:
    """End the runner and everything it started: Ctrl-C to its group (it closes its bag and master), then SIGKILL;
    then any process it started (each launch is a session of its own) that outlived it, by its pid."""
    if process.poll() is None:
        with contextlib.suppress(ProcessLookupError):
            os.killpg(process.pid, signal.SIGINT)
        try:
            process.wait(timeout=40)
        except subprocess.TimeoutExpired:
            pass
    with contextlib.suppress(ProcessLookupError):
        os.killpg(process.pid, signal.SIGKILL)
    process.wait(timeout=10)
    left = [p for p in started.values() if p.is_running()]  # is_running also checks the pid was not reused
    for proc in left:
        with contextlib.suppress(psutil.NoSuchProcess):
            proc.kill()
    if left:
        psutil.wait_procs(left, timeout=10)
        print(f"[bench] killed {len(left)} process(es) the runner left behind", flush=True)


def play(label: str, args: argparse.Namespace, with_page: bool) -> dict[str, Any]:
    """One refereed match with run_match.py, with or without a page on the viewer; its figures."""
    perf_file = args.out / f"viewer_perf_{label}.json"
    resources_file = args.out / f"viewer_resources_{label}.json"
    for stale in (perf_file, resources_file):
        stale.unlink(missing_ok=True)
    command = [sys.executable, "-m", "nubot_tools.ros.match_runner", "--half-seconds", str(args.half_seconds),
               "--halves", str(args.halves), "--out", str(args.out / "matches"), "--perf-json", str(perf_file),
               "--resources-json", str(resources_file), "--resources-period", str(args.sample_period),
               "--viewer-port", "0", "--no-report"]
    process = subprocess.Popen(command, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True,
                               start_new_session=True)
    output = RunnerOutput(process)
    runner = RunnerWatch(process.pid)
    load_start = [round(v, 2) for v in os.getloadavg()]
    page_figures: dict[str, Any] = {}
    try:
        url = output.wait_for(r"watch it at (http://\S+)", URL_TIMEOUT)[1]
        if with_page:
            page_figures = watch(url, output, args, runner)
        else:
            output.wait_for(r"robots ready; kick-off", KICKOFF_TIMEOUT)
            print(f"[bench] {label}: kick-off; no page open", flush=True)
        while process.poll() is None:
            runner.tick()
            time.sleep(1.0)
    finally:
        stop_group(process, runner.started)
    output.thread.join(timeout=10)
    folder = output.search(r"folder (\S+)$")
    if not perf_file.exists() or not resources_file.exists():
        raise RuntimeError(f"the {label} match left no figures (status {process.returncode}):\n"
                           + "".join(output.lines[-20:]))
    figures = match_figures(json.loads(perf_file.read_text()), json.loads(resources_file.read_text()))
    return {"page": with_page, "status": process.returncode, "folder": folder[1] if folder else None,
            "load_average_start": load_start, "load_average_end": [round(v, 2) for v in os.getloadavg()],
            "other_match_or_test_processes_seen": runner.others_max, **figures, **page_figures}


def watch(url: str, output: RunnerOutput, args: argparse.Namespace, runner: RunnerWatch) -> dict[str, Any]:
    """Keep a page open on ``url`` until the runner's full time; sample the page's counters and Chromium's CPU."""
    game_seconds = args.half_seconds * args.halves
    with Page(url, width=args.width, height=args.height) as page:
        meter = ChromiumMeter(page.driver.service.process.pid)
        output.wait_for(r"robots ready; kick-off", KICKOFF_TIMEOUT)
        meter.sample()
        first = page.wait_for(page.stats, 30, "the page's counters")
        kickoff = time.monotonic()
        print(f"[bench] page open on {url} ({args.width} x {args.height}); kick-off", flush=True)
        fps: list[float] = []
        chromium: list[float] = []
        last, last_time = first, kickoff
        counts: list[tuple[float, int]] = [(kickoff, first["frames"])]
        shot: dict[str, Any] | None = None
        next_sample = kickoff + args.sample_period
        while output.search(r"(full time|match over) after") is None and output.process.poll() is None:
            runner.tick()
            if time.monotonic() < next_sample:
                time.sleep(0.2)
                continue
            next_sample += args.sample_period
            last, last_time = page.stats() or last, time.monotonic()
            fps.append(float(last["fps"]))
            counts.append((last_time, last["frames"]))
            chromium.append(meter.sample())
            print(f"[bench] page: {last['fps']} frames/s by its own count, {counter_rates(counts[-2:])[0]:.1f} "
                  f"frames/s over the last {args.sample_period:g} s, Chromium {chromium[-1]:.2f} cores", flush=True)
            if args.screenshot and shot is None and time.monotonic() - kickoff >= SCREENSHOT_AT * game_seconds:
                page.screenshot(args.screenshot)
                size = shrink_png(args.screenshot, args.screenshot_bytes)
                shot = {"path": str(args.screenshot), "bytes": size, "wall_after_kickoff_s":
                        round(time.monotonic() - kickoff, 1)}
                print(f"[bench] screenshot {args.screenshot}: {size / 1000:.0f} KB", flush=True)
    figures: dict[str, Any] = {"window_px": [args.width, args.height], "chromium_cpu_cores": spread(chromium),
                               "page_fps": rate_summary(fps), "page_frame_rate": rate_summary(counter_rates(counts))}
    if last_time > kickoff:  # kick-off to the last sample
        figures["page_frames"] = frame_budget(first["frames"], last["frames"], last_time - kickoff, VIEWER_RATE_HZ)
    if shot is not None:
        figures["screenshot"] = shot
    return figures


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--half-seconds", type=float, default=60.0, help="[s of game time]")
    parser.add_argument("--halves", type=int, default=2)
    parser.add_argument("--sample-period", type=float, default=5.0, help="the page's and the nodes' samples [s, wall]")
    parser.add_argument("--width", type=int, default=1280, help="the browser window [px]")
    parser.add_argument("--height", type=int, default=720, help="the browser window [px]")
    parser.add_argument("--screenshot", type=Path, help="save the page mid-match here (PNG)")
    parser.add_argument("--screenshot-bytes", type=int, default=200_000, help="the screenshot's size limit")
    args = parser.parse_args(argv)
    if args.half_seconds <= 0 or args.halves < 1 or args.sample_period <= 0:
        parser.error("--half-seconds and --sample-period must be positive, --halves at least 1")
    args.out.mkdir(parents=True, exist_ok=True)
    load_start = [round(v, 2) for v in os.getloadavg()]
    print(f"[bench] viewer: two 5 vs 5 matches of {args.halves} x {args.half_seconds:g} s at real time on "
          f"{os.cpu_count()} cores (load average {load_start})", flush=True)
    matches = {}
    for label, with_page in (("no_page", False), ("page", True)):
        print(f"[bench] viewer: match {'with a headless Chromium page open' if with_page else 'with no page open'}",
              flush=True)
        matches[label] = play(label, args, with_page)
        print(f"[bench] viewer: {label}: real-time factor {matches[label]['achieved_real_time_factor']}, viewer "
              f"{matches[label]['viewer_cpu_cores']} cores", flush=True)
    result = {
        "half_seconds": args.half_seconds, "halves": args.halves, "real_time_factor": 1.0,
        "viewer_rate_hz": VIEWER_RATE_HZ, "sample_period_s": args.sample_period,
        "machine": {"cpus": os.cpu_count(), "load_average_start": load_start,
                    "load_average_end": [round(v, 2) for v in os.getloadavg()],
                    "note": "the matches run at real time on every core; other work on the machine lowers the "
                            "real-time factor and raises the CPU figures"},
        "matches": matches,
        "page_cost": page_cost(matches["no_page"], matches["page"]),
    }
    (args.out / "viewer.json").write_text(strict_json(result, indent=2))
    plot(result, args.out / "viewer.png")
    print(f"[bench] viewer: page cost {json.dumps(result['page_cost'])}", flush=True)
    print(f"figures: {args.out / 'viewer.json'}, {args.out / 'viewer.png'}", flush=True)
    return 0 if all(m["status"] == 0 for m in matches.values()) else 1


if __name__ == "__main__":
    sys.exit(main())
