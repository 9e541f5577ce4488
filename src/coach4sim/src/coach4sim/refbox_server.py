"""A practice RefBox: sends the box's commands to connected base stations and judges their worldstates.

Requires: nothing but sockets (no ROS); binds 127.0.0.1 unless told otherwise.
Provides: ``RefboxServer`` (accepts base stations on a TCP port, sends ``RefboxCommand``s and raw bytes to all of
them, decodes what they send with ``refbox.FrameDecoder``, checks each worldstate with
``refbox.worldstate_problems``, counts valid, invalid and malformed messages and the rate of valid worldstates per
connection, and logs every rejection); ``parse_script_line`` -> ``ScriptStep`` (the practice script's grammar,
``SCRIPT_HELP``); ``main`` (the ``refbox_server`` command line).
"""

from __future__ import annotations

import argparse
import socket
import sys
import threading
import time
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any, NoReturn, TextIO

from coach4sim.refbox import (
    COMMAND_RULES,
    DEFAULT_PORT,
    MAX_MESSAGE,
    TERMINATOR,
    FrameDecoder,
    RateMeter,
    RefboxCommand,
    RefboxError,
    encode_message,
    worldstate_problems,
)

Logger = Callable[[str], None]
KEPT_ERRORS = 100  # rejections kept in words (the count goes on: ``rejected``)


@dataclass
class Connection:
    """One base station connected to the server, and what it sent."""

    number: int  # 1, 2, ... in the order of connecting
    peer: str  # address:port
    sock: socket.socket
    decoder: FrameDecoder
    rate: RateMeter = field(default_factory=RateMeter)
    valid: int = 0  # worldstates that passed the validator
    invalid: int = 0  # JSON objects that did not
    malformed: int = 0  # frames that were no JSON object (or too long)
    last_worldstate: dict[str, Any] | None = None
    open: bool = True


@dataclass(frozen=True)
class ConnectionStats:
    number: int
    peer: str
    open: bool
    valid: int
    invalid: int
    malformed: int
    rate: float  # valid worldstates per second over the last 2 s [Hz]
    team_name: str  # the last valid worldstate's teamName

    def __str__(self) -> str:
        state = "connected" if self.open else "closed"
        return (f"#{self.number} {self.peer} ({self.team_name or 'no worldstate yet'}, {state}): "
                f"{self.rate:.1f} Hz, {self.valid} valid, {self.invalid} invalid, {self.malformed} malformed")


