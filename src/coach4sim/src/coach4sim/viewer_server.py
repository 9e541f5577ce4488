"""The match viewer's web server: one page that draws a match live or from a bag, and coaches it.

Requires: a ``ViewerBackend`` (the live node's, over ROS topics, or the replay's, over a bag) and an address.
Provides: ``ViewerServer``: GET ``/`` (the page), ``/static/...`` (its script and style; every asset is
served from here, the page needs no internet) and the WebSocket ``/ws``. Over ``/ws`` the server sends a
``hello`` (the field, the teams, the game commands, the replay's span and marks) and then ``frame`` messages
at ``rate`` [Hz], each client at its own pace: a client still busy with the last frame skips one, so a slow
or vanished browser costs nothing. The page sends JSON objects:

- ``{"type": "command", "command": "<MatchMode name>", "team": "<prefix>", "token": "..."}``: a game command,
  through the backend (the referee's ``/referee/command``, as ``rosrun coach4sim coach``);
- ``{"type": "watch", "robot": "<name or empty>"}``: draw what that robot believes over the truth;
- ``{"type": "replay", "action": "play" | "pause" | "seek" | "speed", "t": s, "speed": x}``: replay only.

Anything malformed or unknown gets ``{"type": "error", "message": ...}``, is logged (a line every few seconds at
most per peer, with the count) and changes nothing; a page may send ``MAX_COMMANDS_PER_SECOND`` commands a second.
Bound to 127.0.0.1 unless told otherwise; on any other address commands need a token (one is made when none
is given), which the page takes from its address (``?token=...``) and presents with each command. Served on
loopback without a token, it answers only requests addressed to a loopback name (``Host``) and, for the WebSocket,
from a page of one (``Origin``): a web site the browser visits cannot reach it by DNS rebinding.
"""

from __future__ import annotations

import asyncio
import hmac
import ipaddress
import json
import secrets
import socket
import time
from collections.abc import Callable
from pathlib import Path
from typing import Any, Protocol
from urllib.parse import urlsplit

import tornado.web
import tornado.websocket

from coach4sim import CoachError
from nubot_common import NubotCommonError
from nubot_common.match_mode import MatchMode, parse_match_mode
from nubot_common.rejections import RejectionReporter
from nubot_common.untrusted import UntrustedInputError, json_object

ASSETS = Path(__file__).resolve().parent / "viewer_assets"
MAX_MESSAGE = 16 * 1024  # the largest message a page may send [bytes]
SEND_BUFFER = 16 * 1024  # the kernel's buffer towards each page [bytes] (it doubles it): a few frames at most
ROBOT_NAME_MAX = 64
MAX_COMMANDS_PER_SECOND = 5  # a page's game commands: a person clicks far slower
REFUSAL_LOG_INTERVAL = 5.0  # [s] between two log lines about one peer's refused messages
LOOPBACK_NAMES = frozenset({"localhost", "localhost.localdomain", "ip6-localhost"})
COMMANDS = [m for m in MatchMode if m != MatchMode.TEST]  # TEST needs a test mode's points: the console's


class ViewerInputError(CoachError):
    """A message from the page that the viewer cannot act on; the page gets the text."""


class ViewerBackend(Protocol):
    def hello(self) -> dict[str, Any]:
        """The field, the teams and (replay) the span and marks."""

    def frame(self, watch: str) -> str | None:
        """The JSON text of the match now, with ``watch``'s world model; None before there is anything."""

    def command(self, command: MatchMode, team: str) -> tuple[bool, str]:
        """Send a game command for ``team``; (accepted, what was done or why not). May block (runs apart)."""

    def control(self, message: dict[str, Any]) -> None:
        """A replay control; raise ``ViewerInputError`` when it cannot be done."""


def is_loopback(host: str) -> bool:
    host = host.strip("[]").lower()
    if host in LOOPBACK_NAMES:
        return True
    try:
        return ipaddress.ip_address(host).is_loopback
    except ValueError:
        return False


