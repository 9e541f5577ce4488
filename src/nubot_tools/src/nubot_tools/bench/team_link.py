"""Benchmark the LCM team link (nubot_comm) inside network namespaces of its own: latency, delivery, CPU.

    python scripts/bench_team_link.py [--out bench/results] [--seconds 10] [--rate 100]

Requires: root (``ip netns``, ``nft``; without them it says so and writes nothing), a built workspace. Nothing
leaves the loopback of the namespaces it makes.
- Latency and delivery: two ``TeamLink`` s (nubot1 sends, nubot2 hears) on LCM's default group in one namespace;
  nubot1 sends ``--rate`` packets a second for ``--seconds`` at 0, 10 and 30 % of the datagrams dropped at random
  on input (nftables). Latency = when nubot2's link took the packet - its send stamp (one clock): p50, p99, max
  [ms]; delivery = packets taken / sent.
- CPU: one team_link node (nubot1, its roscore in the namespace) fed its world model and strategy at 30 Hz by
  ``rostopic pub``, hearing four teammates' links at 30 Hz, over ``--seconds``: cores and RSS.
- Signing: what the team key costs a packet (``nubot_comm.signing``): HMAC-SHA256 to sign and to check [us].
Provides: ``<out>/team_link.json`` and ``<out>/team_link.png`` (latency distribution per loss).
"""

from __future__ import annotations

import argparse
import tempfile
import threading
import time
from pathlib import Path

import matplotlib.pyplot as plt
import numpy as np
import psutil

from nubot_comm import netns
from nubot_comm.codec import DEFAULT_URL
from nubot_comm.link import TeamLink
from nubot_comm.signing import sign, verify
from nubot_common.json_text import strict_json
from nubot_common.processes import RosMaster, wait_until
from nubot_lcm import coach_packet_t, team_packet_t
from nubot_tools.workspace import BENCH_RESULTS

LOSSES = (0, 10, 30)  # [%] of the datagrams dropped on input
TEAMMATE_RATE = 30.0  # [Hz] a robot's packets: world_model's rate
SETTLE = 1.0  # [s] after the last packet, for stragglers


def content(agent_id: int) -> team_packet_t:
    """A packet of a robot seeing five obstacles: about the size a match gives."""
    packet = team_packet_t()
    packet.robot.AgentID = packet.strategy.AgentID = agent_id
    packet.obstacles.pos = [type(packet.robot.pos)() for _ in range(5)]
    packet.obstacles.polar_pos = [type(packet.ball.real_pos)() for _ in range(5)]
    packet.obstacles.num_pos = packet.obstacles.num_polar_pos = 5
    return packet


def measure_signing(packets: int = 20000) -> dict:
    """What the team key costs a packet: signing it (sender) and checking it (each receiver), on one core [us]."""
    data = content(1).encode()
    key = b"a team key of 32 bytes, for test"
    signed = sign(key, "NUBOT_TEAM_nubot", data)
    started = time.perf_counter()
    for _ in range(packets):
        sign(key, "NUBOT_TEAM_nubot", data)
    signing = time.perf_counter() - started
    started = time.perf_counter()
    for _ in range(packets):
        verify(key, "NUBOT_TEAM_nubot", signed)
    checking = time.perf_counter() - started
    return {"packet_bytes": len(data), "tag_bytes": len(signed) - len(data),
            "sign_us": round(signing / packets * 1e6, 2), "verify_us": round(checking / packets * 1e6, 2)}


def measure_latency(ns: netns.NetNamespace, loss: int, seconds: float, rate: float) -> dict:
    """nubot1 -> nubot2 in ``ns`` with ``loss`` % dropped: latency [ms] percentiles and delivery ratio."""
    _group, port = netns.group_of(DEFAULT_URL)
    ns.set_loss(port, loss)
    arrivals: dict[int, float] = {}

    def took(packet: team_packet_t | coach_packet_t) -> None:
        if isinstance(packet, team_packet_t):
            arrivals[packet.seq] = (time.time_ns() - packet.sent_ns) / 1e6

    with netns.entered(ns.name):
        sender = TeamLink.open(DEFAULT_URL, "nubot", 1)
        receiver = TeamLink.open(DEFAULT_URL, "nubot", 2, on_accept=took)
    receiver.start()
    sent = int(seconds * rate)
    start = time.monotonic()
    try:
        for k in range(sent):
            sender.send_team(content(1))
            time.sleep(max(start + (k + 1) / rate - time.monotonic(), 0.0))
        time.sleep(SETTLE)
    finally:
        receiver.close()
        sender.close()
        ns.set_loss(port, 0)
    latencies = np.array(sorted(arrivals.values()))
    return {"loss_percent": loss, "sent": sent, "delivered": len(latencies),
            "delivery_ratio": round(len(latencies) / sent, 4),
            "p50_ms": round(float(np.percentile(latencies, 50)), 3) if len(latencies) else None,
            "p99_ms": round(float(np.percentile(latencies, 99)), 3) if len(latencies) else None,
            "max_ms": round(float(latencies.max()), 3) if len(latencies) else None,
            "latencies_ms": [round(float(x), 4) for x in latencies]}