class RefboxServer:
    """The box's base-station side over TCP; thread-safe; ``start`` binds, ``close`` stops and disconnects all."""

    def __init__(self, host: str = "127.0.0.1", port: int = DEFAULT_PORT, max_message: int = MAX_MESSAGE,
                 welcome: bool = True, log: Logger | None = None):
        self.host, self.requested_port = host, port
        self.max_message = max_message
        self.welcome = welcome  # send WELCOME to each new connection, as the box does when it accepts a team
        self.log: Logger = log or (lambda text: None)
        self.lock = threading.Lock()
        self.connections: list[Connection] = []
        self.errors: list[str] = []  # the latest KEPT_ERRORS rejections, in words (each also logged)
        self.rejected = 0  # rejections in all
        self._listener: socket.socket | None = None
        self._threads: list[threading.Thread] = []
        self._closing = threading.Event()

    # --- life cycle --------------------------------------------------------------------------------
    def start(self) -> RefboxServer:
        listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)
        listener.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)  # restart on the same port at once
        try:
            listener.bind((self.host, self.requested_port))
        except OSError:
            listener.close()
            raise
        listener.listen(4)
        listener.settimeout(0.2)
        self._listener = listener
        self._spawn(self._accept_loop, "refbox-accept")
        self.log(f"RefBox practice server on {self.host}:{self.port}")
        return self

    @property
    def port(self) -> int:
        """The port bound (the one asked for, or the one the system chose for port 0)."""
        if self._listener is None:
            raise RefboxError("the server is not started")
        return int(self._listener.getsockname()[1])

    def close(self) -> None:
        """Stop listening and close every connection (the clients see the box go away)."""
        self._closing.set()
        if self._listener is not None:
            self._listener.close()
        with self.lock:
            for conn in self.connections:
                self._shut(conn)
        for thread in self._threads:
            thread.join(timeout=2.0)

    def __enter__(self) -> RefboxServer:
        return self.start()

    def __exit__(self, *_exc: object) -> None:
        self.close()

    # --- sending -----------------------------------------------------------------------------------
    def send(self, command: str, target_team: str = "", robot_id: int | None = None) -> int:
        """Send a command to every connected base station; return how many it reached."""
        cmd = RefboxCommand(command, target_team, robot_id)
        sent = self.send_raw(encode_message(cmd.to_message()))
        self.log(f"sent {cmd} to {sent} base station(s)")
        return sent

    def send_raw(self, data: bytes) -> int:
        """Send bytes as they are (practice: malformed or oversized messages); return the connections reached."""
        with self.lock:
            targets = [c for c in self.connections if c.open]
        sent = 0
        for conn in targets:
            try:
                conn.sock.sendall(data)
                sent += 1
            except OSError as exc:
                self._closed(conn, f"send failed: {exc}")
        return sent

    # --- what the clients sent ------------------------------------------------------------------------
    def stats(self) -> list[ConnectionStats]:
        now = time.monotonic()
        with self.lock:
            return [ConnectionStats(c.number, c.peer, c.open, c.valid, c.invalid, c.malformed, c.rate.rate(now),
                                    str((c.last_worldstate or {}).get("teamName", ""))) for c in self.connections]

    def open_connections(self) -> int:
        with self.lock:
            return sum(c.open for c in self.connections)

    def last_worldstate(self) -> dict[str, Any] | None:
        with self.lock:
            for conn in reversed(self.connections):
                if conn.last_worldstate is not None:
                    return conn.last_worldstate
        return None

    def wait_for(self, predicate: Callable[[], Any], timeout: float, what: str) -> Any:
        deadline = time.monotonic() + timeout
        while time.monotonic() < deadline:
            value = predicate()
            if value:
                return value
            time.sleep(0.02)
        raise TimeoutError(f"timed out after {timeout:g} s waiting for {what}")

    # --- threads ----------------------------------------------------------------------------------------
    def _spawn(self, target: Callable[..., None], name: str, *args: Any) -> None:
        thread = threading.Thread(target=target, args=args, name=name, daemon=True)
        self._threads.append(thread)
        thread.start()

    def _accept_loop(self) -> None:
        assert self._listener is not None
        while not self._closing.is_set():
            try:
                sock, (address, port) = self._listener.accept()
            except TimeoutError:
                continue
            except OSError:
                return  # closed
            sock.settimeout(0.2)
            failure = ""
            with self.lock:
                conn = Connection(len(self.connections) + 1, f"{address}:{port}", sock, FrameDecoder(self.max_message))
                if self.welcome:  # before the connection is listed: no command to every station can come first
                    try:
                        sock.sendall(encode_message(RefboxCommand("WELCOME").to_message()))
                    except OSError as exc:
                        failure = f"send failed: {exc}"
                self.connections.append(conn)
            self.log(f"base station #{conn.number} connected from {conn.peer}")
            if failure:
                self._closed(conn, failure)
                continue
            self._spawn(self._read_loop, f"refbox-read-{conn.number}", conn)

    def _read_loop(self, conn: Connection) -> None:
        while not self._closing.is_set() and conn.open:
            try:
                data = conn.sock.recv(65536)
            except TimeoutError:
                continue
            except OSError as exc:
                self._closed(conn, str(exc))
                return
            if not data:
                self._closed(conn, "the base station closed the connection")
                return
            for frame in conn.decoder.feed(data):
                self._judge(conn, frame.message, frame.error)

    def _judge(self, conn: Connection, message: dict[str, Any] | None, error: str) -> None:
        now = time.monotonic()
        if message is None:
            with self.lock:
                conn.malformed += 1
            self._reject(conn, f"rejected a malformed message: {error}")
            return
        problems = worldstate_problems(message)
        if problems:
            with self.lock:
                conn.invalid += 1
            self._reject(conn, "rejected an invalid worldstate: " + "; ".join(problems[:5])
                         + (f" (and {len(problems) - 5} more)" if len(problems) > 5 else ""))
            return
        with self.lock:
            conn.valid += 1
            conn.rate.add(now)
            conn.last_worldstate = message

    def _reject(self, conn: Connection, text: str) -> None:
        line = f"base station #{conn.number}: {text}"
        with self.lock:
            self.rejected += 1
            self.errors.append(line)
            del self.errors[:-KEPT_ERRORS]  # a peer sending rejects for hours must not fill the memory
        self.log(line)

    def _closed(self, conn: Connection, reason: str) -> None:
        with self.lock:
            if not conn.open:
                return
            self._shut(conn)
        if not self._closing.is_set():
            self.log(f"base station #{conn.number} disconnected ({reason})")

    @staticmethod
    def _shut(conn: Connection) -> None:
        conn.open = False
        try:
            conn.sock.shutdown(socket.SHUT_RDWR)
        except OSError:
            pass
        conn.sock.close()


