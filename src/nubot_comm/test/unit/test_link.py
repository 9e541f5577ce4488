"""TeamLink over LCM's in-process provider (memq://): what it keeps, what it drops and counts, and why."""

from __future__ import annotations

import math
import time

import lcm
import pytest

from nubot_comm import NubotCommError
from nubot_comm.codec import MAX_PACKET_BYTES, decode_team
from nubot_comm.link import TeamLink
from nubot_comm.signing import verify
from nubot_lcm import coach_info_t, coach_packet_t, team_packet_t


class Clock:
    def __init__(self) -> None:
        self.now = 100.0

    def __call__(self) -> float:
        return self.now


@pytest.fixture
def bus():
    """One in-process LCM: every link made on it hears every other one."""
    return lcm.LCM("memq://")


def content(agent_id: int, x: float = 1.0) -> team_packet_t:
    packet = team_packet_t()
    packet.robot.AgentID = packet.strategy.AgentID = agent_id
    packet.robot.pos.x = x
    return packet


def pump(bus) -> None:
    """Deliver everything published so far."""
    while bus.handle_timeout(0) > 0:
        pass


def dropped(link: TeamLink) -> dict[str, int]:
    return {reason.value: n for reason, n in link.stats().dropped.items() if n}


def test_teammates_hear_each_other_and_each_keeps_its_own_packet(bus):
    links = [TeamLink(bus, "nubot", k) for k in (1, 2, 3)]
    for k, link in enumerate(links, 1):
        link.send_team(content(k, x=10.0 * k))
    pump(bus)
    for link in links:
        assert [(p.agent_id, p.robot.pos.x) for p in link.teammates()] == [(1, 10.0), (2, 20.0), (3, 30.0)]
        stats = link.stats()
        assert (stats.sent, stats.heard, stats.accepted, stats.echoes, stats.total_dropped) == (1, 3, 2, 1, 0)


def test_the_envelope_numbers_each_senders_packets_within_its_session(bus):
    link = TeamLink(bus, "nubot", 4, session=77, wall_ns=lambda: 123)
    sent = [link.send_team(content(4)) for _ in range(3)]
    assert [(p.team, p.agent_id, p.session, p.seq, p.sent_ns) for p in sent] == [("nubot", 4, 77, s, 123)
                                                                                for s in range(3)]


def test_the_latest_packet_of_a_member_replaces_the_one_before(bus):
    a, b = TeamLink(bus, "nubot", 1), TeamLink(bus, "nubot", 2)
    a.send_team(content(1, x=1.0))
    a.send_team(content(1, x=2.0))
    pump(bus)
    assert [p.robot.pos.x for p in b.teammates() if p.agent_id == 1] == [2.0]


def test_a_member_not_heard_from_within_max_age_is_left_out(bus):
    clock = Clock()
    a, b = TeamLink(bus, "nubot", 1), TeamLink(bus, "nubot", 2, max_age=0.3, clock=clock)
    a.send_team(content(1))
    pump(bus)
    clock.now += 0.3
    assert [p.agent_id for p in b.teammates()] == [1]
    clock.now += 0.01
    assert b.teammates() == []


def test_another_teams_channel_is_counted_and_kept_apart(bus):
    nubot, rival = TeamLink(bus, "nubot", 1), TeamLink(bus, "rival", 1)
    nubot.send_team(content(1, x=1.0))
    rival.send_team(content(1, x=-1.0))
    pump(bus)
    assert [p.robot.pos.x for p in nubot.teammates()] == [1.0]
    assert [p.robot.pos.x for p in rival.teammates()] == [-1.0]
    assert dropped(nubot) == dropped(rival) == {"foreign_channel": 1}


def test_a_packet_naming_another_team_on_our_channel_is_foreign_team(bus):
    link = TeamLink(bus, "nubot", 1)
    impostor = TeamLink(bus, "rival", 2)
    packet = content(2)
    impostor._envelope(packet)  # a rival envelope, sent on nubot's channel
    packet.agent_id = 2
    bus.publish("NUBOT_TEAM_nubot", packet.encode())
    pump(bus)
    assert link.teammates() == [] and dropped(link) == {"foreign_team": 1}


