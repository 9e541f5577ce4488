"""Our base station's link to the MSL RefBox, without ROS: the connection (reconnecting with back-off, never giving
up), the commands read from it and the worldstates sent to it, and the picture of our team they are made from.

Provides ``TeamPicture`` (the latest world model and strategy of each of our robots, by arrival, and the worldstate
they make) and ``RefboxLink`` (``run`` keeps the connection until ``shutdown``: each command the box sends goes to
``on_command`` as a ``CommandEffect``, a malformed one is counted and dropped; every 1/worldstate_rate s [wall] it
sends ``worldstate()``; ``status()`` says how it goes). The refbox_client node gives them its topics, its
referee-or-topic way of putting a command in force and its logger.
"""

from __future__ import annotations

import select
import socket
import threading
import time
from collections.abc import Callable, Mapping
from typing import Any

from coach4sim import conversions as conv
from coach4sim.refbox import (
    Backoff,
    BallSnapshot,
    CommandEffect,
    FrameDecoder,
    OutageLog,
    RateMeter,
    RefboxClientParams,
    RefboxError,
    build_worldstate,
    choose_ball,
    encode_message,
    map_command,
    merge_obstacles,
    parse_command,
)
from nubot_common import NubotCommonError

Log = Callable[[str, str], None]  # (level: "info" or "warn", line)


class BoxGone(Exception):
    """The box closed the connection or stopped taking our bytes."""


class TeamPicture:
    """The latest world model and strategy of each of our robots (by AgentID, with their arrival [s, monotonic]),
    and the worldstate the fresh ones make."""

    def __init__(self, params: RefboxClientParams):
        self.params = params
        self.lock = threading.Lock()
        self.models: dict[int, tuple[float, Any]] = {}  # AgentID -> (arrival, WorldModelInfo)
        self.strategies: dict[int, tuple[float, Any]] = {}  # AgentID -> (arrival, StrategyInfo)

    def on_model(self, agent: int, msg: Any, arrival: float) -> None:
        with self.lock:
            self.models[agent] = (arrival, msg)

    def on_strategy(self, agent: int, msg: Any, arrival: float) -> None:
        with self.lock:
            self.strategies[agent] = (arrival, msg)

    def worldstate(self, intention: str, now: float) -> dict[str, Any]:
        """The worldstate of the robots heard within ``max_age`` of ``now`` [s, monotonic]."""
        p = self.params
        with self.lock:
            models = {a: m for a, m in self.models.items() if now - m[0] <= p.max_age}
            strategies = {a: s[1] for a, s in self.strategies.items() if now - s[0] <= p.max_age}
        robots, balls, opponents = [], [], []
        for agent, (_, msg) in sorted(models.items()):
            robot, ball, seen = conv.refbox_view(msg, agent, strategies.get(agent), p.battery_level)
            if robot is not None:
                robots.append(robot)
            if ball is not None:
                balls.append(ball)
            opponents.append(seen)
        newest = max((arrival for arrival, _ in models.values()), default=now)
        team_ball: tuple[BallSnapshot, float] | None = choose_ball(balls)
        return build_worldstate(p.team_name, intention, (now - newest) * 1000.0, robots, team_ball,
                                merge_obstacles(opponents, p.obstacle_merge, p.obstacle_radius))