# --- the practice script ----------------------------------------------------------------------------------
SCRIPT_HELP = """\
One step a line ('#' starts a comment):
  COMMAND [TARGET [ROBOT_ID]]  send a box command, e.g. KICKOFF A, YELLOW_CARD B 3, START
                               TARGET: A or B (--team-a / --team-b), - for both teams, or an address as it is
  wait SECONDS                 pause
  wait-clients N               pause until N base stations are connected
  raw TEXT                     send TEXT and a zero byte as they are (practise malformed input)
  status                       print what each base station sent
  help                         this text"""


@dataclass(frozen=True)
class ScriptStep:
    kind: str  # "send", "wait", "wait-clients", "raw", "status", "help" or "nothing"
    command: RefboxCommand | None = None
    seconds: float = 0.0
    count: int = 0
    text: str = ""


def parse_script_line(line: str, aliases: dict[str, str]) -> ScriptStep:
    """One line of a practice script (``SCRIPT_HELP``); ``aliases`` maps A and B to the teams' addresses.
    Raises ``RefboxError`` naming what is wrong."""
    text = line.split("#", 1)[0].strip()
    if not text:
        return ScriptStep("nothing")
    word, _, rest = text.partition(" ")
    word, rest = word.strip(), rest.strip()
    keyword = word.lower()
    if keyword == "raw":
        return ScriptStep("raw", text=rest)
    args = rest.split()
    if keyword in ("status", "help"):
        return ScriptStep(keyword)
    if keyword == "wait":
        seconds = _number(args, "wait SECONDS")
        if not 0.0 <= seconds <= 3600.0:
            raise RefboxError(f"wait takes 0 to 3600 seconds, got {seconds:g}")
        return ScriptStep("wait", seconds=seconds)
    if keyword == "wait-clients":
        count = int(_number(args, "wait-clients N"))
        if count < 1:
            raise RefboxError(f"wait-clients takes a count of at least 1, got {count}")
        return ScriptStep("wait-clients", count=count)
    command = word.upper()
    if command not in COMMAND_RULES:
        raise RefboxError(f"unknown command {word!r}; the box's commands: {', '.join(COMMAND_RULES)}")
    if len(args) > 2:
        raise RefboxError(f"too many words after {command}: {' '.join(args)} (TARGET and ROBOT_ID at most)")
    target = args[0] if args else "-"
    target = aliases.get(target.upper(), "" if target == "-" else target)
    robot = None
    if len(args) == 2:
        try:
            robot = int(args[1])
        except ValueError:
            raise RefboxError(f"ROBOT_ID must be a whole number, got {args[1]!r}") from None
    return ScriptStep("send", command=RefboxCommand(command, target, robot))


def _number(args: Sequence[str], usage: str) -> float:
    if len(args) != 1:
        raise RefboxError(f"usage: {usage}")
    try:
        return float(args[0])
    except ValueError:
        raise RefboxError(f"usage: {usage} (got {args[0]!r})") from None


# --- the command line -------------------------------------------------------------------------------------
class _Parser(argparse.ArgumentParser):
    def error(self, message: str) -> NoReturn:
        raise RefboxError(message)


