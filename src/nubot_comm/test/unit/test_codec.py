"""The team link's packets: every field survives ROS -> LCM -> bytes -> LCM -> ROS; what is refused, and why."""

from __future__ import annotations

import math
import re

import numpy as np
import pytest

from nubot_comm import NubotCommError
from nubot_comm import conversions as conv
from nubot_comm.codec import (
    MAX_OBSTACLES,
    MAX_PACKET_BYTES,
    UINT32_MAX,
    DropReason,
    PacketDropped,
    check_team_name,
    coach_channel,
    decode_coach,
    decode_team,
    team_channel,
)
from nubot_common.msg import CoachInfo, StrategyInfo, TeamMessage
from nubot_lcm import coach_packet_t, point2d_t, ppoint_t, team_packet_t

from .filled import differences, fill

AGENT = 2


def filled_messages() -> tuple[TeamMessage, StrategyInfo]:
    message, strategy = fill(TeamMessage()), fill(StrategyInfo())
    message.robot.AgentID = strategy.AgentID = AGENT
    return message, strategy


def valid_packet() -> team_packet_t:
    """A team packet as a link sends it, every field set."""
    packet = conv.team_packet(*filled_messages())
    packet.team, packet.agent_id, packet.session, packet.seq, packet.sent_ns = "nubot", AGENT, 99, 7, 1_700_000_000_5
    return packet


def valid_coach() -> coach_packet_t:
    packet = conv.coach_packet(fill(CoachInfo()))
    packet.team, packet.session, packet.seq, packet.sent_ns = "nubot", 5, 3, 1_700_000_000_000
    return packet


def test_every_field_of_team_message_and_strategy_survives_the_trip_through_bytes():
    message, strategy = filled_messages()
    packet = conv.team_packet(message, strategy)
    packet.team, packet.agent_id, packet.session, packet.seq, packet.sent_ns = "nubot", AGENT, 1, 0, 1
    heard = decode_team(packet.encode())
    assert differences(conv.team_message(heard), message) == []
    assert differences(conv.strategy_info(heard), strategy) == []
    assert (heard.team, heard.agent_id, heard.session, heard.seq, heard.sent_ns) == ("nubot", AGENT, 1, 0, 1)


def test_every_field_of_a_packet_survives_encoding():
    packet = valid_packet()
    assert differences(decode_team(packet.encode()), packet) == []
    coach = valid_coach()
    assert differences(decode_coach(coach.encode()), coach) == []


def test_every_field_of_coach_info_survives_the_trip_through_bytes():
    command = fill(CoachInfo())
    packet = conv.coach_packet(command)
    packet.team, packet.session, packet.seq, packet.sent_ns = "rival", 1, 0, 1
    assert differences(conv.coach_info(decode_coach(packet.encode())), command) == []


def test_chars_given_as_bytes_or_letters_leave_as_numbers():
    command = CoachInfo(MatchMode=b"\x0a", MatchType="\x01")
    assert (conv.coach_packet(command).coach.MatchMode, conv.coach_packet(command).coach.MatchType) == (10, 1)


def test_stamps_keep_their_nanoseconds():
    stamp = conv.ros_time(1_700_000_123_456_789_012)
    assert (stamp.secs, stamp.nsecs) == (1_700_000_123, 456_789_012)
    assert conv.nanoseconds(stamp) == 1_700_000_123_456_789_012


def test_a_packet_at_every_limit_fits_in_the_size_bound():
    packet = valid_packet()
    packet.team = "t" * 32
    obstacles = packet.obstacles
    obstacles.pos = [point2d_t() for _ in range(MAX_OBSTACLES)]
    obstacles.polar_pos = [ppoint_t() for _ in range(MAX_OBSTACLES)]
    obstacles.num_pos = obstacles.num_polar_pos = MAX_OBSTACLES
    data = packet.encode()
    assert len(data) <= MAX_PACKET_BYTES
    assert decode_team(data).obstacles.num_pos == MAX_OBSTACLES


def test_channels_name_the_team():
    assert (team_channel("rival"), coach_channel("rival")) == ("NUBOT_TEAM_rival", "NUBOT_COACH_rival")
    with pytest.raises(NubotCommError, match="a team prefix is 1 to 32 letters"):
        team_channel("nubot 2")


@pytest.mark.parametrize("name", ["", "nubot1", "a" * 33, "nu-bot", "ñubot"])
def test_a_team_name_is_letters_and_underscores(name):
    with pytest.raises(NubotCommError, match="a team prefix"):
        check_team_name(name)


NUMBERS = ["robot.pos.x", "robot.heading", "robot.vtrans.y", "robot.target.x", "robot.role_time", "ball.real_pos.angle",
           "ball.velocity.y", "obstacles.pos[1].x", "obstacles.polar_pos[2].radius", "strategy.role_time",
           "strategy.pass_cmd.catch_pt.y"]


