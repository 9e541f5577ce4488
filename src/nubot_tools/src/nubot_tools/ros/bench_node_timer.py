"""Benchmark what a periodic cycle costs a rospy node on sim time, with nothing else to do.

    python scripts/bench_node_timer.py [--out bench/results] [--nodes 20] [--seconds 20] [--repeats 3]

A 5 vs 5 match runs 10 such cycles at 33 Hz (each robot's node; 20 with ``--processes two``: world_model at 30 Hz,
nubot_control at 33 Hz) against a /clock of 100 Hz. Here ``--nodes`` idle rospy nodes take a /clock of
``--clock-rate`` Hz published by this process, in three kinds, measured in turn ``--repeats`` times for
``--seconds`` each:
- ``clock only``: no cycle; what the /clock deliveries alone cost;
- ``rospy.Timer``: a 33 Hz cycle that does nothing, on rospy's timer (its thread wakes at every /clock);
- ``node_io.timer``: the same cycle on the workspace's timer (its thread wakes only when a cycle is due).
Provides: ``<out>/node_timer.json`` (CPU per node [% of a core] and per /clock message [us], each run) and
``<out>/node_timer.png``.
"""

from __future__ import annotations

import argparse
import statistics
import sys
import tempfile
import threading
import time
from pathlib import Path

import matplotlib.pyplot as plt
import psutil
import rospy
from rosgraph_msgs.msg import Clock

from nubot_common.json_text import strict_json
from nubot_common.node_io import publisher
from nubot_common.processes import RosMaster, wait_until
from nubot_tools.workspace import BENCH_RESULTS

CYCLE_HZ = 33.0  # nubot_control's rate
KINDS = ("clock only", "rospy.Timer", "node_io.timer")
NODE = """
import sys, rospy
from nubot_common.node_io import timer
kind, hz = sys.argv[1], float(sys.argv[2])
rospy.init_node("timed", anonymous=True)
cycles = []
if kind == "rospy.Timer":
    rospy.Timer(rospy.Duration(1.0 / hz), cycles.append)
elif kind == "node_io.timer":
    timer(1.0 / hz, cycles.append)
print("up", flush=True)
rospy.spin()
"""


def measure(master: RosMaster, kind: str, nodes: int, seconds: float) -> float:
    """CPU [core-seconds] the ``nodes`` nodes of ``kind`` took over ``seconds`` of wall time."""
    launched = [master.launch(f"{kind.replace(' ', '_')}_{i}", [sys.executable, "-c", NODE, kind, str(CYCLE_HZ)])
                for i in range(nodes)]
    try:
        wait_until(lambda: all("up" in n.log_text() for n in launched), 60, f"{nodes} nodes up")
        time.sleep(2.0)  # connected to /clock
        processes = [psutil.Process(n.process.pid) for n in launched]
        before = [p.cpu_times() for p in processes]
        time.sleep(seconds)
        after = [p.cpu_times() for p in processes]
    finally:
        for node in launched:
            node.interrupt()
        for node in launched:
            node.stop()
    return sum((a.user - b.user) + (a.system - b.system) for a, b in zip(after, before))


def run(nodes: int, seconds: float, repeats: int, clock_rate: float) -> dict:
    with tempfile.TemporaryDirectory() as logs, RosMaster(Path(logs)) as master:
        master.use_in_this_process()
        rospy.init_node("bench_node_timer", disable_signals=True)
        rospy.set_param("/use_sim_time", True)  # for the nodes started from now on (this one keeps wall time)
        clock, stop = publisher("/clock", Clock), threading.Event()

        def tick() -> None:
            period, t, due = 1.0 / clock_rate, 0.0, time.monotonic()
            while not stop.is_set():
                t += period
                clock.publish(Clock(rospy.Time.from_sec(t)))
                due += period
                time.sleep(max(0.0, due - time.monotonic()))

        ticker = threading.Thread(target=tick, daemon=True)
        ticker.start()
        runs: dict[str, list[float]] = {k: [] for k in KINDS}
        try:
            for r in range(repeats):
                for kind in KINDS:
                    cpu = measure(master, kind, nodes, seconds)
                    runs[kind].append(cpu / seconds / nodes)
                    print(f"[bench] run {r + 1}/{repeats}, {kind}: {100 * runs[kind][-1]:.2f} % of a core per node",
                          flush=True)
        finally:
            stop.set()
            ticker.join(timeout=2.0)
            rospy.signal_shutdown("bench done")
    summary = {}
    for kind, shares in runs.items():
        median = statistics.median(shares)
        summary[kind] = {"percent_core_per_node": [round(100 * s, 3) for s in shares],
                         "median_percent_core_per_node": round(100 * median, 3),
                         "median_us_per_clock_message": round(1e6 * median / clock_rate, 1)}
    base = statistics.median(runs["clock only"])
    for kind in KINDS[1:]:
        summary[kind]["median_cycle_cost_percent_core_per_node"] = round(100 * (statistics.median(runs[kind]) - base),
                                                                         3)
    return {"nodes": nodes, "seconds": seconds, "repeats": repeats, "clock_rate_hz": clock_rate, "cycle_hz": CYCLE_HZ,
            "kinds": summary}


def plot(result: dict, path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for i, kind in enumerate(KINDS):
        shares = result["kinds"][kind]["percent_core_per_node"]
        ax.bar(i, result["kinds"][kind]["median_percent_core_per_node"], color="0.8")
        ax.plot([i] * len(shares), shares, "o", color="tab:blue")
    ax.set_xticks(range(len(KINDS)), KINDS)
    ax.set_ylabel("% of a core per node")
    ax.set_title(f"{result['nodes']} idle nodes, /clock at {result['clock_rate_hz']:.0f} Hz, "
                 f"cycle {result['cycle_hz']:.0f} Hz")
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--nodes", type=int, default=20)
    parser.add_argument("--seconds", type=float, default=20.0)
    parser.add_argument("--repeats", type=int, default=3)
    parser.add_argument("--clock-rate", type=float, default=100.0)
    args = parser.parse_args(argv)
    if args.nodes < 1 or args.seconds <= 0 or args.repeats < 1 or args.clock_rate <= 0:
        parser.error("--nodes, --seconds, --repeats and --clock-rate must be positive")
    result = run(args.nodes, args.seconds, args.repeats, args.clock_rate)
    args.out.mkdir(parents=True, exist_ok=True)
    (args.out / "node_timer.json").write_text(strict_json(result, indent=2))
    plot(result, args.out / "node_timer.png")
    for kind in KINDS:
        k = result["kinds"][kind]
        print(f"{kind:14s} {k['median_percent_core_per_node']:.2f} % of a core per node "
              f"({k['median_us_per_clock_message']:.0f} us per /clock message)")
    print(f"figures: {args.out / 'node_timer.json'}, {args.out / 'node_timer.png'}")
    return 0