class RefboxLink:
    """The TCP link to the box at ``params.host:port``: ``run`` it in a thread of its own; ``shutdown`` ends it."""

    def __init__(self, params: RefboxClientParams, worldstate: Callable[[], Mapping[str, Any]],
                 on_command: Callable[[CommandEffect], None], log: Log, on_change: Callable[[], None]):
        self.params = params
        self.worldstate, self.on_command, self.log, self.on_change = worldstate, on_command, log, on_change
        self.stop = threading.Event()
        self.lock = threading.Lock()
        self.outage = OutageLog(f"{params.host}:{params.port}")
        self.backoff = Backoff(params.reconnect_initial, params.reconnect_max)
        self.sent = RateMeter()
        self.counts = {"commands": 0, "malformed": 0}
        self.last_robots: list[int] = []
        self.sock: socket.socket | None = None
        self._quiet_until: dict[str, float] = {}  # warnings said at most once per period [s, monotonic]

    def status(self) -> dict[str, Any]:
        p = self.params
        with self.lock:
            return {"box": f"{p.host}:{p.port}", "connected": self.sock is not None,
                    "connections": self.outage.connections, "outages": self.outage.outages, **self.counts,
                    "worldstates_sent": self.sent.count, "worldstate_rate": round(self.sent.rate(time.monotonic()), 1),
                    "robots": list(self.last_robots)}

    def shutdown(self) -> None:
        self.stop.set()
        with self.lock:
            sock = self.sock
        if sock is not None:
            try:
                sock.shutdown(socket.SHUT_RDWR)
            except OSError:
                pass

    def run(self) -> None:
        p = self.params
        while not self.stop.is_set():
            try:
                sock = socket.create_connection((p.host, p.port), timeout=p.connect_timeout)
            except OSError as exc:
                line = self.outage.failed(time.monotonic(), exc.strerror or str(exc))
                if line:
                    self.log("warn", line)
                self.on_change()
                self.stop.wait(self.backoff.next_delay())
                continue
            connected = time.monotonic()
            self.log("info", self.outage.up(connected))
            with self.lock:
                self.sock = sock
            self.on_change()
            try:
                reason = self.serve(sock)
            except (OSError, BoxGone) as exc:
                reason = str(exc) or type(exc).__name__
            except Exception as exc:  # noqa: BLE001 - whatever a peer makes of us, the link reconnects, never dies
                reason = f"the link failed ({type(exc).__name__}: {exc}); reconnecting"
            finally:
                with self.lock:
                    self.sock = None
                sock.close()
            if time.monotonic() - connected >= p.reconnect_max:
                self.backoff.reset()  # a box that drops us at once (not our address range) is not asked every 0.5 s
            if not self.stop.is_set():
                self.log("warn", self.outage.lost(time.monotonic(), reason))
                self.on_change()
                self.stop.wait(self.backoff.next_delay())

    def serve(self, sock: socket.socket) -> str:
        """Read commands and send worldstates until the box goes away; return why it ended."""
        p = self.params
        sock.settimeout(p.connect_timeout)  # a send the box does not take within this ends the connection
        decoder = FrameDecoder(p.max_message)
        period = 1.0 / p.worldstate_rate
        next_send = time.monotonic()
        while not self.stop.is_set():
            readable, _, _ = select.select([sock], [], [], max(0.0, next_send - time.monotonic()))
            if readable:
                data = sock.recv(65536)
                if not data:
                    raise BoxGone("the box closed the connection")
                self.on_data(decoder, data)
            now = time.monotonic()
            if now >= next_send:
                self.send_worldstate(sock)
                next_send += period
                if next_send <= now:  # late (a stall): carry on from now instead of sending a burst
                    next_send = now + period
        return "shutting down"

    def on_data(self, decoder: FrameDecoder, data: bytes) -> None:
        for frame in decoder.feed(data):
            try:
                if frame.message is None:
                    raise RefboxError(frame.error)
                effect = map_command(parse_command(frame.message), self.params.identity)
            except RefboxError as exc:
                with self.lock:
                    self.counts["malformed"] += 1
                    count = self.counts["malformed"]
                self._warn_now_and_then("malformed", 1.0, f"message from the box dropped ({count} so far): {exc}")
                continue
            with self.lock:
                self.counts["commands"] += 1
            self.on_command(effect)

    def send_worldstate(self, sock: socket.socket) -> None:
        try:
            message = self.worldstate()
            data = encode_message(message)
        except (RefboxError, NubotCommonError) as exc:  # our own data is bad: skip this one, keep the link
            self._warn_now_and_then("worldstate", 5.0, f"no worldstate this time: {exc}")
            return
        try:
            sock.sendall(data)
        except TimeoutError:
            raise BoxGone(f"the box took no data for {self.params.connect_timeout:g} s") from None
        with self.lock:
            self.sent.add(time.monotonic())
            self.last_robots = [r["id"] for r in message["robots"]]

    def _warn_now_and_then(self, kind: str, period: float, line: str) -> None:
        now = time.monotonic()
        if now >= self._quiet_until.get(kind, -1.0):
            self._quiet_until[kind] = now + period
            self.log("warn", line)