@pytest.mark.parametrize(("channel", "data", "reason"), [
    ("NUBOT_TEAM_nubot", b"\x01" * 40, "foreign_type"),
    ("NUBOT_TEAM_nubot", b"", "foreign_type"),
    ("NUBOT_COACH_nubot", b"\x00" * 12, "foreign_type"),
    ("NUBOT_TEAM_nubot", b"\x00" * (MAX_PACKET_BYTES + 1), "oversize"),
    ("NUBOT_TEAM_nubot", team_packet_t._get_packed_fingerprint() + b"\x00" * 5, "malformed"),
    ("SOMETHING_ELSE", b"hello", "foreign_channel"),
], ids=["random", "empty", "coach_zeros", "oversize", "truncated", "other_channel"])
def test_what_is_no_packet_of_ours_is_counted_under_its_reason_and_never_raises(bus, channel, data, reason):
    link = TeamLink(bus, "nubot", 1)
    bus.publish(channel, data)
    pump(bus)
    assert dropped(link) == {reason: 1} and link.stats().heard == 1


def test_an_invalid_packet_is_counted_and_not_kept(bus):
    link, sender = TeamLink(bus, "nubot", 1), TeamLink(bus, "nubot", 2)
    packet = sender.send_team(content(2))
    packet.seq += 1
    packet.robot.pos.y = math.nan
    bus.publish("NUBOT_TEAM_nubot", packet.encode())
    pump(bus)
    assert dropped(link) == {"invalid": 1}
    assert [p.robot.pos.y for p in link.teammates() if p.agent_id == 2] == [0.0], "the valid packet before it stays"


def test_a_datagram_of_no_type_at_all_never_stops_the_link(bus):
    link = TeamLink(bus, "nubot", 1)
    link.on_datagram("NUBOT_TEAM_nubot", None)  # type: ignore[arg-type] - what LCM never hands over
    assert dropped(link) == {"malformed": 1}


def test_duplicates_and_older_sequence_numbers_are_dropped(bus):
    link, sender = TeamLink(bus, "nubot", 1), TeamLink(bus, "nubot", 2)
    first = sender.send_team(content(2, x=1.0)).encode()
    second = sender.send_team(content(2, x=2.0)).encode()
    pump(bus)
    bus.publish("NUBOT_TEAM_nubot", second)
    bus.publish("NUBOT_TEAM_nubot", first)
    pump(bus)
    assert dropped(link) == {"duplicate": 1, "stale": 1}
    assert [p.robot.pos.x for p in link.teammates() if p.agent_id == 2] == [2.0]


def test_a_restarted_sender_is_heard_again_and_its_old_session_is_stale(bus):
    wall = iter(range(1000, 2000, 10))
    link = TeamLink(bus, "nubot", 1, wall_ns=lambda: 1500)
    before = TeamLink(bus, "nubot", 2, session=1, wall_ns=lambda: next(wall))
    late = [before.send_team(content(2, x=float(k))).encode() for k in range(5)]
    before.close()
    after = TeamLink(bus, "nubot", 2, session=2, wall_ns=lambda: next(wall))
    after.send_team(content(2, x=-1.0))  # seq 0 again, of a new session
    pump(bus)
    bus.publish("NUBOT_TEAM_nubot", late[-1])  # delayed on the way
    pump(bus)
    assert [p.robot.pos.x for p in link.teammates() if p.agent_id == 2] == [-1.0]
    assert dropped(link) == {"stale": 1}
    assert dropped(after) == {"own_agent": 6}, "the old session's packets are not the new link's own"


NOW_NS = 1_800_000_000 * 10**9  # a wall clock for the links of a test [ns]


def forged(agent_id: int, session: int, sent_ns: int, x: float = 9.0) -> bytes:
    """A team packet anyone on the network could send for robot ``agent_id``."""
    packet = content(agent_id, x=x)
    packet.team, packet.agent_id, packet.session, packet.seq, packet.sent_ns = "nubot", agent_id, session, 0, sent_ns
    return packet.encode()