def parse_page_message(text: str | bytes) -> dict[str, Any]:
    """Decode one message of the page; raise ``ViewerInputError`` naming what is wrong."""
    try:
        message = json_object(text)
    except UntrustedInputError as exc:
        raise ViewerInputError(f"not a JSON object: {exc}") from None
    if not isinstance(message.get("type"), str):
        raise ViewerInputError('a message is a JSON object with a "type"')
    kind = message["type"]
    if kind == "command":
        if not isinstance(message.get("command"), str) or not isinstance(message.get("team", ""), str):
            raise ViewerInputError('a command needs "command" (a MatchMode name) and "team" (a team prefix)')
        try:
            mode = parse_match_mode(message["command"])
        except (NubotCommonError, ValueError) as exc:
            raise ViewerInputError(str(exc)) from None
        if mode not in COMMANDS:
            raise ViewerInputError(f"{mode.name} is not a command of the page (use rosrun coach4sim coach --console)")
        message["mode"] = mode
    elif kind == "watch":
        robot = message.get("robot", "")
        if not isinstance(robot, str) or len(robot) > ROBOT_NAME_MAX:
            raise ViewerInputError('"robot" must be a robot name or empty')
    elif kind == "replay":
        if message.get("action") not in ("play", "pause", "seek", "speed"):
            raise ViewerInputError('a replay control\'s "action" is play, pause, seek or speed')
        for key in ("t", "speed"):
            if key in message and (not isinstance(message[key], (int, float)) or isinstance(message[key], bool)
                                   or message[key] != message[key] or abs(message[key]) == float("inf")):
                raise ViewerInputError(f'"{key}" must be a finite number')
    else:
        raise ViewerInputError(f"unknown message type {kind!r} (command, watch or replay)")
    return message


def _forget(future: Any) -> None:
    """Take a finished write's outcome: a page that left makes its writes fail, which is no fault to report."""
    if not future.cancelled():
        future.exception()


def _send(handler: tornado.websocket.WebSocketHandler, text: str) -> Any:
    """Write ``text`` to the page; the write's failure, if it left meanwhile, is taken, never reported as lost."""
    future = handler.write_message(text)
    future.add_done_callback(_forget)
    return future


class _Client(tornado.websocket.WebSocketHandler):
    server: ViewerServer

    def initialize(self, server: ViewerServer) -> None:
        self.server = server
        self.watch = ""
        self.sending: Any = None  # the write in flight
        self.commands: list[float] = []  # when this page's latest commands came [s, monotonic]

    def prepare(self) -> None:
        self.server.check_host(self)

    def check_origin(self, origin: str) -> bool:
        return self.server.origin_allowed(origin, self.request.host_name) and super().check_origin(origin)

    def open(self, *args: str, **kwargs: str) -> None:
        self.set_nodelay(True)
        stream = getattr(self.ws_connection, "stream", None)
        if stream is not None and stream.socket is not None:  # a small send buffer: a slow page skips frames
            stream.socket.setsockopt(socket.SOL_SOCKET, socket.SO_SNDBUF, SEND_BUFFER)  # instead of lagging
        self.server.clients.add(self)
        _send(self, json.dumps({"type": "hello", **self.server.hello()}))

    def on_close(self) -> None:
        self.server.clients.discard(self)

    async def on_message(self, text: str | bytes) -> None:
        try:
            message = parse_page_message(text)
            reply = await self.server.handle(self, message)
        except CoachError as exc:  # ViewerInputError and the backend's refusals
            self.server.refused(self.request.remote_ip or "?", str(exc))
            reply = {"type": "error", "message": str(exc)}
        if reply is not None and self.ws_connection is not None:
            _send(self, json.dumps(reply))

    def push(self, text: str) -> bool:
        """Send a frame unless the last one is still on its way; True when sent."""
        if self.ws_connection is None or (self.sending is not None and not self.sending.done()):
            return False
        try:
            self.sending = _send(self, text)
        except tornado.websocket.WebSocketClosedError:
            return False
        return True


class _Page(tornado.web.RequestHandler):
    def initialize(self, server: ViewerServer) -> None:
        self.server = server

    def prepare(self) -> None:
        self.server.check_host(self)

    def get(self) -> None:
        self.set_header("Cache-Control", "no-store")
        self.set_header("Content-Type", "text/html; charset=utf-8")
        self.write((ASSETS / "index.html").read_bytes())


class _Static(tornado.web.StaticFileHandler):
    def initialize(self, path: str, server: ViewerServer) -> None:
        super().initialize(path)
        self.server = server

    def prepare(self) -> None:
        self.server.check_host(self)


