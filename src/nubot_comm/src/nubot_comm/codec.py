"""Channels, limits and the checks every packet of the team link passes (no rospy, no sockets).

Requires: the generated LCM types ``nubot_lcm.team_packet_t`` and ``nubot_lcm.coach_packet_t``.
Provides: ``team_channel``/``coach_channel`` (``NUBOT_TEAM_<team>``, ``NUBOT_COACH_<team>``), ``DropReason``
(why a datagram was dropped), ``PacketDropped`` (raised with its reason), ``decode_team``/``decode_coach``
(bytes -> a checked packet) and ``check_team``/``check_coach`` (a packet's values: finite numbers, AgentID
1..``MAX_AGENT_ID``, a team prefix, bounded lists, stamps and ROS uint32 ranges).
"""

from __future__ import annotations

import enum
import math
import re
import struct
from io import BytesIO
from typing import Any, NoReturn, TypeVar

from nubot_comm import NubotCommError
from nubot_lcm import coach_packet_t, team_packet_t

DEFAULT_URL = "udpm://239.255.76.67:7667?ttl=1"  # LCM's default group and port; ttl=1: the robots' own LAN
TEAM_CHANNEL = "NUBOT_TEAM_{team}"
COACH_CHANNEL = "NUBOT_COACH_{team}"
MAX_AGENT_ID = 5  # an MSL team fields five robots
MAX_TEAM_NAME = 32  # [characters]
MAX_OBSTACLES = 32  # per list of a packet: more than every other robot on the field and then some
MAX_MAGNITUDE = 1e5  # no float a robot or a coach sends is larger (positions within 100 km, times under a day)
MAX_PACKET_BYTES = 2048  # a team packet at every limit is about 1.2 kB; anything larger is no packet of ours
UINT32_MAX = 2**32 - 1

_TEAM = re.compile(r"[A-Za-z_]+")
P = TypeVar("P", team_packet_t, coach_packet_t)


class DropReason(enum.Enum):
    """Why the link dropped a datagram; the value names its counter."""

    FOREIGN_CHANNEL = "foreign_channel"  # a channel not of our team (another team's, or anything else)
    OVERSIZE = "oversize"  # longer than MAX_PACKET_BYTES
    FOREIGN_TYPE = "foreign_type"  # its LCM fingerprint is not the channel's type
    MALFORMED = "malformed"  # our type's fingerprint, but truncated, with bytes left over or undecodable
    INVALID = "invalid"  # decoded, but a value is out of range (NaN, AgentID, list sizes, team name, ...)
    FOREIGN_TEAM = "foreign_team"  # on our channel, but its team field names another team
    NOT_MEMBER = "not_member"  # an AgentID beyond the team's size
    OWN_AGENT = "own_agent"  # our own AgentID, sent by another link (two robots configured as one)
    DUPLICATE = "duplicate"  # the sender's sequence number heard before
    STALE = "stale"  # older than what the sender was last heard sending (reordered, or a session before)
    SIGNATURE = "signature"  # the link has the team's key, and the datagram carries no valid tag of it
    CLOCK = "clock"  # sent further than max_clock_skew from the receiver's clock: a clock gone wrong, or forged


class PacketDropped(NubotCommError):
    """A datagram the link does not take, with the reason it is counted under."""

    def __init__(self, reason: DropReason, detail: str):
        super().__init__(f"{reason.value}: {detail}")
        self.reason = reason


def team_channel(team: str) -> str:
    return TEAM_CHANNEL.format(team=check_team_name(team))


def coach_channel(team: str) -> str:
    return COACH_CHANNEL.format(team=check_team_name(team))


def check_team_name(team: str) -> str:
    """Return ``team`` if it can name a team (letters and underscores, at most MAX_TEAM_NAME), else raise."""
    if not isinstance(team, str) or len(team) > MAX_TEAM_NAME or not _TEAM.fullmatch(team):
        raise NubotCommError(f"a team prefix is 1 to {MAX_TEAM_NAME} letters and underscores, got {team!r}")
    return team


def decode_team(data: bytes) -> team_packet_t:
    """A checked team packet from a datagram's payload; raises ``PacketDropped`` with the reason."""
    packet = _decode(data, team_packet_t)
    check_team(packet)
    return packet


def decode_coach(data: bytes) -> coach_packet_t:
    """A checked coach packet from a datagram's payload; raises ``PacketDropped`` with the reason."""
    packet = _decode(data, coach_packet_t)
    check_coach(packet)
    return packet


