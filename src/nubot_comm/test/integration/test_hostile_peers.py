"""The team link against a hostile peer on the team's network, over real LCM multicast inside a network namespace of
its own (root only): ``nubot_comm.probe``'s forged, badly signed, altered, replayed, oversized, garbage, absurd and
far-stamped datagrams from another process, against a signed team (nubot, the team key) and an unsigned one
(rival). Each case's outcome is what a robot hears afterwards. (``make bench`` runs the same probe, larger.)"""

from __future__ import annotations

import json
import subprocess
import sys

import pytest

from nubot_comm import netns
from nubot_comm.probe import FORGED_X, GENUINE_X, MAX_AGE, longest_run

pytestmark = [pytest.mark.integration,
              pytest.mark.skipif(netns.unavailable() is not None, reason=str(netns.unavailable()))]
PER_CASE = 20


def test_forged_replayed_altered_and_far_stamped_datagrams_leave_the_team_playing():
    with netns.NetNamespace("hostile") as ns:
        team = subprocess.Popen(ns.command(sys.executable, "-m", "nubot_comm.probe", "team", "2.5"),
                                stdout=subprocess.PIPE, text=True)
        try:
            assert team.stdout.readline().strip() == "up"
            attacker = subprocess.run(ns.command(sys.executable, "-m", "nubot_comm.probe", "attack", str(PER_CASE)),
                                      capture_output=True, text=True, timeout=60)
            assert attacker.returncode == 0, attacker.stderr[-2000:]
            assert int(attacker.stdout) >= PER_CASE, "the attacker heard the signed team's datagrams to replay"
            out = json.loads(team.communicate(timeout=60)[0].strip().splitlines()[-1])
        finally:
            if team.poll() is None:
                team.kill()
    signed, unsigned = out["nubot"], out["rival"]
    # The signed team hears only its teammate: forged, badly tagged and altered datagrams are 'signature', the
    # replayed ones 'duplicate' or 'stale'.
    assert all(xs in ([], [GENUINE_X]) for xs in signed["heard"]) and signed["heard"][-1] == [GENUINE_X]
    assert signed["dropped"].get("signature", 0) >= 3 * PER_CASE
    assert signed["dropped"].get("duplicate", 0) + signed["dropped"].get("stale", 0) >= PER_CASE
    # The unsigned team: oversize, garbage, absurd values and far stamps each counted; the session forged within the
    # clocks' tolerance is taken and holds the teammate's own packets back for max_age at most.
    dropped = unsigned["dropped"]
    assert dropped.get("oversize", 0) >= PER_CASE and dropped.get("invalid", 0) >= PER_CASE
    assert dropped.get("clock", 0) >= 2 * PER_CASE
    assert dropped.get("foreign_type", 0) + dropped.get("malformed", 0) >= PER_CASE
    assert unsigned["heard"][-1] == [GENUINE_X]
    assert longest_run(unsigned["heard"], FORGED_X) <= (MAX_AGE + 0.3) * 30
