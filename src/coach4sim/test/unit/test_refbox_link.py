"""The base station's link (coach4sim.refbox_link) against the practice RefBox over real loopback sockets: commands
in, worldstates out, malformed messages counted, reconnection after the box goes away."""

import threading
from dataclasses import replace

from coach4sim.refbox import RefboxClientParams, RefboxError
from coach4sim.refbox_link import RefboxLink, TeamPicture
from coach4sim.refbox_server import RefboxServer
from nubot_common.match_mode import MatchMode

US = RefboxClientParams().team_address


def start_link(port: int, worldstate=None):
    params = replace(RefboxClientParams(), port=port, worldstate_rate=20.0, reconnect_initial=0.05,
                     reconnect_max=0.2)
    effects, lines = [], []
    picture = TeamPicture(params)
    link = RefboxLink(params, worldstate or (lambda: picture.worldstate("STOPROBOT", 0.0)), effects.append,
                      lambda level, line: lines.append((level, line)), lambda: None)
    thread = threading.Thread(target=link.run, daemon=True)
    thread.start()
    return link, thread, effects, lines


def test_commands_come_in_worldstates_go_out_and_bad_messages_are_counted():
    with RefboxServer(port=0) as box:
        link, thread, effects, lines = start_link(box.port)
        try:
            box.wait_for(lambda: box.open_connections() == 1, 5.0, "the link's connection")
            box.wait_for(lambda: box.last_worldstate() is not None, 5.0, "a worldstate")
            assert box.last_worldstate()["type"] == "worldstate" and box.last_worldstate()["robots"] == []
            box.send("KICKOFF", US)
            box.send_raw(b"{not json\x00")
            box.wait_for(lambda: len(effects) == 2 and link.status()["malformed"] == 1, 5.0, "the command")
            assert effects[0].command.command == "WELCOME" and effects[0].mode is None, "the box's greeting"
            assert effects[1].mode is MatchMode.OUR_KICKOFF
            status = link.status()
            assert status["connected"] and status["commands"] == 2 and status["worldstates_sent"] >= 1
            assert any(level == "warn" and "dropped (1 so far)" in line for level, line in lines)
        finally:
            link.shutdown()
            thread.join(timeout=5.0)
        assert not thread.is_alive() and not link.status()["connected"]


def test_the_link_comes_back_when_the_box_does_and_skips_a_worldstate_it_cannot_make():
    def broken() -> dict:
        raise RefboxError("our picture is bad")

    with RefboxServer(port=0) as box:
        port = box.port
        link, thread, _effects, lines = start_link(port, broken)
        try:
            box.wait_for(lambda: box.open_connections() == 1, 5.0, "the first connection")
        finally:
            box.close()
        with RefboxServer(port=port) as again:
            again.wait_for(lambda: again.open_connections() == 1, 10.0, "the link's reconnection")
            assert link.status()["connections"] >= 2 and link.status()["worldstates_sent"] == 0
        link.shutdown()
        thread.join(timeout=5.0)
        assert any("no worldstate this time: our picture is bad" in line for _, line in lines)


def test_a_huge_number_or_deep_nesting_from_the_box_is_dropped_and_the_link_goes_on():
    """Each once killed the link's thread for good while its status still said connected (under the 100 KB cap)."""
    with RefboxServer(port=0) as box:
        link, thread, effects, _lines = start_link(box.port)
        try:
            box.wait_for(lambda: box.open_connections() == 1, 5.0, "the link's connection")
            box.send_raw(b'{"command": "KICKOFF", "targetTeam": "", "robotID": ' + b"9" * 5000 + b"}\x00")
            box.send_raw(b"[" * 40000 + b"]" * 40000 + b"\x00")
            box.send("START", US)
            box.wait_for(lambda: any(e.mode is MatchMode.STARTROBOT for e in effects), 5.0, "the command after them")
            status = link.status()
            assert status["connected"] and status["malformed"] == 2 and status["connections"] == 1
            assert thread.is_alive()
        finally:
            link.shutdown()
            thread.join(timeout=5.0)


def test_the_practice_box_survives_the_same_and_keeps_only_its_latest_rejections_in_words():
    import socket

    from coach4sim.refbox_server import KEPT_ERRORS

    logged: list[str] = []
    with RefboxServer(port=0, log=logged.append) as box, \
            socket.create_connection(("127.0.0.1", box.port), timeout=5.0) as peer:
        box.wait_for(lambda: box.open_connections() == 1, 5.0, "the peer's connection")
        peer.sendall(b'{"type": "worldstate", "ageMs": ' + b"9" * 5000 + b"}\x00")
        peer.sendall(b"[" * 40000 + b"]" * 40000 + b"\x00")
        peer.sendall(b"{not json\x00" * (KEPT_ERRORS + 50))
        box.wait_for(lambda: box.rejected == KEPT_ERRORS + 52, 5.0, "every rejection counted")
        assert len(box.errors) == KEPT_ERRORS and box.open_connections() == 1
        assert "cannot be decoded" in " ".join(logged) and "nested 40000 deep" in " ".join(logged)
