"""The viewer's web server over real sockets on 127.0.0.1: the page and its assets, the hello and the frames, game
commands and their token, and every kind of bad message (each gets a clear error and changes nothing)."""

import asyncio
import base64
import json
import os
import socket
import struct
import urllib.error
import urllib.request
from types import SimpleNamespace as NS

import pytest
import tornado.httpclient
import tornado.websocket

from coach4sim import CoachError
from coach4sim.scene import Scene, field_layout
from coach4sim.viewer_server import ViewerInputError, ViewerServer, is_loopback, parse_page_message
from nubot_common.match_mode import MatchMode
from nubot_common.world_description import WorldDescription


class SceneBackend:
    """The live node's backend without ROS: a scene fed by hand, commands collected."""

    def __init__(self):
        self.scene = Scene(WorldDescription())
        pose = NS(position=NS(x=-1.0, y=2.0, z=0.0), orientation=NS(x=0.0, y=0.0, z=0.0, w=1.0))
        twist = NS(linear=NS(x=0.0, y=0.0, z=0.0))
        self.scene.on_model_states(NS(header=NS(stamp=NS(secs=5, nsecs=0)), name=["nubot1", "football"],
                                      pose=[pose, pose], twist=[twist, twist]))
        self.commands = []

    def hello(self):
        return {"mode": "live", "field": field_layout(self.scene.world), "teams": self.scene.teams}

    def frame(self, watch):
        return json.dumps(self.scene.frame(watch))

    def command(self, command, team):
        self.commands.append((command, team))
        return team == "nubot", "in force" if team == "nubot" else f"unknown team {team}"

    def control(self, message):
        raise CoachError("a live match cannot be paused")


async def serving(backend, **kwargs):
    server = ViewerServer(backend, port=0, log=lambda text: None, **kwargs)
    urls = []
    task = asyncio.create_task(server.run(ready=urls.append))
    while not urls:
        await asyncio.sleep(0.01)
    return server, task, urls[0]


async def connect(server):
    ws = await tornado.websocket.websocket_connect(f"ws://127.0.0.1:{server.port}/ws")
    hello = json.loads(await ws.read_message())
    return ws, hello


async def reply(ws, message):
    """Send ``message`` and return the next message that is not a frame."""
    await ws.write_message(message if isinstance(message, str) else json.dumps(message))
    while True:
        answer = json.loads(await asyncio.wait_for(ws.read_message(), 5.0))
        if answer["type"] != "frame":
            return answer


def run(coroutine):
    return asyncio.run(asyncio.wait_for(coroutine, 30.0))


def test_the_page_and_its_assets_are_served_and_frames_stream_at_the_rate():
    async def scenario():
        server, task, url = await serving(SceneBackend(), rate=20.0)
        loop = asyncio.get_running_loop()
        page = await loop.run_in_executor(None, lambda: urllib.request.urlopen(url).read().decode())
        script = await loop.run_in_executor(
            None, lambda: urllib.request.urlopen(f"{url}static/viewer.js").read().decode())
        assert "/static/viewer.js" in page and "http" not in page.replace("http-equiv", "")  # nothing from outside
        assert "new WebSocket" in script
        ws, hello = await connect(server)
        assert hello["type"] == "hello" and hello["field"]["length"] == 18.0 and not hello["token_required"]
        commands = {c["name"] for c in hello["commands"]}
        assert "STOPROBOT" in commands and "DROPBALL" in commands and "TEST" not in commands
        start = loop.time()
        frames = [json.loads(await ws.read_message()) for _ in range(20)]
        elapsed = loop.time() - start
        assert all(f["type"] == "frame" and f["robots"][0]["name"] == "nubot1" for f in frames)
        assert 0.6 < elapsed < 1.6, f"20 frames at 20 Hz took {elapsed:.2f} s"
        ws.close()
        server.stop()
        await task
    run(scenario())


def test_a_command_goes_to_the_backend_and_its_answer_comes_back():
    async def scenario():
        backend = SceneBackend()
        server, task, _ = await serving(backend)
        ws, _ = await connect(server)
        ok = await reply(ws, {"type": "command", "command": "OUR_KICKOFF", "team": "nubot"})
        assert ok == {"type": "result", "ok": True, "command": "OUR_KICKOFF", "team": "nubot", "message": "in force"}
        refused = await reply(ws, {"type": "command", "command": "15", "team": "blue"})
        assert refused["ok"] is False and "unknown team" in refused["message"]
        assert backend.commands == [(MatchMode.OUR_KICKOFF, "nubot"), (MatchMode.STARTROBOT, "blue")]
        server.stop()
        await task
    run(scenario())


