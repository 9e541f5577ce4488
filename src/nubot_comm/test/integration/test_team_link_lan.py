"""team_link nodes over real LCM multicast, only ever inside network namespaces these tests make (root only).

One LAN: the links of nubot1..3 and rival1..2 and nubot's coach share one namespace, one roscore and one group;
then 3,000 malformed, oversized and foreign datagrams (make bench's hostile probe sends 10,000 more). Two LANs:
nubot1 and nubot2 in one namespace, nubot3 in another (each with its own roscore), joined by a relay that delays
every datagram 50 ms, and 30 % of the datagrams dropped on the way into each. ``ns_team.py`` plays the robots
and watches the links inside a namespace.
"""

from __future__ import annotations

import json
import statistics
import subprocess
import sys
from pathlib import Path

import pytest

from nubot_comm import netns
from nubot_comm.codec import DEFAULT_URL

pytestmark = [pytest.mark.integration,
              pytest.mark.skipif(netns.unavailable() is not None, reason=str(netns.unavailable()))]

DRIVER = Path(__file__).with_name("ns_team.py")
TABLE = Path(__file__).resolve().parents[4] / "docs" / "topics.md"
FRESH = 0.3  # [s] teammate data older than this is invalid (NUBOT_FACTS)
CONTENT_REASONS = ("oversize", "foreign_type", "malformed", "invalid")
FUZZ = 3_000


def drive(ns: netns.NetNamespace, out: Path, *args: str) -> subprocess.Popen:
    log = open(out.with_suffix(".log"), "wb")  # noqa: SIM115 - the child writes it; closed with the process
    return subprocess.Popen(ns.command(sys.executable, str(DRIVER), "--out", str(out), *args), stdout=log,
                            stderr=subprocess.STDOUT, stdin=subprocess.DEVNULL)


def finish(process: subprocess.Popen, out: Path, timeout: float = 90.0) -> dict:
    process.wait(timeout=timeout)
    if not out.exists():
        raise AssertionError(f"{DRIVER.name} wrote nothing:\n{out.with_suffix('.log').read_text()[-5000:]}")
    result = json.loads(out.read_text())
    assert "error" not in result, f"{result['error']}:\n{result.get('log', '')[-5000:]}"
    return result


def assert_graph_matches_the_topic_table(publishers: dict[str, list[str]], robot: str) -> None:
    """``robot``'s graph (alone on its roscore, as on a real robot) has the producers docs/topics.md names."""
    text = TABLE.read_text().split("## Topics of a real robot's team link")[1].split("## ")[0]
    rows = [[c.strip().strip("`") for c in line.strip("|").split("|")] for line in text.splitlines()
            if line.startswith("| `/")]
    team = robot.rstrip("0123456789")
    assert len(rows) == 4
    for topic, _type, producer, *_ in rows:
        name = topic.replace("<r>", robot).replace("<T>", team)
        assert publishers.get(name) == [producer.replace("<r>", robot)], f"{name}: {publishers.get(name)}"


def drops(status: dict) -> dict[str, int]:
    return dict(zip(status["drop_reasons"], status["drop_counts"]))


@pytest.fixture(scope="module")
def one_lan(tmp_path_factory):
    """Two teams' links and nubot's coach on one group, 3 s of play, 3,000 bad datagrams, 2 s of play again."""
    out = tmp_path_factory.mktemp("one_lan") / "result.json"
    with netns.NetNamespace("lan") as ns:
        driver = drive(ns, out, "--links", "nubot1,nubot2,nubot3,rival1,rival2", "--coach",
                       "nubot:/nubot/coach_commands", "--feed", "nubot1,nubot2,nubot3,rival1,rival2",
                       "--expect", "nubot=1,2,3;rival=1,2", "--seconds", "3", "--fuzz", str(FUZZ))
        return finish(driver, out)


def test_every_link_publishes_its_whole_team_fresh(one_lan):
    for team, links in (("nubot", (1, 2, 3)), ("rival", (1, 2))):
        for k in links:
            samples = one_lan["measure"][f"/{team}{k}/team_link"]
            assert sorted(samples) == [str(a) for a in links], f"{team}{k} publishes {sorted(samples)}"
            for agent, ages in samples.items():
                assert len(ages) >= 75, f"{team}{k} published its teammates {len(ages)} times in 3 s, not ~90"
                assert None not in ages and max(ages) < FRESH, f"{team}{k} on {team}{agent}: up to {max(ages):.3f} s"


def test_the_published_messages_carry_what_each_robot_sent(one_lan):
    for k in (1, 2, 3):
        team = one_lan["last_team"][f"/nubot{k}/team_link"]["messages"]
        assert [m["robot"]["AgentID"] for m in team] == [1, 2, 3]
        for agent, m in zip((1, 2, 3), team):
            assert (m["robot"]["pos"]["x"], m["robot"]["pos"]["y"], m["robot"]["current_role"]) == (agent + 0.25, 1.5,
                                                                                                     agent)
            assert (m["ball"]["pos"]["x"], m["ball"]["pos_known"]) == (agent, True)
            assert [p["x"] for p in m["obstacles"]["pos"]] == [agent, agent + 1, agent + 2]
            assert [p["radius"] for p in m["obstacles"]["polar_pos"]] == [4.0, 5.0, 6.0]
            assert m["header"]["stamp"] == m["robot"]["header"]["stamp"] > 0
        strategies = one_lan["last_strategy"][f"/nubot{k}/team_link"]["strategy_msgs"]
        assert [(s["AgentID"], s["role"], s["pass_cmd"]["catch_id"], s["pass_cmd"]["catch_pt"]["x"], s["role_time"])
                for s in strategies] == [(a, a, a, 6.0, 0.5) for a in (1, 2, 3)]