def _decode(data: bytes, kind: type[P]) -> P:
    if len(data) > MAX_PACKET_BYTES:
        raise PacketDropped(DropReason.OVERSIZE, f"{len(data)} bytes, at most {MAX_PACKET_BYTES}")
    if data[:8] != kind._get_packed_fingerprint():
        raise PacketDropped(DropReason.FOREIGN_TYPE, f"not a {kind.__name__} (fingerprint {data[:8].hex()})")
    buf = BytesIO(data)
    buf.seek(8)
    try:
        packet = kind._decode_one(buf)
    except (struct.error, ValueError, TypeError, IndexError) as exc:
        raise PacketDropped(DropReason.MALFORMED, f"{kind.__name__} does not decode: {exc}") from None
    if buf.tell() != len(data):
        raise PacketDropped(DropReason.MALFORMED, f"{len(data) - buf.tell()} bytes after the {kind.__name__}")
    return packet


def check_team(packet: team_packet_t) -> None:
    """Raise ``PacketDropped(INVALID)`` naming the first value of ``packet`` out of range."""
    _check_name(packet.team)
    if not 1 <= packet.agent_id <= MAX_AGENT_ID:
        _invalid(f"agent_id {packet.agent_id} is not an AgentID 1..{MAX_AGENT_ID}")
    for name, agent in (("robot.AgentID", packet.robot.AgentID), ("strategy.AgentID", packet.strategy.AgentID)):
        if agent != packet.agent_id:
            _invalid(f"{name} {agent} is not the sender's agent_id {packet.agent_id}")
    _check_envelope(packet)
    for name in ("message_stamp_ns", "robot.stamp_ns", "ball.stamp_ns", "obstacles.stamp_ns", "strategy.stamp_ns"):
        _check_range(name, _get(packet, name), 0, None)
    obstacles = packet.obstacles
    for count, items in (("num_pos", obstacles.pos), ("num_polar_pos", obstacles.polar_pos)):
        number = getattr(obstacles, count)
        if not 0 <= number <= MAX_OBSTACLES or len(items) != number:
            _invalid(f"obstacles.{count} {number} for {len(items)} items (at most {MAX_OBSTACLES})")
    for name in ("strategy.role", "strategy.action", "strategy.pass_cmd.pass_id", "strategy.pass_cmd.catch_id"):
        _check_range(name, _get(packet, name), 0, UINT32_MAX)
    _check_finite(packet, "")


def check_coach(packet: coach_packet_t) -> None:
    """Raise ``PacketDropped(INVALID)`` naming the first value of ``packet`` out of range."""
    _check_name(packet.team)
    _check_envelope(packet)
    _check_range("coach.stamp_ns", packet.coach.stamp_ns, 0, None)
    _check_finite(packet, "")


def _check_envelope(packet: team_packet_t | coach_packet_t) -> None:
    _check_range("session", packet.session, 1, None)
    _check_range("seq", packet.seq, 0, None)
    _check_range("sent_ns", packet.sent_ns, 0, None)


def _check_name(team: str) -> None:
    try:
        check_team_name(team)
    except NubotCommError as exc:
        _invalid(f"team: {exc}")


def _check_range(name: str, value: int, low: int, high: int | None) -> None:
    if value < low or (high is not None and value > high):
        _invalid(f"{name} {value} is outside [{low}, {'' if high is None else high}]")


def _check_finite(obj: Any, where: str) -> None:
    """Every float of an LCM struct, nested structs and arrays included, must be finite and at most
    ``MAX_MAGNITUDE`` in size (a position of 1e30 m is no robot's)."""
    for name, typename in zip(obj.__slots__, obj.__typenames__):
        value = getattr(obj, name)
        if typename in ("float", "double"):
            if not math.isfinite(value) or abs(value) > MAX_MAGNITUDE:
                _invalid(f"{where}{name} is {value}")
        elif typename.startswith("nubot_lcm."):
            for i, item in enumerate(value) if isinstance(value, list) else ((None, value),):
                _check_finite(item, f"{where}{name}{'' if i is None else f'[{i}]'}.")


def _get(obj: Any, dotted: str) -> Any:
    for part in dotted.split("."):
        obj = getattr(obj, part)
    return obj


def _invalid(detail: str) -> NoReturn:
    raise PacketDropped(DropReason.INVALID, detail)
