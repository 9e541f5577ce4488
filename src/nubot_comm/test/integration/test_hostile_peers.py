"""The team link against a hostile peer on the team's network, over real LCM multicast inside a network namespace of
its own (root only): forged, replayed, altered and far-stamped datagrams sent by another process, against a signed
team (nubot, the team key) and an unsigned one (rival). Each case's outcome is what a robot hears afterwards."""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from nubot_comm import netns

pytestmark = [pytest.mark.integration,
              pytest.mark.skipif(netns.unavailable() is not None, reason=str(netns.unavailable()))]

ROBOTS = r'''
import json, sys, threading, time
from nubot_comm.codec import DEFAULT_URL
from nubot_comm.link import TeamLink
from nubot_lcm import team_packet_t

KEY = b"the nubot team's key, 32 bytes!!"

def content(agent, x):
    p = team_packet_t()
    p.robot.AgentID = p.strategy.AgentID = agent
    p.robot.pos.x = x
    return p

links = {("nubot", 1): TeamLink.open(DEFAULT_URL, "nubot", 1, key=KEY, max_age=0.5),
         ("nubot", 2): TeamLink.open(DEFAULT_URL, "nubot", 2, key=KEY, max_age=0.5),
         ("rival", 1): TeamLink.open(DEFAULT_URL, "rival", 1, max_age=0.5),
         ("rival", 2): TeamLink.open(DEFAULT_URL, "rival", 2, max_age=0.5)}
for link in links.values():
    link.start()
print("up", flush=True)
heard = {"nubot": [], "rival": []}
end = time.monotonic() + float(sys.argv[1])
while time.monotonic() < end:  # robot 2 of each team sends x = 2.0, 30 times a second
    for team in ("nubot", "rival"):
        links[(team, 2)].send_team(content(2, 2.0))
        heard[team].append([p.robot.pos.x for p in links[(team, 1)].teammates() if p.agent_id == 2])
    time.sleep(1 / 30)
out = {team: {"heard": heard[team],
              "dropped": {r.value: n for r, n in links[(team, 1)].stats().dropped.items() if n}}
       for team in ("nubot", "rival")}
for link in links.values():
    link.close()
print(json.dumps(out), flush=True)
'''

ATTACKER = r'''
import sys, time
import lcm
from nubot_comm.codec import DEFAULT_URL
from nubot_lcm import team_packet_t

bus = lcm.LCM(DEFAULT_URL)
captured = []
bus.subscribe("NUBOT_TEAM_nubot", lambda channel, data: captured.append(data))
until = time.monotonic() + 1.0
while time.monotonic() < until:  # listen to the signed team for a second
    bus.handle_timeout(50)
now = time.time_ns()

def forged(team, session, sent_ns, x=99.0):
    p = team_packet_t()
    p.team, p.agent_id, p.session, p.seq, p.sent_ns = team, 2, session, 0, sent_ns
    p.robot.AgentID = p.strategy.AgentID = 2
    p.robot.pos.x = x
    return p.encode()

cases = {"forged_unsigned": ("NUBOT_TEAM_nubot", [forged("nubot", 11, now)] * 20),
         "forged_bad_tag": ("NUBOT_TEAM_nubot", [forged("nubot", 12, now) + bytes(32)] * 20),
         "altered": ("NUBOT_TEAM_nubot", [c[:-40] + bytes([c[-40] ^ 1]) + c[-39:] for c in captured[:20]]),
         "replayed": ("NUBOT_TEAM_nubot", captured[:20]),
         "future_hour": ("RIVAL_TEAM", [forged("rival", 13, now + 3600 * 10**9)] * 20),
         "old_hour": ("RIVAL_TEAM", [forged("rival", 14, now - 3600 * 10**9)] * 20),
         "future_30s": ("RIVAL_TEAM", [forged("rival", 15, now + 30 * 10**9)])}
for name, (channel, datagrams) in cases.items():
    channel = "NUBOT_TEAM_rival" if channel == "RIVAL_TEAM" else channel
    for data in datagrams:
        bus.publish(channel, data)
        time.sleep(0.002)
print(len(captured), flush=True)
'''


def test_forged_replayed_altered_and_far_stamped_datagrams_leave_the_team_playing(tmp_path):
    with netns.NetNamespace("hostile") as ns:
        robots = subprocess.Popen(ns.command(sys.executable, "-c", ROBOTS, "4.0"), stdout=subprocess.PIPE, text=True)
        try:
            assert robots.stdout.readline().strip() == "up"
            attacker = subprocess.run(ns.command(sys.executable, "-c", ATTACKER), capture_output=True, text=True,
                                      timeout=60)
            assert attacker.returncode == 0, attacker.stderr[-2000:]
            assert int(attacker.stdout) >= 20, "the attacker heard the signed team's datagrams to replay"
            out = json.loads(robots.communicate(timeout=60)[0].strip().splitlines()[-1])
        finally:
            if robots.poll() is None:
                robots.kill()
    signed, unsigned = out["nubot"], out["rival"]
    # The signed team never heard anything but its teammate's own packets: 20 forged, 20 with a bad tag and 20
    # altered are 'signature', the 20 replayed 'duplicate' (or 'stale').
    assert all(xs in ([], [2.0]) for xs in signed["heard"]) and signed["heard"][-1] == [2.0]
    assert signed["dropped"].get("signature", 0) >= 60
    assert signed["dropped"].get("duplicate", 0) + signed["dropped"].get("stale", 0) >= 20
    # The unsigned team: the hour-ahead and hour-old stamps are 'clock'; the one forged within the clocks' tolerance
    # is taken, and holds the teammate's own packets back for max_age (0.5 s) at most: it is heard at the end.
    assert unsigned["dropped"].get("clock", 0) >= 40
    assert unsigned["heard"][-1] == [2.0]
    forged_run = [i for i, xs in enumerate(unsigned["heard"]) if xs == [99.0]]
    assert len(forged_run) <= 0.8 * 30, f"the forged session held the teammate out for {len(forged_run)} cycles"