@pytest.mark.parametrize("path", NUMBERS)
@pytest.mark.parametrize("bad", [math.nan, math.inf, -math.inf])
def test_a_number_that_is_not_finite_is_invalid_and_named(path, bad):
    packet = valid_packet()
    *parents, last = path.replace("[", ".").replace("]", "").split(".")
    owner = packet
    for part in parents:
        owner = owner[int(part)] if part.isdigit() else getattr(owner, part)
    setattr(owner, last, bad)
    with pytest.raises(PacketDropped, match=f"invalid: {re.escape(path)} is") as caught:
        decode_team(packet.encode())
    assert caught.value.reason is DropReason.INVALID


def test_a_coach_point_that_is_not_finite_is_invalid():
    packet = valid_coach()
    packet.coach.pointA.x = math.nan
    with pytest.raises(PacketDropped, match="invalid: coach.pointA.x is nan"):
        decode_coach(packet.encode())


@pytest.mark.parametrize(("change", "message"), [
    (lambda p: setattr(p, "agent_id", 0), "agent_id 0 is not an AgentID 1..5"),
    (lambda p: setattr(p, "agent_id", 6), "agent_id 6 is not an AgentID 1..5"),
    (lambda p: setattr(p.robot, "AgentID", 3), "robot.AgentID 3 is not the sender's agent_id 2"),
    (lambda p: setattr(p.strategy, "AgentID", 1), "strategy.AgentID 1 is not the sender's agent_id 2"),
    (lambda p: setattr(p, "team", "nubot2"), "team: a team prefix"),
    (lambda p: setattr(p, "team", ""), "team: a team prefix"),
    (lambda p: setattr(p, "session", 0), r"session 0 is outside \[1, \]"),
    (lambda p: setattr(p, "seq", -1), r"seq -1 is outside \[0, \]"),
    (lambda p: setattr(p, "sent_ns", -5), r"sent_ns -5 is outside"),
    (lambda p: setattr(p.ball, "stamp_ns", -1), r"ball.stamp_ns -1 is outside"),
    (lambda p: setattr(p.strategy, "role", UINT32_MAX + 1), rf"strategy.role {UINT32_MAX + 1} is outside"),
    (lambda p: setattr(p.strategy.pass_cmd, "catch_id", -1), r"strategy.pass_cmd.catch_id -1 is outside"),
], ids=["agent_0", "agent_6", "robot_agent", "strategy_agent", "team_digit", "team_empty", "session_0", "seq",
        "sent", "stamp", "role", "catch_id"])
def test_a_value_out_of_range_is_invalid_and_named(change, message):
    packet = valid_packet()
    change(packet)
    with pytest.raises(PacketDropped, match=f"invalid: {message}"):
        decode_team(packet.encode())


def test_too_many_obstacles_are_invalid():
    packet = valid_packet()
    packet.obstacles.pos = [point2d_t() for _ in range(MAX_OBSTACLES + 1)]
    packet.obstacles.num_pos = MAX_OBSTACLES + 1
    with pytest.raises(PacketDropped, match=f"invalid: obstacles.num_pos {MAX_OBSTACLES + 1} for"):
        decode_team(packet.encode())


def test_a_datagram_longer_than_any_packet_is_oversize():
    with pytest.raises(PacketDropped, match=f"oversize: {MAX_PACKET_BYTES + 1} bytes") as caught:
        decode_team(b"\0" * (MAX_PACKET_BYTES + 1))
    assert caught.value.reason is DropReason.OVERSIZE


@pytest.mark.parametrize("data", [b"", b"abc", b"\x00" * 100, valid_coach().encode()], ids=["empty", "short", "zeros",
                                                                                         "coach_packet"])
def test_another_type_is_foreign(data):
    with pytest.raises(PacketDropped, match="foreign_type: not a team_packet_t") as caught:
        decode_team(data)
    assert caught.value.reason is DropReason.FOREIGN_TYPE


def test_a_team_packet_is_no_coach_packet():
    with pytest.raises(PacketDropped, match="foreign_type: not a coach_packet_t"):
        decode_coach(valid_packet().encode())


@pytest.mark.parametrize("cut", [9, 20, 100, -1])
def test_a_truncated_packet_is_malformed(cut):
    with pytest.raises(PacketDropped, match="malformed: team_packet_t does not decode") as caught:
        decode_team(valid_packet().encode()[:cut])
    assert caught.value.reason is DropReason.MALFORMED


def test_bytes_after_a_packet_make_it_malformed():
    with pytest.raises(PacketDropped, match="malformed: 3 bytes after the team_packet_t"):
        decode_team(valid_packet().encode() + b"abc")


def test_any_corruption_of_a_packet_is_decoded_or_dropped_with_a_reason():
    rng = np.random.default_rng(0)
    data = valid_packet().encode()
    reasons = set()
    for _ in range(3000):
        corrupted = bytearray(data)
        for at in rng.integers(8, len(data), size=rng.integers(1, 4)):
            corrupted[at] = int(rng.integers(0, 256))
        try:
            decode_team(bytes(corrupted))
        except PacketDropped as exc:
            reasons.add(exc.reason)
    assert reasons <= {DropReason.MALFORMED, DropReason.INVALID}
    assert DropReason.INVALID in reasons and DropReason.MALFORMED in reasons