def test_one_future_stamped_datagram_cannot_lock_a_robot_out_of_its_team(bus):
    """Once, a packet of a new session stamped an hour ahead was taken, and every genuine packet of that robot was
    then dropped as stale until the receiver restarted: the robot fell out of its team."""
    clock = Clock()
    link = TeamLink(bus, "nubot", 1, clock=clock, wall_ns=lambda: NOW_NS)
    robot = TeamLink(bus, "nubot", 2, clock=clock, wall_ns=lambda: NOW_NS)
    robot.send_team(content(2, x=1.0))
    bus.publish("NUBOT_TEAM_nubot", forged(2, 666, NOW_NS + 3600 * 10**9))  # an hour ahead: a clock fault
    bus.publish("NUBOT_TEAM_nubot", forged(2, 667, NOW_NS - 3600 * 10**9))  # an hour old: a replay
    robot.send_team(content(2, x=2.0))
    pump(bus)
    assert dropped(link) == {"clock": 2}
    assert [p.robot.pos.x for p in link.teammates() if p.agent_id == 2] == [2.0]
    # Stamped within the clocks' tolerance (30 s ahead), a forged session is taken, but holds the robot's own
    # packets back only while it keeps coming: max_age after its last one, the genuine session is heard again.
    bus.publish("NUBOT_TEAM_nubot", forged(2, 668, NOW_NS + 30 * 10**9, x=9.0))
    robot.send_team(content(2, x=3.0))
    pump(bus)
    assert [p.robot.pos.x for p in link.teammates() if p.agent_id == 2] == [9.0]
    clock.now += link.max_age
    robot.send_team(content(2, x=4.0))
    pump(bus)
    assert [p.robot.pos.x for p in link.teammates() if p.agent_id == 2] == [4.0]


def test_one_future_stamped_datagram_cannot_cut_a_team_off_its_coach(bus):
    clock = Clock()
    robot = TeamLink(bus, "nubot", 1, clock=clock, wall_ns=lambda: NOW_NS)
    coach = TeamLink(bus, "nubot", 0, clock=clock, wall_ns=lambda: NOW_NS)
    fake = coach_packet_t()
    fake.team, fake.session, fake.seq, fake.sent_ns = "nubot", 5, 0, NOW_NS + 20 * 10**9
    fake.coach.MatchMode = 0
    bus.publish("NUBOT_COACH_nubot", fake.encode())
    pump(bus)
    assert robot.take_coach().coach.MatchMode == 0  # within the tolerance: taken (a signed link refuses it)
    clock.now += robot.max_age
    command = coach_packet_t()
    command.coach.MatchMode = 15
    coach.send_coach(command)
    pump(bus)
    taken = robot.take_coach()
    assert taken is not None and taken.coach.MatchMode == 15


def test_a_position_of_1e30_m_is_invalid(bus):
    link = TeamLink(bus, "nubot", 1, wall_ns=lambda: NOW_NS)
    bus.publish("NUBOT_TEAM_nubot", forged(2, 7, NOW_NS, x=1e30))
    pump(bus)
    assert dropped(link) == {"invalid": 1} and link.teammates() == []


def test_another_link_sending_as_our_agent_is_counted(bus):
    me, twin = TeamLink(bus, "nubot", 3), TeamLink(bus, "nubot", 3)
    twin.send_team(content(3, x=5.0))
    me.send_team(content(3, x=1.0))
    pump(bus)
    assert [p.robot.pos.x for p in me.teammates()] == [1.0]
    assert dropped(me) == {"own_agent": 1} and me.stats().echoes == 1


def test_an_agent_beyond_the_team_size_is_not_a_member(bus):
    link, fifth = TeamLink(bus, "nubot", 1, team_size=3), TeamLink(bus, "nubot", 5)
    fifth.send_team(content(5))
    pump(bus)
    assert link.teammates() == [] and dropped(link) == {"not_member": 1}


def test_the_coach_side_sends_commands_the_robots_take_once(bus):
    coach, robot = TeamLink(bus, "nubot", 0), TeamLink(bus, "nubot", 1)
    for mode in (10, 15):
        packet = coach_packet_t()
        packet.coach.MatchMode = mode
        coach.send_coach(packet)
    pump(bus)
    taken = robot.take_coach()
    assert taken is not None and taken.coach.MatchMode == 15 and robot.take_coach() is None
    assert coach.take_coach() is None and coach.stats().echoes == 2


def test_coach_packets_for_another_team_or_out_of_order_are_dropped(bus):
    robot, rival_coach = TeamLink(bus, "nubot", 1), TeamLink(bus, "rival", 0)
    coach = TeamLink(bus, "nubot", 0)
    old = coach.send_coach(coach_packet_t()).encode()
    coach.send_coach(coach_packet_t())
    rival_coach.send_coach(coach_packet_t())
    packet = coach_packet_t()
    packet.team, packet.session, packet.seq, packet.sent_ns, packet.coach = "rival", 9, 0, 1, coach_info_t()
    bus.publish("NUBOT_COACH_nubot", packet.encode())
    pump(bus)
    bus.publish("NUBOT_COACH_nubot", old)
    pump(bus)
    assert dropped(robot) == {"foreign_channel": 1, "foreign_team": 1, "stale": 1}