class ViewerServer:
    """Serves the page and streams frames; ``run`` until ``stop``."""

    def __init__(self, backend: ViewerBackend, host: str = "127.0.0.1", port: int = 8080, token: str = "",
                 rate: float = 25.0, log: Callable[[str], None] = print):
        if not 1.0 <= rate <= 60.0:
            raise CoachError(f"the viewer's frame rate must lie in [1, 60] Hz, got {rate}")
        self.backend, self.host, self.port, self.rate, self.log = backend, host, port, rate, log
        self.token = token or ("" if is_loopback(host) else secrets.token_urlsafe(12))
        self.clients: set[_Client] = set()
        self.refusals = RejectionReporter(REFUSAL_LOG_INTERVAL)
        self.frames_sent = 0
        self.frames_skipped = 0
        self._stop: asyncio.Event | None = None
        self._hello: dict[str, Any] | None = None

    @property
    def url(self) -> str:
        """The page's address; served on every interface (0.0.0.0, ::), by this machine's name, which other machines
        can open (the wildcard address no machine can)."""
        host = socket.gethostname() if self.host in ("0.0.0.0", "::", "") else self.host
        host = f"[{host}]" if ":" in host else host
        return f"http://{host}:{self.port}/" + (f"?token={self.token}" if self.token else "")

    @property
    def open_to_loopback_only(self) -> bool:
        """Served on loopback without a token: only loopback names may be addressed."""
        return not self.token and is_loopback(self.host)

    def check_host(self, handler: tornado.web.RequestHandler) -> None:
        """Refuse (403) a request addressed to another name than loopback's, when loopback is all that is served
        (a rebound DNS name would otherwise let any web site's page in)."""
        if self.open_to_loopback_only and not is_loopback(handler.request.host_name):
            self.refused(handler.request.remote_ip or "?", f"request for host {handler.request.host_name!r}")
            raise tornado.web.HTTPError(403, "this viewer serves this machine's own pages only")

    def origin_allowed(self, origin: str, host: str) -> bool:
        if not self.open_to_loopback_only:
            return True
        try:
            return is_loopback(urlsplit(origin).hostname or "")
        except ValueError:
            return False

    def refused(self, peer: str, what: str) -> None:
        """Log a refused message or request of ``peer``: the first, then a line every few seconds with the count."""
        line = self.refusals.count(f"viewer: {peer}", "refused", what, time.monotonic())
        if line is not None:
            self.log(line)

    def hello(self) -> dict[str, Any]:
        return {**self.backend.hello(), "token_required": bool(self.token), "rate": self.rate,
                "commands": [{"name": m.name, "value": int(m)} for m in COMMANDS]}

    async def handle(self, client: _Client, message: dict[str, Any]) -> dict[str, Any] | None:
        kind = message["type"]
        if kind == "command":
            now = time.monotonic()
            client.commands = [t for t in client.commands if now - t < 1.0]
            if len(client.commands) >= MAX_COMMANDS_PER_SECOND:
                raise ViewerInputError(f"at most {MAX_COMMANDS_PER_SECOND} commands a second")
            client.commands.append(now)
        if kind == "watch":
            client.watch = message.get("robot", "")
            return None
        if kind == "replay":
            self.backend.control(message)
            return None
        if self.token and not hmac.compare_digest(str(message.get("token", "")).encode(), self.token.encode()):
            raise ViewerInputError("this viewer needs its token for commands (open the address it printed)")
        mode, team = message["mode"], message.get("team", "")
        loop = asyncio.get_running_loop()
        accepted, text = await loop.run_in_executor(None, self.backend.command, mode, team)
        self.log(f"viewer: {mode.name} for {team or 'the first team'}: {'done' if accepted else 'refused'}: {text}")
        return {"type": "result", "ok": accepted, "command": mode.name, "team": team, "message": text}

    def _tick(self) -> None:
        texts: dict[str, str | None] = {}
        for client in list(self.clients):
            if client.watch not in texts:
                texts[client.watch] = self.backend.frame(client.watch)
            text = texts[client.watch]
            if text is None:
                continue
            if client.push(text):
                self.frames_sent += 1
            else:
                self.frames_skipped += 1

    def application(self) -> tornado.web.Application:
        return tornado.web.Application([
            (r"/", _Page, {"server": self}),
            (r"/ws", _Client, {"server": self}),
            (r"/static/(.*)", _Static, {"path": str(ASSETS), "server": self}),
        ], websocket_max_message_size=MAX_MESSAGE, websocket_ping_interval=10.0)

    async def run(self, ready: Callable[[str], None] | None = None) -> None:
        """Serve until ``stop``; ``ready(url)`` once listening. Raises ``CoachError`` when the port is taken."""
        self._stop = asyncio.Event()
        try:
            http = self.application().listen(self.port, address=self.host, xheaders=False)
        except OSError as exc:
            raise CoachError(f"the viewer cannot listen on {self.host}:{self.port}: {exc.strerror}") from None
        if self.port == 0:
            self.port = next(iter(http._sockets.values())).getsockname()[1]
        if ready is not None:
            ready(self.url)
        period = 1.0 / self.rate
        next_tick = time.monotonic()
        try:
            while not self._stop.is_set():
                self._tick()
                next_tick = max(next_tick + period, time.monotonic())
                try:
                    await asyncio.wait_for(self._stop.wait(), next_tick - time.monotonic())
                except TimeoutError:
                    pass
        finally:
            http.stop()
            for client in list(self.clients):
                client.close()

    def stop(self) -> None:
        """End ``run`` (from the server's own loop)."""
        if self._stop is not None:
            self._stop.set()
