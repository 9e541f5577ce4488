"""TeamLink: one team's robot-to-robot and coach packets over LCM, as RTDB shared them between real teammates.

Requires: an ``lcm.LCM`` (``udpm://`` on the robots' LAN; ``memq://`` in a process) and the team's prefix.
Provides: ``TeamLink``, which
- sends this robot's team packet on ``NUBOT_TEAM_<team>`` (``send_team``) or, on the coach's side, coach
  packets on ``NUBOT_COACH_<team>`` (``send_coach``), numbering them within a random session;
- hears every channel of the group and keeps, per member, the latest team packet (``teammates``: those heard
  within ``max_age`` [s], its own included) and the latest coach packet not yet taken (``take_coach``);
- drops, counts per ``DropReason`` and never raises on: other channels, other types, malformed, invalid or
  oversized payloads, packets naming another team, AgentIDs beyond the team, duplicates and stale packets, and
  packets stamped further than ``max_clock_skew`` [s] from its own clock, in either direction (``stats``);
- orders each sender's packets by its session and sequence number; a new session (a restarted sender) is taken
  when it was sent after the last one heard, or once the last one has been silent for ``max_age``: so no packet,
  however stamped, keeps a member out for longer than that;
- with the team's shared ``key`` (``nubot_comm.signing``), signs every datagram it sends and takes only datagrams
  signed with it;
- hands every packet it takes to ``on_accept`` (in the receiving thread; it must not raise), e.g. to time it;
- runs ``lcm.handle_timeout`` in a thread of its own (``start``/``close``), or one call at a time (``handle``).
The latest packet per member is kept by ``nubot_comm.relay.TeamRelay``, the relay the simulation uses too.
"""

from __future__ import annotations

import secrets
import threading
import time
from collections.abc import Callable, Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any

from nubot_comm import NubotCommError
from nubot_comm.codec import (
    MAX_AGENT_ID,
    DropReason,
    PacketDropped,
    check_coach,
    check_team,
    check_team_name,
    coach_channel,
    decode_coach,
    decode_team,
    team_channel,
)
from nubot_comm.relay import TeamRelay
from nubot_comm.signing import MIN_KEY_BYTES, sign, verify
from nubot_lcm import coach_packet_t, team_packet_t

MAX_CLOCK_SKEW = 60.0  # [s] the robots' and the coach's clocks agree within this (chrony/NTP keeps them to ms)
HANDLE_TIMEOUT = 0.1  # [s] the receiving thread looks at its stop flag this often
SESSION_BITS = 62  # sessions are positive int64


@dataclass(frozen=True)
class LinkStats:
    """What a link has done since it was made."""

    sent: int  # packets it sent
    heard: int  # datagrams LCM handed it, on any channel
    accepted: int  # packets it took (teammates' and the coach's)
    echoes: int  # its own packets heard back (not counted as dropped)
    dropped: Mapping[DropReason, int]  # every reason, 0 included

    @property
    def total_dropped(self) -> int:
        return sum(self.dropped.values())


@dataclass
class _LastHeard:
    session: int
    seq: int
    sent_ns: int
    heard: float  # [s] on the receiver's clock


def _newer(last: _LastHeard | None, packet: team_packet_t | coach_packet_t, now: float,
           max_age: float) -> DropReason | None:
    """None if ``packet`` follows what its sender was last heard sending, else why it does not."""
    if last is None:
        return None
    if packet.session == last.session:
        if packet.seq == last.seq:
            return DropReason.DUPLICATE
        return DropReason.STALE if packet.seq < last.seq else None
    if packet.sent_ns > last.sent_ns or now - last.heard >= max_age:  # a restarted sender's new session
        return None
    return DropReason.STALE