def test_the_coach_side_sends_no_team_packet(bus):
    with pytest.raises(NubotCommError, match="the coach's side of the link sends no team packet"):
        TeamLink(bus, "nubot", 0).send_team(content(1))


def test_a_packet_teammates_would_drop_is_not_sent(bus):
    link, mate = TeamLink(bus, "nubot", 2), TeamLink(bus, "nubot", 1)
    bad = content(2)
    bad.ball.pos.x = math.inf
    with pytest.raises(NubotCommError, match="not sent, teammates would drop it: invalid: ball.pos.x is inf"):
        link.send_team(bad)
    with pytest.raises(NubotCommError, match="robot.AgentID 3 is not the sender's agent_id 2"):
        link.send_team(content(3))
    pump(bus)
    assert mate.stats().heard == 0 and link.stats().sent == 0


@pytest.mark.parametrize(("kwargs", "message"), [
    ({"team": "nubot1", "agent_id": 1}, "a team prefix"),
    ({"team": "nubot", "agent_id": 6}, r"agent_id must be 0 \(the coach\) or an AgentID 1..5, got 6"),
    ({"team": "nubot", "agent_id": 4, "team_size": 3}, r"AgentID 1..3, got 4"),
    ({"team": "nubot", "agent_id": 1, "team_size": 6}, r"team_size must lie in \[1, 5\], got 6"),
    ({"team": "nubot", "agent_id": 1, "max_age": 0.0}, "max_age must be positive, got 0.0"),
])
def test_a_link_that_cannot_be_is_refused(bus, kwargs, message):
    with pytest.raises(NubotCommError, match=message):
        TeamLink(bus, **kwargs)


def test_a_url_lcm_cannot_open_is_refused():
    with pytest.raises(NubotCommError, match="cannot open LCM at 'nonsense://x'"):
        TeamLink.open("nonsense://x", "nubot", 1)


def test_the_receiving_thread_takes_packets_and_stops_promptly(bus):
    sender, receiver = TeamLink(bus, "nubot", 1), TeamLink(lcm.LCM("memq://"), "nubot", 2)
    receiver.start()
    receiver.start()  # a second start is no second thread
    receiver._lcm.publish("NUBOT_TEAM_nubot", sender.send_team(content(1)).encode())
    deadline = time.monotonic() + 2.0
    while time.monotonic() < deadline and len(receiver.teammates()) < 1:
        time.sleep(0.005)
    assert [p.agent_id for p in receiver.teammates()] == [1]
    start = time.monotonic()
    receiver.close()
    assert time.monotonic() - start < 0.5
    receiver.close()  # twice is harmless


KEY = b"the team's shared secret, 32 b!!"


def test_with_the_teams_key_only_signed_datagrams_are_taken_and_replays_are_refused(bus):
    """Anyone on the network could speak for a robot or the coach: with a key set, an unsigned datagram, one signed
    with another key, one changed on the way and a replayed one are each refused and counted."""
    link = TeamLink(bus, "nubot", 1, key=KEY)
    robot = TeamLink(bus, "nubot", 2, key=KEY)
    stranger = TeamLink(bus, "nubot", 3)  # no key
    impostor = TeamLink(bus, "nubot", 4, key=b"another team's key, also 32 b!!!")
    sent: list[bytes] = []
    bus.subscribe("NUBOT_TEAM_nubot", lambda _channel, data: sent.append(data))
    robot.send_team(content(2, x=1.0))
    stranger.send_team(content(3, x=3.0))
    impostor.send_team(content(4, x=4.0))
    pump(bus)
    genuine = sent[0]
    changed = bytearray(genuine)
    changed[40] ^= 0x01
    bus.publish("NUBOT_TEAM_nubot", bytes(changed))  # one bit flipped
    bus.publish("NUBOT_TEAM_nubot", genuine)  # replayed
    bus.publish("NUBOT_COACH_nubot", genuine)  # the robot's signed bytes on the coach's channel
    pump(bus)
    assert [p.agent_id for p in link.teammates()] == [2]
    assert dropped(link) == {"signature": 4, "duplicate": 1}
    assert decode_team(verify(KEY, "NUBOT_TEAM_nubot", genuine)).robot.pos.x == 1.0  # the message, then its tag
    assert dropped(stranger)["malformed"] >= 3, "a link without the key cannot read signed datagrams either"