def parse_server_args(argv: Sequence[str]) -> argparse.Namespace:
    parser = _Parser(prog="refbox_server", formatter_class=argparse.RawDescriptionHelpFormatter,
                     description="A practice MSL RefBox: sends commands from a script or typed lines to the base "
                                 "stations that connect, and checks their worldstates.", epilog=SCRIPT_HELP)
    parser.add_argument("--host", default="127.0.0.1", help="address to listen on (default 127.0.0.1)")
    parser.add_argument("--port", type=int, default=DEFAULT_PORT, help=f"TCP port (default {DEFAULT_PORT})")
    parser.add_argument("--script", default="", help="run the steps of this file; without it, read lines typed "
                                                      "on standard input")
    parser.add_argument("--team-a", default="224.16.32.53", help="the address TARGET A stands for (default NuBot's "
                                                                 "224.16.32.53)")
    parser.add_argument("--team-b", default="224.16.32.127", help="the address TARGET B stands for (default "
                                                                  "224.16.32.127)")
    parser.add_argument("--linger", type=float, default=0.0,
                        help="after the script, keep serving this long [s] (default 0)")
    parser.add_argument("--report-period", type=float, default=5.0,
                        help="print each base station's statistics this often [s] (0: never; default 5)")
    args = parser.parse_args(list(argv))
    if not 0 <= args.port <= 65535:
        raise RefboxError(f"--port must lie in [0, 65535], got {args.port}")
    if not 0.0 <= args.linger <= 24 * 3600.0:
        raise RefboxError(f"--linger must lie in [0, 86400] s, got {args.linger:g}")
    if not 0.0 <= args.report_period <= 3600.0:
        raise RefboxError(f"--report-period must lie in [0, 3600] s, got {args.report_period:g}")
    return args


def run_steps(server: RefboxServer, lines: Sequence[str] | TextIO, aliases: dict[str, str],
              out: Callable[[str], None]) -> int:
    """Run a script's lines against ``server``; return the number of lines refused (each one is reported)."""
    refused = 0
    for number, line in enumerate(lines, 1):
        try:
            step = parse_script_line(line, aliases)
        except RefboxError as exc:
            out(f"line {number}: {exc}")
            refused += 1
            continue
        if step.kind == "send" and step.command is not None:
            c = step.command
            server.send(c.command, c.target_team, c.robot_id)
        elif step.kind == "wait":
            time.sleep(step.seconds)
        elif step.kind == "wait-clients":
            while server.open_connections() < step.count:
                time.sleep(0.05)
        elif step.kind == "raw":
            reached = server.send_raw(step.text.encode() + TERMINATOR)
            out(f"sent {len(step.text)} raw bytes and a zero byte to {reached} base station(s)")
        elif step.kind == "status":
            out("\n".join(str(s) for s in server.stats()) or "no base station has connected")
        elif step.kind == "help":
            out(SCRIPT_HELP)
    return refused


def main(argv: Sequence[str] | None = None) -> None:
    def out(text: str) -> None:
        print(f"[{time.strftime('%H:%M:%S')}] {text}", flush=True)

    try:
        args = parse_server_args(sys.argv[1:] if argv is None else argv)
        lines: Sequence[str] | TextIO = sys.stdin
        if args.script:
            with open(args.script, encoding="utf-8") as handle:
                lines = handle.readlines()
    except (RefboxError, OSError) as exc:
        print(f"refbox_server: {exc}", file=sys.stderr)
        sys.exit(2)
    server = RefboxServer(args.host, args.port, log=out)
    try:
        server.start()
    except OSError as exc:
        print(f"refbox_server: cannot listen on {args.host}:{args.port}: {exc}", file=sys.stderr)
        sys.exit(1)
    done = threading.Event()

    def report() -> None:
        while not done.wait(args.report_period):
            for stats in server.stats():
                out(str(stats))

    if args.report_period > 0:
        threading.Thread(target=report, daemon=True).start()
    refused = 0
    try:
        refused = run_steps(server, lines, {"A": args.team_a, "B": args.team_b}, out)
        time.sleep(args.linger)
    except KeyboardInterrupt:
        pass
    finally:
        done.set()
        for stats in server.stats():
            out(str(stats))
        server.close()
    sys.exit(1 if refused else 0)
