"""The practice RefBox (coach4sim.refbox_server) over real loopback sockets, with a hand-written base station:
commands out, worldstates judged, malformed and invalid ones rejected and logged; the script's grammar."""

import socket
import time

import pytest

from coach4sim.refbox import FrameDecoder, RefboxCommand, RefboxError, build_worldstate, encode_message
from coach4sim.refbox_server import RefboxServer, parse_script_line, parse_server_args, run_steps

ALIASES = {"A": "224.16.32.53", "B": "224.16.32.127"}


@pytest.fixture
def server():
    lines: list[str] = []
    with RefboxServer(port=0, log=lines.append) as srv:
        srv.lines = lines
        yield srv


def connect(srv: RefboxServer) -> socket.socket:
    sock = socket.create_connection(("127.0.0.1", srv.port), timeout=2.0)
    srv.wait_for(lambda: srv.open_connections() == 1, 2.0, "the connection")
    return sock


def receive(sock: socket.socket, count: int) -> list[dict]:
    decoder, messages = FrameDecoder(), []
    deadline = time.monotonic() + 2.0
    while len(messages) < count and time.monotonic() < deadline:
        messages += [f.message for f in decoder.feed(sock.recv(4096))]
    return messages


def test_the_server_listens_on_loopback_only_by_default():
    assert RefboxServer().host == "127.0.0.1"


def test_a_base_station_is_welcomed_and_gets_commands_with_their_target_and_robot(server):
    with connect(server) as sock:
        assert server.send("KICKOFF", "224.16.32.53") == 1
        assert server.send("REPAIR", "224.16.32.127", 4) == 1
        assert receive(sock, 3) == [{"command": "WELCOME", "targetTeam": ""},
                                    {"command": "KICKOFF", "targetTeam": "224.16.32.53"},
                                    {"command": "REPAIR", "targetTeam": "224.16.32.127", "robotID": 4}]


def test_worldstates_are_validated_counted_and_their_rate_measured(server):
    worldstate = encode_message(build_worldstate("NuBot", "play", 5.0, []))
    with connect(server) as sock:
        for _ in range(21):
            sock.sendall(worldstate)
            time.sleep(0.05)
        server.wait_for(lambda: server.stats()[0].valid == 21, 2.0, "21 worldstates")
        [stats] = server.stats()
    assert (stats.valid, stats.invalid, stats.malformed, stats.team_name) == (21, 0, 0, "NuBot")
    assert 12.0 < stats.rate < 21.0, "about 20 Hz (sleep overshoots)"
    assert server.errors == []


def test_malformed_and_invalid_messages_are_rejected_with_a_logged_reason_and_the_link_stays(server):
    good = build_worldstate("NuBot", "", 0.0, [])
    bad = dict(good)
    del bad["ageMs"]
    with connect(server) as sock:
        sock.sendall(b'{"type": "worldstate",\0' + encode_message(bad) + encode_message(good)[:10])
        sock.sendall(encode_message(good)[10:])
        server.wait_for(lambda: server.stats()[0].valid == 1, 2.0, "the valid worldstate after the bad ones")
        [stats] = server.stats()
    assert (stats.valid, stats.invalid, stats.malformed, stats.open) == (1, 1, 1, True)
    assert server.errors == [
        "base station #1: rejected a malformed message: malformed JSON (Expecting property name enclosed in double "
        "quotes at character 22): '{\"type\": \"worldstate\",'",
        "base station #1: rejected an invalid worldstate: worldstate lacks \"ageMs\""]
    assert all(line in server.lines for line in server.errors), "each rejection is logged"


def test_a_base_station_that_goes_away_is_noticed_and_another_may_connect(server):
    sock = connect(server)
    assert receive(sock, 1) == [{"command": "WELCOME", "targetTeam": ""}]  # read all: close() sends FIN, not RST
    sock.close()
    server.wait_for(lambda: server.open_connections() == 0, 2.0, "the disconnection")
    assert "base station #1 disconnected (the base station closed the connection)" in server.lines
    with connect(server):
        assert [s.number for s in server.stats()] == [1, 2]


def test_closing_the_server_closes_its_connections():
    srv = RefboxServer(port=0).start()
    sock = socket.create_connection(("127.0.0.1", srv.port), timeout=2.0)
    srv.wait_for(lambda: srv.open_connections() == 1, 2.0, "the connection")
    srv.close()
    receive(sock, 1)  # WELCOME, perhaps
    sock.settimeout(2.0)
    assert sock.recv(100) == b"", "the client sees the box go away"
    sock.close()


@pytest.mark.parametrize(("line", "step"), [
    ("KICKOFF A", ("send", RefboxCommand("KICKOFF", "224.16.32.53"))),
    ("freekick b  # for them", ("send", RefboxCommand("FREEKICK", "224.16.32.127"))),
    ("YELLOW_CARD 10.0.0.7 3", ("send", RefboxCommand("YELLOW_CARD", "10.0.0.7", 3))),
    ("START", ("send", RefboxCommand("START", ""))),
    ("DROP_BALL -", ("send", RefboxCommand("DROP_BALL", ""))),
])
def test_script_lines_that_send(line, step):
    parsed = parse_script_line(line, ALIASES)
    assert (parsed.kind, parsed.command) == step


def test_script_lines_that_wait_or_report():
    assert parse_script_line("wait 0.5", ALIASES).seconds == 0.5
    assert parse_script_line("wait-clients 2", ALIASES).count == 2
    assert parse_script_line("raw {oops", ALIASES).text == "{oops"
    assert parse_script_line("  # just a comment", ALIASES).kind == "nothing"
    assert parse_script_line("status", ALIASES).kind == "status"


@pytest.mark.parametrize(("line", "error"), [
    ("KICKOF A", "unknown command 'KICKOF'; the box's commands: START, STOP"),
    ("wait", "usage: wait SECONDS"),
    ("wait soon", "usage: wait SECONDS (got 'soon')"),
    ("wait -1", "wait takes 0 to 3600 seconds, got -1"),
    ("REPAIR A two", "ROBOT_ID must be a whole number, got 'two'"),
    ("REPAIR A 2 3", "too many words after REPAIR: A 2 3"),
])
def test_bad_script_lines_are_refused_by_name(line, error):
    with pytest.raises(RefboxError, match=error.replace("(", r"\(").replace(")", r"\)")):
        parse_script_line(line, ALIASES)


def test_a_script_runs_in_order_and_reports_the_lines_it_refused(server):
    out: list[str] = []
    with connect(server) as sock:
        refused = run_steps(server, ["KICKOFF A", "BOGUS", "wait 0.01", "START", "status"], ALIASES, out.append)
        messages = receive(sock, 3)
    assert refused == 1 and out[0].startswith("line 2: unknown command 'BOGUS'")
    assert [m["command"] for m in messages] == ["WELCOME", "KICKOFF", "START"]
    assert out[1].startswith("#1 127.0.0.1:")


def test_server_arguments_are_checked():
    assert parse_server_args([]).port == 28097
    with pytest.raises(RefboxError, match=r"--port must lie in \[0, 65535\], got 70000"):
        parse_server_args(["--port", "70000"])