@pytest.mark.parametrize(("message", "error"), [
    ("{not json", "malformed JSON"),
    ("[1, 2]", "JSON object"),
    ("[" * 8000 + "]" * 8000, "nested 8000 deep"),  # under the 16 KiB cap: once an uncaught RecursionError
    ('{"type": "watch", "robot": ' + "9" * 5000 + "}", "cannot be decoded"),  # once an uncaught ValueError
    ('{"type": "replay", "action": "seek", "t": NaN}', "NaN is not a JSON number"),
    ({"type": "dance"}, "unknown message type"),
    ({"type": "command", "command": "OUR_HATTRICK", "team": "nubot"}, "OUR_HATTRICK"),
    ({"type": "command", "command": "TEST", "team": "nubot"}, "not a command of the page"),
    ({"type": "command", "team": "nubot"}, "needs \"command\""),
    ({"type": "watch", "robot": 7}, "robot name"),
    ({"type": "replay", "action": "rewind"}, "play, pause, seek or speed"),
    ({"type": "replay", "action": "pause"}, "cannot be paused"),
], ids=lambda value: str(value)[:40])
def test_bad_messages_get_a_clear_error_and_change_nothing(message, error):
    async def scenario():
        backend = SceneBackend()
        server, task, _ = await serving(backend)
        ws, _ = await connect(server)
        answer = await reply(ws, message)
        assert answer["type"] == "error" and error in answer["message"], answer
        assert backend.commands == []
        ok = await reply(ws, {"type": "command", "command": "STOPROBOT", "team": "nubot"})
        assert ok["ok"], "the connection goes on"
        server.stop()
        await task
    run(scenario())


def test_replay_numbers_must_be_finite():
    with pytest.raises(ViewerInputError, match="NaN is not a JSON number"):
        parse_page_message('{"type": "replay", "action": "seek", "t": NaN}')
    with pytest.raises(ViewerInputError, match="finite"):
        parse_page_message('{"type": "replay", "action": "seek", "t": 1e999}')
    with pytest.raises(ViewerInputError, match="finite"):
        parse_page_message('{"type": "replay", "action": "speed", "speed": true}')


def test_with_a_token_commands_without_it_are_refused():
    async def scenario():
        backend = SceneBackend()
        server, task, url = await serving(backend, token="s3cret")
        assert url.endswith("?token=s3cret")
        ws, hello = await connect(server)
        assert hello["token_required"]
        refused = await reply(ws, {"type": "command", "command": "STARTROBOT", "team": "nubot", "token": "guess"})
        assert refused["type"] == "error" and "token" in refused["message"] and backend.commands == []
        ok = await reply(ws, {"type": "command", "command": "STARTROBOT", "team": "nubot", "token": "s3cret"})
        assert ok["ok"] and backend.commands == [(MatchMode.STARTROBOT, "nubot")]
        server.stop()
        await task
    run(scenario())


def test_any_address_but_loopback_gets_a_token_made_for_it():
    assert is_loopback("127.0.0.1") and is_loopback("::1") and is_loopback("localhost")
    assert not is_loopback("0.0.0.0") and not is_loopback("192.168.1.5")
    server = ViewerServer(SceneBackend(), host="0.0.0.0", port=8080)
    assert len(server.token) >= 12 and server.url.endswith(f"?token={server.token}")
    assert ViewerServer(SceneBackend()).token == ""


def test_a_browser_that_goes_away_costs_nothing():
    async def scenario():
        server, task, _ = await serving(SceneBackend())
        gone, _ = await connect(server)
        staying, _ = await connect(server)
        gone.close()
        for _ in range(30):  # the server goes on sending to the one that stays
            assert json.loads(await staying.read_message())["type"] == "frame"
        assert len(server.clients) == 1
        server.stop()
        await task
    run(scenario())


def test_a_taken_port_is_a_clear_error():
    with socket.socket() as taken:
        taken.bind(("127.0.0.1", 0))
        taken.listen()
        port = taken.getsockname()[1]
        server = ViewerServer(SceneBackend(), port=port)
        with pytest.raises(CoachError, match=f"cannot listen on 127.0.0.1:{port}"):
            run(server.run())


def test_the_frame_rate_is_bounded():
    with pytest.raises(CoachError, match="frame rate"):
        ViewerServer(SceneBackend(), rate=500.0)


def _get(port: int, host: str) -> int:
    request = urllib.request.Request(f"http://127.0.0.1:{port}/", headers={"Host": host})
    try:
        with urllib.request.urlopen(request, timeout=5) as answer:
            return answer.status
    except urllib.error.HTTPError as exc:
        return exc.code


