"""A hostile peer against a team link, over real LCM: run both sides inside a network namespace of their own (the
tests' hostile-peer suite and ``make bench``'s probe do), never on a real network.

``python -m nubot_comm.probe team SECONDS`` holds two teams' links for SECONDS: nubot (signed with ``KEY``) and rival
(unsigned), robot 2 of each sending x = 2.0 thirty times a second, robot 1 of each listening; it prints ``up`` when
ready and, at the end, a JSON line: per team, what robot 1 heard of robot 2 each cycle and its drop counts.
``python -m nubot_comm.probe attack COUNT`` listens to the signed team for a second (to replay and alter what it
hears), then sends COUNT datagrams of each case of ``CASES`` and prints how many it captured.
"""

from __future__ import annotations

import json
import sys
import time
from collections.abc import Callable

from nubot_comm.codec import DEFAULT_URL
from nubot_comm.link import TeamLink
from nubot_lcm import team_packet_t

KEY = b"the nubot team's key, 32 bytes!!"
MAX_AGE = 0.5  # [s] the probed links' max_age
PACE = 0.002  # [s] between two of the attacker's datagrams
GENUINE_X, FORGED_X = 2.0, 99.0
CASES = ("forged_unsigned", "forged_bad_tag", "altered", "replayed", "oversize", "garbage", "huge_value",
         "future_hour", "old_hour", "future_30s")


def content(agent: int, x: float) -> team_packet_t:
    packet = team_packet_t()
    packet.robot.AgentID = packet.strategy.AgentID = agent
    packet.robot.pos.x = x
    return packet


def team(seconds: float) -> dict:
    links = {(t, k): TeamLink.open(DEFAULT_URL, t, k, key=KEY if t == "nubot" else None, max_age=MAX_AGE)
             for t in ("nubot", "rival") for k in (1, 2)}
    for link in links.values():
        link.start()
    print("up", flush=True)
    heard: dict[str, list[list[float]]] = {"nubot": [], "rival": []}
    end = time.monotonic() + seconds
    while time.monotonic() < end:
        for name in ("nubot", "rival"):
            links[(name, 2)].send_team(content(2, GENUINE_X))
            heard[name].append([p.robot.pos.x for p in links[(name, 1)].teammates() if p.agent_id == 2])
        time.sleep(1 / 30)
    out = {name: {"heard": heard[name],
                  "dropped": {r.value: n for r, n in links[(name, 1)].stats().dropped.items() if n}}
           for name in ("nubot", "rival")}
    for link in links.values():
        link.close()
    return out


def _forged(name: str, session: int, sent_ns: int, x: float = FORGED_X) -> bytes:
    packet = content(2, x)
    packet.team, packet.agent_id, packet.session, packet.seq, packet.sent_ns = name, 2, session, 0, sent_ns
    return packet.encode()


def attack(count: int) -> int:
    import lcm

    bus = lcm.LCM(DEFAULT_URL)
    captured: list[bytes] = []
    bus.subscribe("NUBOT_TEAM_nubot", lambda _channel, data: captured.append(data))
    until = time.monotonic() + 1.0
    while time.monotonic() < until:
        bus.handle_timeout(50)
    now = time.time_ns()
    signed, unsigned = "NUBOT_TEAM_nubot", "NUBOT_TEAM_rival"
    cases: dict[str, tuple[str, Callable[[int], bytes]]] = {
        "forged_unsigned": (signed, lambda k: _forged("nubot", 100 + k, now)),
        "forged_bad_tag": (signed, lambda k: _forged("nubot", 100 + k, now) + bytes(32)),
        "altered": (signed, lambda k: _flip(captured[k % len(captured)], k)),
        "replayed": (signed, lambda k: captured[k % len(captured)]),
        "oversize": (unsigned, lambda k: bytes(3000)),
        "garbage": (unsigned, lambda k: bytes((k * 7 + i) % 256 for i in range(64))),
        "huge_value": (unsigned, lambda k: _forged("rival", 200 + k, now, x=1e30)),
        "future_hour": (unsigned, lambda k: _forged("rival", 300 + k, now + 3600 * 10**9)),
        "old_hour": (unsigned, lambda k: _forged("rival", 400 + k, now - 3600 * 10**9)),
        "future_30s": (unsigned, lambda k: _forged("rival", 500, now + 30 * 10**9)),
    }
    for case in CASES:
        channel, make = cases[case]
        for k in range(count if case != "future_30s" else 1):
            bus.publish(channel, make(k))
            time.sleep(PACE)  # the receivers' socket buffers are not what is probed
    return len(captured)


def _flip(datagram: bytes, k: int) -> bytes:
    at = len(datagram) - 40 - k % 20
    return datagram[:at] + bytes([datagram[at] ^ 1]) + datagram[at + 1:]


def longest_run(heard: list[list[float]], value: float) -> int:
    """The most consecutive cycles robot 1 heard ``value`` from robot 2."""
    best = run = 0
    for xs in heard:
        run = run + 1 if xs == [value] else 0
        best = max(best, run)
    return best


def main(argv: list[str]) -> int:
    if len(argv) != 2 or argv[0] not in ("team", "attack"):
        print("usage: python -m nubot_comm.probe team SECONDS | attack COUNT", file=sys.stderr)
        return 2
    if argv[0] == "team":
        print(json.dumps(team(float(argv[1]))), flush=True)
    else:
        print(attack(int(argv[1])), flush=True)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