def measure_node_cpu(ns: netns.NetNamespace, seconds: float, logs: Path) -> dict:
    """One team_link node (nubot1) at work for ``seconds``: CPU [cores] and RSS [MiB]."""
    with netns.entered(ns.name), RosMaster(logs) as master:  # roscore and its clients inherit the namespace
        node = master.launch("team_link", ["rosrun", "nubot_comm", "team_link", "__name:=team_link", "__ns:=nubot1",
                                           "_robot:=nubot1"])
        for topic, kind, fields in (("worldmodel/teammessage", "TeamMessage",
                                     "{header: {stamp: now}, robot: {header: {stamp: now}, AgentID: 1}}"),
                                    ("nubotcontrol/strategy", "StrategyInfo", "{header: {stamp: now}, AgentID: 1}")):
            master.launch(f"feed_{kind}", ["rostopic", "pub", "-s", "-r", str(TEAMMATE_RATE), f"/nubot1/{topic}",
                                           f"nubot_common/{kind}", fields])
        from_node: list[int] = []  # seq of every packet of the node a teammate took

        def took(packet: team_packet_t | coach_packet_t) -> None:
            if isinstance(packet, team_packet_t) and packet.agent_id == 1:
                from_node.append(packet.seq)

        mates = [TeamLink.open(DEFAULT_URL, "nubot", k, on_accept=took) for k in (2, 3, 4, 5)]
        for mate in mates:
            mate.start()
        stop = threading.Event()

        def play() -> None:
            while not stop.wait(1.0 / TEAMMATE_RATE):
                for k, mate in enumerate(mates, 2):
                    mate.send_team(content(k))

        player = threading.Thread(target=play, daemon=True)
        player.start()
        try:
            process = psutil.Process(node.process.pid)
            wait_until(lambda: node.alive() and "team_link: nubot1" in node.log_text(), 30, "the team_link node")
            time.sleep(2.0)  # the feeds are up and the node sends its own packets
            before, start, heard = process.cpu_times(), time.monotonic(), len(from_node)
            time.sleep(seconds)
            after, wall, heard = process.cpu_times(), time.monotonic() - start, len(from_node) - heard
            rss = process.memory_info().rss / 2**20
            status = node.log_text()
        finally:
            stop.set()
            player.join(timeout=2.0)
            for mate in mates:
                mate.close()
    cpu = (after.user - before.user) + (after.system - before.system)
    return {"seconds": round(wall, 2), "cpu_seconds": round(cpu, 3), "cores": round(cpu / wall, 4),
            "rss_mib": round(rss, 1), "teammates": len(mates), "teammates_rate_hz": TEAMMATE_RATE,
            "node_packets_per_s": round(heard / len(mates) / wall, 1), "traceback": "Traceback" in status}


def plot(rows: list[dict], path: Path) -> None:
    fig, ax = plt.subplots(figsize=(6, 3.5))
    for row in rows:
        values = np.array(row["latencies_ms"])
        if len(values):
            ax.plot(values, np.arange(1, len(values) + 1) / len(values),
                    label=f"{row['loss_percent']} % loss: delivered {row['delivery_ratio']:.0%}, "
                          f"p99 {row['p99_ms']:.2f} ms")
    ax.set_xscale("log")
    ax.set_xlabel("latency, send stamp to the receiving link [ms]")
    ax.set_ylabel("share of the delivered packets")
    ax.set_title("LCM team link on loopback multicast (network namespace)", fontsize=9)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=100)
    plt.close(fig)


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, default=BENCH_RESULTS)
    parser.add_argument("--seconds", type=float, default=10.0, help="per loss level, and for the CPU [s]")
    parser.add_argument("--rate", type=float, default=100.0, help="packets a second for the latency [Hz]")
    args = parser.parse_args(argv)
    if not args.seconds > 0 or not args.rate > 0:
        parser.error("--seconds and --rate must be positive")
    signing = measure_signing()
    print(f"team key: {signing['sign_us']} us to sign a {signing['packet_bytes']}-byte packet, "
          f"{signing['verify_us']} us to check it", flush=True)
    why = netns.unavailable()
    if why is not None:
        print(f"[bench] team link: skipped: {why}")
        return 0
    args.out.mkdir(parents=True, exist_ok=True)
    rows = []
    with netns.NetNamespace("bench") as ns:
        for loss in LOSSES:
            print(f"[bench] team link: {args.rate:g} packets/s for {args.seconds:g} s at {loss} % loss ...", flush=True)
            rows.append(measure_latency(ns, loss, args.seconds, args.rate))
        print(f"[bench] team link: one team_link node for {args.seconds:g} s ...", flush=True)
        with tempfile.TemporaryDirectory(prefix="bench_team_link_") as logs:
            cpu = measure_node_cpu(ns, args.seconds, Path(logs))
    result = {"url": DEFAULT_URL, "rate_hz": args.rate, "seconds": args.seconds,
              "latency": [{k: v for k, v in row.items() if k != "latencies_ms"} for row in rows], "node": cpu,
              "signing": signing}
    (args.out / "team_link.json").write_text(strict_json(result, indent=2))
    plot(rows, args.out / "team_link.png")
    for row in result["latency"]:
        print(f"loss {row['loss_percent']:>2} %: delivered {row['delivered']}/{row['sent']} "
              f"({row['delivery_ratio']:.1%}), latency p50 {row['p50_ms']} ms, p99 {row['p99_ms']} ms, "
              f"max {row['max_ms']} ms")
    print(f"team_link node (nubot1, 4 teammates at {TEAMMATE_RATE:g} Hz): {cpu['cores'] * 100:.1f} % of a core, "
          f"RSS {cpu['rss_mib']} MiB over {cpu['seconds']} s, sending {cpu['node_packets_per_s']} packets/s")
    print(f"figures: {args.out / 'team_link.json'}, {args.out / 'team_link.png'}")
    return 0