def test_a_loopback_viewer_answers_only_loopback_names_and_pages_against_dns_rebinding():
    """A web site the browser visits could rebind its name to 127.0.0.1 and send game commands (neither Host nor
    Origin was checked and loopback needs no token)."""
    async def scenario():
        server, task, _url = await serving(SceneBackend())
        port = server.port
        statuses = await asyncio.to_thread(lambda: [_get(port, h) for h in (
            f"127.0.0.1:{port}", f"localhost:{port}", f"[::1]:{port}", f"evil.example:{port}", "attacker.test")])
        assert statuses == [200, 200, 200, 403, 403]
        for host, origin in ((f"evil.example:{port}", f"http://evil.example:{port}"),
                             (f"127.0.0.1:{port}", f"http://evil.example:{port}")):
            request = tornado.httpclient.HTTPRequest(f"ws://127.0.0.1:{port}/ws",
                                                     headers={"Host": host, "Origin": origin})
            with pytest.raises(tornado.httpclient.HTTPClientError, match="403"):
                await tornado.websocket.websocket_connect(request)
        ws, hello = await connect(server)  # a page of this machine (no Origin, or a loopback one) is served
        assert hello["type"] == "hello"
        ws.close()
        server.stop()
        await task
    run(scenario())


def test_a_page_may_send_a_few_commands_a_second_and_no_more():
    async def scenario():
        backend = SceneBackend()
        server, task, _url = await serving(backend)
        ws, _ = await connect(server)
        answers = [await reply(ws, {"type": "command", "command": "STOPROBOT", "team": "nubot"}) for _ in range(7)]
        assert [a["type"] for a in answers] == ["result"] * 5 + ["error"] * 2
        assert "at most 5 commands a second" in answers[-1]["message"] and len(backend.commands) == 5
        server.stop()
        await task
    run(scenario())


def _slow_page(port: int) -> socket.socket:
    """A page that opens the WebSocket and then reads nothing more, with a small receive buffer."""
    page = socket.socket()
    page.setsockopt(socket.SOL_SOCKET, socket.SO_RCVBUF, 2048)
    page.connect(("127.0.0.1", port))
    key = base64.b64encode(os.urandom(16)).decode()
    page.sendall(f"GET /ws HTTP/1.1\r\nHost: 127.0.0.1:{port}\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n"
                 f"Sec-WebSocket-Key: {key}\r\nSec-WebSocket-Version: 13\r\n\r\n".encode())
    assert page.recv(1024).startswith(b"HTTP/1.1 101")
    return page


def test_pages_that_leave_while_frames_are_on_their_way_leave_no_unretrieved_errors():
    """Each slow page that left once printed a 'Future exception was never retrieved' traceback."""
    async def scenario():
        lost = []
        asyncio.get_running_loop().set_exception_handler(lambda _loop, context: lost.append(context))
        server, task, _url = await serving(SceneBackend(), rate=60.0)
        pages = [await asyncio.to_thread(_slow_page, server.port) for _ in range(10)]
        await asyncio.sleep(1.5)  # they read nothing: their buffers fill and a write stays on its way
        for page in pages:  # gone, as a closed tab or a lost network (a reset, not a goodbye)
            page.setsockopt(socket.SOL_SOCKET, socket.SO_LINGER, struct.pack("ii", 1, 0))
            page.close()
        await asyncio.sleep(0.5)
        server.stop()
        await task
        import gc

        gc.collect()  # an unretrieved future's error is reported when it is collected
        await asyncio.sleep(0.1)
        return lost
    assert run(scenario()) == []


def test_served_on_every_interface_it_names_an_address_another_machine_can_open():
    server = ViewerServer(SceneBackend(), host="0.0.0.0", port=8080, log=lambda text: None)
    assert server.url.startswith(f"http://{socket.gethostname()}:8080/?token=") and "0.0.0.0" not in server.url


def test_a_flood_of_bad_page_messages_is_logged_as_a_count():
    """Each malformed page message once had a log line of its own."""
    async def scenario():
        lines = []
        server = ViewerServer(SceneBackend(), port=0, log=lines.append)
        urls = []
        task = asyncio.create_task(server.run(ready=urls.append))
        while not urls:
            await asyncio.sleep(0.01)
        ws, _ = await connect(server)
        for k in range(200):
            answer = await reply(ws, "{not json %d" % k)
            assert answer["type"] == "error"
        server.stop()
        await task
        return lines
    lines = run(scenario())
    refused = [line for line in lines if "refused" in line]
    assert len(refused) == 1 and "malformed JSON" in refused[0], refused[:3]
