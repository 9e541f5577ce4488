"""Property-based: whatever bytes arrive on the team's channels, the LCM decoders answer with a packet or with
their own PacketDropped, never another exception; a valid packet cut, extended or with bytes changed included."""

from hypothesis import given
from hypothesis import strategies as st

from nubot_comm.codec import PacketDropped, check_coach, check_team, decode_coach, decode_team
from nubot_lcm import coach_packet_t, team_packet_t


def _valid_team() -> bytes:
    packet = team_packet_t()
    packet.team, packet.agent_id, packet.session, packet.seq, packet.sent_ns = "nubot", 2, 7, 3, 10**18
    packet.robot.AgentID = packet.strategy.AgentID = 2
    packet.obstacles.pos = [type(packet.robot.pos)() for _ in range(3)]
    packet.obstacles.num_pos = 3
    return packet.encode()


def _valid_coach() -> bytes:
    packet = coach_packet_t()
    packet.team, packet.session, packet.seq, packet.sent_ns = "nubot", 5, 1, 10**18
    return packet.encode()


def _mutated(valid: bytes) -> st.SearchStrategy[bytes]:
    """``valid`` cut short, extended, or with up to 8 bytes changed."""
    changes = st.lists(st.tuples(st.integers(0, len(valid) - 1), st.integers(0, 255)), max_size=8)
    return st.one_of(
        st.integers(0, len(valid)).map(lambda n: valid[:n]),
        st.binary(max_size=64).map(lambda tail: valid + tail),
        changes.map(lambda edits: bytes(_apply(bytearray(valid), edits))))


def _apply(data: bytearray, edits: list[tuple[int, int]]) -> bytearray:
    for at, value in edits:
        data[at] = value
    return data


def _decodes_or_drops(decode, check, data: bytes) -> None:
    try:
        check(decode(data))
    except PacketDropped:
        pass


@given(st.one_of(st.binary(max_size=3000), _mutated(_valid_team())))
def test_team_datagrams_decode_or_are_dropped_with_the_reason(data):
    _decodes_or_drops(decode_team, check_team, data)


@given(st.one_of(st.binary(max_size=500), _mutated(_valid_coach())))
def test_coach_datagrams_decode_or_are_dropped_with_the_reason(data):
    _decodes_or_drops(decode_coach, check_coach, data)