def test_two_teams_on_one_group_stay_apart_and_count_each_others_packets(one_lan):
    for link, message in one_lan["last_team"].items():
        positive = link.startswith("/nubot")
        for m in message["messages"]:
            assert (m["robot"]["pos"]["y"] > 0) == positive, f"{link} publishes a robot of the other team"
    for topic, status in one_lan["status"].items():
        assert drops(status)["foreign_channel"] > 0, f"{topic} never heard the other team"
        assert drops(status)["foreign_team"] == 0


def test_the_coachs_commands_reach_its_robots_only(one_lan):
    assert sorted(one_lan["coach"]) == ["/nubot1/team_link", "/nubot2/team_link", "/nubot3/team_link"]
    for link, commands in one_lan["coach"].items():
        assert one_lan["coach_count"][link] >= 30, f"{link} published {one_lan['coach_count'][link]} commands"
        last = commands[-1]
        assert (last["MatchMode"], last["MatchType"], last["angleA"], last["kickforce"], last["pointA"]["x"]) == \
            (10, 0, -45, 7, 1.5)
    coach = one_lan["status"]["/nubot/team_link/status"]
    assert coach["agent_id"] == 0 and coach["sent"] > 10 and coach["members_heard"] == [1, 2, 3]


def test_the_links_report_their_counters(one_lan):
    for k in (1, 2, 3):
        status = one_lan["status"][f"/nubot{k}/team_link/status"]
        assert (status["team"], status["agent_id"], status["members_heard"]) == ("nubot", k, [1, 2, 3])
        assert status["sent"] > 60 and status["echoes"] > 0 and status["accepted"] > 2 * 60
        assert status["dropped"] == sum(status["drop_counts"])


def test_three_thousand_bad_datagrams_are_counted_and_the_team_plays_on(one_lan):
    sent = one_lan["fuzz_sent"]
    assert sum(sent["by_kind"].values()) == FUZZ and 60_000 < sent["largest"] <= 65_000
    for topic, before in one_lan["status"].items():
        after = one_lan["status_after_fuzz"][topic]
        team = after["team"]
        counted = sum(drops(after)[r] - drops(before)[r] for r in CONTENT_REASONS)
        expected = sent["content_by_team"][team]
        # what the kernel dropped before the link could read it (its buffer full on a busy machine) is not the link's
        lost = one_lan["kernel_drops_after_fuzz"][topic] - one_lan["kernel_drops"][topic]
        assert lost < 0.2 * expected, f"{topic}: the kernel dropped {lost} datagrams at the link's socket"
        assert 0.97 * expected - lost <= counted <= expected, \
            f"{topic} counted {counted} of the {expected} bad datagrams ({lost} dropped by the kernel)"
        assert all(drops(after)[r] - drops(before)[r] > 0 for r in CONTENT_REASONS), drops(after)
    assert one_lan["alive"] and "Traceback" not in one_lan["log"]
    for link, samples in one_lan["after_fuzz"].items():
        for agent, ages in samples.items():
            assert len(ages) >= 45 and None not in ages and max(ages) < FRESH, f"{link} on {agent} after the fuzz"


def test_with_30_percent_loss_and_50_ms_delay_each_robot_sees_each_teammate_fresh(tmp_path):
    group, port = netns.group_of(DEFAULT_URL)
    with netns.NetNamespace("a") as a, netns.NetNamespace("b") as b:
        for ns in (a, b):
            ns.set_loss(port, 30)
        with netns.DelayRelay([a.name, b.name], DEFAULT_URL, delay=0.05) as relay:
            common = ("--expect", "nubot=1,2,3", "--seconds", "7")
            left = drive(a, tmp_path / "a.json", "--links", "nubot1,nubot2", "--feed", "nubot1,nubot2", *common)
            right = drive(b, tmp_path / "b.json", "--links", "nubot3", "--feed", "nubot3", *common)
            results = [finish(left, tmp_path / "a.json"), finish(right, tmp_path / "b.json")]
            assert relay.forwarded > 0
    report = []
    for result in results:
        for link, samples in result["measure"].items():
            own = link.split("/")[1][-1]
            for agent, ages in samples.items():
                if agent == own:
                    continue
                fresh = sum(a is not None and a < FRESH for a in ages) / len(ages)
                known = [a for a in ages if a is not None]
                report.append((link, agent, fresh, statistics.median(known), min(known)))
                assert len(ages) >= 175, f"{link} published {len(ages)} times in 7 s"
                assert fresh >= 0.9, f"{link} saw nubot{agent} fresh {fresh:.0%} of the time"
                if {own, agent} & {"3"}:  # across the relay: never faster than its delay
                    assert min(known) >= 0.05, f"{link} heard nubot{agent} {min(known) * 1000:.0f} ms after it sent"
    print("\n".join(f"{link} on nubot{agent}: fresh {fresh:.1%}, median age {median * 1000:.0f} ms, "
                    f"min {low * 1000:.0f} ms" for link, agent, fresh, median, low in report))
    assert_graph_matches_the_topic_table(results[1]["publishers"], "nubot3")
    a_status = results[0]["status"]["/nubot1/team_link/status"]
    b_status = results[1]["status"]["/nubot3/team_link/status"]
    others_sent = results[0]["status"]["/nubot2/team_link/status"]["sent"] + b_status["sent"]
    assert 0.4 < a_status["accepted"] / others_sent < 0.85, "about 70 % of nubot2's packets, 49 % of nubot3's"