class TeamLink:
    """One team's packets over one LCM; ``agent_id`` 0 is the coach's side (it sends no team packet)."""

    def __init__(self, lcm: Any, team: str, agent_id: int, team_size: int = MAX_AGENT_ID, max_age: float = 1.0,
                 clock: Callable[[], float] = time.monotonic, wall_ns: Callable[[], int] = time.time_ns,
                 session: int | None = None, on_accept: Callable[[team_packet_t | coach_packet_t], None] | None = None,
                 max_clock_skew: float = MAX_CLOCK_SKEW, key: bytes | None = None):
        check_team_name(team)
        if not 1 <= team_size <= MAX_AGENT_ID:
            raise NubotCommError(f"team_size must lie in [1, {MAX_AGENT_ID}], got {team_size}")
        if not 0 <= agent_id <= team_size:
            raise NubotCommError(f"agent_id must be 0 (the coach) or an AgentID 1..{team_size}, got {agent_id}")
        if not max_age > 0.0:
            raise NubotCommError(f"max_age must be positive, got {max_age}")
        if not 0.0 < max_clock_skew <= 86400.0:
            raise NubotCommError(f"max_clock_skew must lie in (0, 86400] s, got {max_clock_skew}")
        if key is not None and len(key) < MIN_KEY_BYTES:
            raise NubotCommError(f"a team key has at least {MIN_KEY_BYTES} bytes, got {len(key)}")
        self.max_age, self.max_clock_skew = max_age, max_clock_skew
        self._key = key  # the team's shared key: datagrams signed, and only signed ones taken
        self.team, self.agent_id, self.team_size = team, agent_id, team_size
        self.team_channel, self.coach_channel = team_channel(team), coach_channel(team)
        self.session = session if session is not None else secrets.randbits(SESSION_BITS) + 1
        self._lcm, self._clock, self._wall_ns, self._on_accept = lcm, clock, wall_ns, on_accept
        self._lock = threading.Lock()
        self._members = tuple(f"{team}{k}" for k in range(1, team_size + 1))
        self._relay: TeamRelay[team_packet_t] = TeamRelay(team, self._members, max_age)
        self._last: dict[int, _LastHeard] = {}  # per AgentID
        self._last_coach: _LastHeard | None = None
        self._coach: coach_packet_t | None = None  # the latest coach packet not yet taken
        self._seq = 0
        self._sent = self._heard = self._accepted = self._echoes = 0
        self._dropped = dict.fromkeys(DropReason, 0)
        self._stop = threading.Event()
        self._thread: threading.Thread | None = None
        self._subscription = lcm.subscribe(".*", self.on_datagram)

    @classmethod
    def open(cls, url: str, team: str, agent_id: int, **kwargs: Any) -> TeamLink:
        """A link over a new ``lcm.LCM(url)``, e.g. ``udpm://239.255.76.67:7667?ttl=1``."""
        import lcm

        try:
            handle = lcm.LCM(url)
        except (OSError, RuntimeError) as exc:
            raise NubotCommError(f"cannot open LCM at {url!r}: {exc}") from None
        return cls(handle, team, agent_id, **kwargs)

    # --- sending -----------------------------------------------------------------------------------------
    def send_team(self, packet: team_packet_t) -> team_packet_t:
        """Stamp ``packet`` (its content filled) with this robot's envelope, check and send it; keep it as ours.

        Raises ``NubotCommError`` on the coach's side or for a packet its teammates would drop (naming why)."""
        if self.agent_id == 0:
            raise NubotCommError("the coach's side of the link sends no team packet")
        with self._lock:
            self._envelope(packet)
            packet.agent_id = self.agent_id
            try:
                check_team(packet)
            except PacketDropped as exc:
                raise NubotCommError(f"not sent, teammates would drop it: {exc}") from None
            self._publish(self.team_channel, packet)
            self._relay.put(self._members[self.agent_id - 1], self._clock(), packet)
        return packet

    def send_coach(self, packet: coach_packet_t) -> coach_packet_t:
        """Stamp ``packet`` (its ``coach`` filled) with the link's envelope, check and send it."""
        with self._lock:
            self._envelope(packet)
            try:
                check_coach(packet)
            except PacketDropped as exc:
                raise NubotCommError(f"not sent, the robots would drop it: {exc}") from None
            self._publish(self.coach_channel, packet)
            self._last_coach = _LastHeard(packet.session, packet.seq, packet.sent_ns, self._clock())
        return packet

    def _envelope(self, packet: team_packet_t | coach_packet_t) -> None:
        packet.team, packet.session, packet.seq, packet.sent_ns = self.team, self.session, self._seq, self._wall_ns()

    def _publish(self, channel: str, packet: team_packet_t | coach_packet_t) -> None:
        data = packet.encode()
        self._lcm.publish(channel, data if self._key is None else sign(self._key, channel, data))
        self._seq += 1
        self._sent += 1

    # --- receiving ---------------------------------------------------------------------------------------
    def on_datagram(self, channel: str, data: bytes) -> None:
        """LCM's handler for every channel: take the packet or count why not; never raises."""
        with self._lock:
            self._heard += 1
            try:
                if channel not in (self.team_channel, self.coach_channel):
                    raise PacketDropped(DropReason.FOREIGN_CHANNEL, channel)
                if self._key is not None:
                    signed = verify(self._key, channel, data)
                    if signed is None:
                        raise PacketDropped(DropReason.SIGNATURE, f"{len(data)} bytes on {channel}")
                    data = signed
                if channel == self.team_channel:
                    self._take_team(decode_team(data))
                else:
                    self._take_coach(decode_coach(data))
            except PacketDropped as exc:
                self._dropped[exc.reason] += 1
            except Exception:  # noqa: BLE001 - a datagram must never stop the link; count it as unreadable
                self._dropped[DropReason.MALFORMED] += 1

    def _take_team(self, packet: team_packet_t) -> None:
        if packet.team != self.team:
            raise PacketDropped(DropReason.FOREIGN_TEAM, packet.team)
        if packet.agent_id > self.team_size:
            raise PacketDropped(DropReason.NOT_MEMBER, f"AgentID {packet.agent_id}")
        if packet.agent_id == self.agent_id:
            if packet.session == self.session:
                self._echoes += 1
                return
            raise PacketDropped(DropReason.OWN_AGENT, f"session {packet.session}")
        self._check_clock(packet)
        now = self._clock()
        last = self._last.get(packet.agent_id)
        refused = _newer(last, packet, now, self.max_age)
        if refused is not None:
            raise PacketDropped(refused, f"AgentID {packet.agent_id} seq {packet.seq}")
        self._last[packet.agent_id] = _LastHeard(packet.session, packet.seq, packet.sent_ns, now)
        self._relay.put(self._members[packet.agent_id - 1], self._clock(), packet)
        self._accept(packet)

    def _take_coach(self, packet: coach_packet_t) -> None:
        if packet.team != self.team:
            raise PacketDropped(DropReason.FOREIGN_TEAM, packet.team)
        if packet.session == self.session:
            self._echoes += 1
            return
        self._check_clock(packet)
        now = self._clock()
        refused = _newer(self._last_coach, packet, now, self.max_age)
        if refused is not None:
            raise PacketDropped(refused, f"coach seq {packet.seq}")
        self._last_coach = _LastHeard(packet.session, packet.seq, packet.sent_ns, now)
        self._coach = packet
        self._accept(packet)

    def _check_clock(self, packet: team_packet_t | coach_packet_t) -> None:
        off = (packet.sent_ns - self._wall_ns()) / 1e9
        if abs(off) > self.max_clock_skew:
            raise PacketDropped(DropReason.CLOCK, f"sent {off:+.1f} s from this robot's clock")

    def _accept(self, packet: team_packet_t | coach_packet_t) -> None:
        self._accepted += 1
        if self._on_accept is not None:
            self._on_accept(packet)

    # --- what the node reads -----------------------------------------------------------------------------
    def teammates(self) -> list[team_packet_t]:
        """The latest packet of every member (this robot's own included) heard within ``max_age``, by AgentID."""
        with self._lock:
            return self._relay.collect(self._clock())

    def take_coach(self) -> coach_packet_t | None:
        """The latest coach packet heard since the last call, or None."""
        with self._lock:
            packet, self._coach = self._coach, None
            return packet

    def stats(self) -> LinkStats:
        with self._lock:
            return LinkStats(self._sent, self._heard, self._accepted, self._echoes,
                             MappingProxyType(dict(self._dropped)))

    # --- LCM's receiving loop ------------------------------------------------------------------------------
    def handle(self, timeout: float = HANDLE_TIMEOUT) -> bool:
        """Dispatch at most one datagram waiting within ``timeout`` [s]; True if one was."""
        return self._lcm.handle_timeout(max(int(timeout * 1000), 0)) > 0

    def start(self) -> None:
        """Receive in a thread of its own until ``close``."""
        if self._thread is None:
            self._thread = threading.Thread(target=self._receive, name=f"team_link_{self.team}", daemon=True)
            self._thread.start()

    def _receive(self) -> None:
        while not self._stop.is_set():
            try:
                self.handle(HANDLE_TIMEOUT)
            except OSError:  # the socket went away (interface down): try again, never spin
                self._stop.wait(HANDLE_TIMEOUT)

    def close(self) -> None:
        """Stop receiving (within ``HANDLE_TIMEOUT``) and leave the channels."""
        self._stop.set()
        if self._thread is not None:
            self._thread.join(timeout=5 * HANDLE_TIMEOUT + 1.0)
            self._thread = None
        if self._subscription is not None:
            self._lcm.unsubscribe(self._subscription)
            self._subscription = None
