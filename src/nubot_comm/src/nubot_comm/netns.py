"""Network namespaces for the team link's tests and benchmark: multicast on loopback only, with loss and delay.

Requires: root, iproute2 (``ip netns``) and, for loss, nftables (``nft``). Nothing here sends to any address
but the multicast group, on the loopback of a namespace made here. Provides:
- ``unavailable()``: None, or why namespaces cannot be made here (a test skips with it);
- ``NetNamespace``: a namespace with ``lo`` up and 224.0.0.0/4 routed to it; ``command`` runs a program in it,
  ``set_loss`` drops that share of the UDP datagrams to a port at random on input (nftables ``numgen``),
  ``close`` ends what still runs inside and deletes it (also left-overs of a killed run: ``sweep_stale``);
- ``entered``: the calling thread inside a namespace for a while (its sockets stay there);
- ``DelayRelay``: forwards every datagram of a multicast group heard in one namespace to the others, after a
  fixed delay (this kernel has no netem): robots in two namespaces as on two ends of a slow link.
"""

from __future__ import annotations

import contextlib
import ctypes
import heapq
import os
import re
import select
import shutil
import signal
import socket
import struct
import subprocess
import threading
import time
from collections.abc import Iterator, Sequence
from dataclasses import dataclass, field
from urllib.parse import urlparse

from nubot_comm import NubotCommError
from nubot_comm.codec import DEFAULT_URL

PREFIX = "nubotcomm"  # every namespace made here is named nubotcomm-<pid of its maker>-<tag>
_NAME = re.compile(rf"{PREFIX}-(?P<pid>[0-9]+)-[A-Za-z0-9_]+")
CLONE_NEWNET = 0x40000000
LOSS_TABLE = "nubot_comm_loss"
MAX_DATAGRAM = 65535
_libc = ctypes.CDLL(None, use_errno=True)


def group_of(url: str = DEFAULT_URL) -> tuple[str, int]:
    """(multicast group, port) of an ``udpm://`` LCM URL."""
    parsed = urlparse(url)
    if parsed.scheme != "udpm" or parsed.hostname is None or parsed.port is None:
        raise NubotCommError(f"not an udpm://group:port URL: {url!r}")
    return parsed.hostname, parsed.port


def unavailable() -> str | None:
    """Why network namespaces cannot be made here, or None."""
    if os.geteuid() != 0:
        return "network namespaces (where alone the link's multicast runs) need root"
    missing = [tool for tool in ("ip", "nft") if shutil.which(tool) is None]
    if missing:
        return f"{' and '.join(missing)} not installed (iproute2, nftables)"
    return None


def _ip(*args: str) -> None:
    result = subprocess.run(["ip", *args], capture_output=True, text=True, timeout=30)
    if result.returncode != 0:
        raise NubotCommError(f"ip {' '.join(args)}: {result.stderr.strip()}")


def _namespaces() -> list[str]:
    out = subprocess.run(["ip", "netns", "list"], capture_output=True, text=True, timeout=30).stdout
    return [line.split()[0] for line in out.splitlines() if line.strip()]


def _delete(name: str) -> None:
    """End every process still inside ``name`` (all started by its maker), then delete it."""
    pids = subprocess.run(["ip", "netns", "pids", name], capture_output=True, text=True, timeout=30).stdout.split()
    for pid in pids:
        with contextlib.suppress(ProcessLookupError, ValueError):
            os.kill(int(pid), signal.SIGKILL)
    subprocess.run(["ip", "netns", "del", name], capture_output=True, timeout=30)


def sweep_stale() -> list[str]:
    """Delete the namespaces of this module whose maker is no longer running (a run killed before its cleanup)."""
    swept = []
    for name in _namespaces():
        match = _NAME.fullmatch(name)
        if match and not os.path.exists(f"/proc/{match['pid']}"):
            _delete(name)
            swept.append(name)
    return swept


class NetNamespace:
    """A network namespace of our own, with only ``lo`` (up) and multicast routed to it; a context manager."""

    def __init__(self, tag: str):
        if not re.fullmatch(r"[A-Za-z0-9_]{1,20}", tag):
            raise NubotCommError(f"a namespace tag is 1 to 20 letters, digits or underscores, got {tag!r}")
        self.name = f"{PREFIX}-{os.getpid()}-{tag}"
        self._made = False

    def __enter__(self) -> NetNamespace:
        self.open()
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def open(self) -> None:
        sweep_stale()
        if self.name in _namespaces():
            _delete(self.name)
        _ip("netns", "add", self.name)
        self._made = True
        try:
            _ip("-n", self.name, "link", "set", "lo", "up")
            _ip("-n", self.name, "route", "add", "224.0.0.0/4", "dev", "lo")
        except NubotCommError:
            self.close()
            raise

    def close(self) -> None:
        if self._made:
            _delete(self.name)
            self._made = False

    def command(self, *args: str) -> list[str]:
        """``args`` as a command that runs inside the namespace."""
        return ["ip", "netns", "exec", self.name, *args]

    def set_loss(self, port: int, percent: int) -> None:
        """Drop ``percent`` % of the UDP datagrams to ``port`` at random as they come in (0: none)."""
        if not 0 <= percent <= 100:
            raise NubotCommError(f"loss is a percentage 0..100, got {percent}")
        subprocess.run(self.command("nft", "delete", "table", "inet", LOSS_TABLE), capture_output=True, timeout=30)
        if percent == 0:
            return
        rules = (f"table inet {LOSS_TABLE} {{\n"
                 f"  chain input {{\n"
                 f"    type filter hook input priority 0; policy accept;\n"
                 f"    udp dport {port} numgen random mod 100 < {percent} drop\n"
                 f"  }}\n"
                 f"}}\n")
        result = subprocess.run(self.command("nft", "-f", "-"), input=rules, capture_output=True, text=True,
                                timeout=30)
        if result.returncode != 0:
            raise NubotCommError(f"nft in {self.name}: {result.stderr.strip()}")


@contextlib.contextmanager
def entered(name: str) -> Iterator[None]:
    """Run the calling thread inside network namespace ``name``; sockets made meanwhile stay in it."""
    with open("/proc/thread-self/ns/net", "rb") as home, open(f"/var/run/netns/{name}", "rb") as target:
        if _libc.setns(target.fileno(), CLONE_NEWNET) != 0:
            raise NubotCommError(f"cannot enter {name}: {os.strerror(ctypes.get_errno())}")
        try:
            yield
        finally:
            if _libc.setns(home.fileno(), CLONE_NEWNET) != 0:
                raise NubotCommError(f"cannot leave {name}: {os.strerror(ctypes.get_errno())}")


def group_receiver(group: str, port: int) -> socket.socket:
    """A UDP socket that hears ``group``:``port`` beside LCM's own (in the calling thread's namespace)."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEADDR, 1)
    sock.setsockopt(socket.SOL_SOCKET, socket.SO_REUSEPORT, 1)
    sock.bind(("", port))
    sock.setsockopt(socket.IPPROTO_IP, socket.IP_ADD_MEMBERSHIP,
                    struct.pack("4s4s", socket.inet_aton(group), socket.inet_aton("0.0.0.0")))
    return sock


def group_sender() -> socket.socket:
    """A UDP socket that sends to a multicast group with TTL 1, from a port of its own."""
    sock = socket.socket(socket.AF_INET, socket.SOCK_DGRAM, socket.IPPROTO_UDP)
    sock.setsockopt(socket.IPPROTO_IP, socket.IP_MULTICAST_TTL, 1)
    sock.bind(("", 0))
    return sock


@dataclass
class _End:
    namespace: str
    receiver: socket.socket
    sender: socket.socket
    own_port: int  # what the relay sent into this namespace comes back from this port: not forwarded again


@dataclass(order=True)
class _Pending:
    due: float
    seq: int
    to: int = field(compare=False)
    data: bytes = field(compare=False)


class DelayRelay:
    """Forwards each datagram of ``group``:``port`` heard in one of ``namespaces`` to the others after ``delay``."""

    def __init__(self, namespaces: Sequence[str], url: str = DEFAULT_URL, delay: float = 0.05):
        if len(namespaces) < 2 or not delay >= 0.0:
            raise NubotCommError(f"a relay joins two namespaces or more with a delay >= 0, got {namespaces}, {delay}")
        self.group, self.port = group_of(url)
        self.delay = delay
        self.forwarded = 0
        self._ends: list[_End] = []
        for name in namespaces:
            with entered(name):
                receiver, sender = group_receiver(self.group, self.port), group_sender()
            self._ends.append(_End(name, receiver, sender, sender.getsockname()[1]))
        self._stop = threading.Event()
        self._thread = threading.Thread(target=self._run, name="delay_relay", daemon=True)

    def __enter__(self) -> DelayRelay:
        self._thread.start()
        return self

    def __exit__(self, *_exc: object) -> None:
        self.close()

    def close(self) -> None:
        self._stop.set()
        if self._thread.is_alive():
            self._thread.join(timeout=5.0)
        for end in self._ends:
            end.receiver.close()
            end.sender.close()

    def _run(self) -> None:
        pending: list[_Pending] = []
        count = 0
        by_socket = {end.receiver: i for i, end in enumerate(self._ends)}
        while not self._stop.is_set():
            now = time.monotonic()
            while pending and pending[0].due <= now:
                item = heapq.heappop(pending)
                with contextlib.suppress(OSError):
                    self._ends[item.to].sender.sendto(item.data, (self.group, self.port))
                    self.forwarded += 1
            wait = min(pending[0].due - now, 0.05) if pending else 0.05
            readable, _, _ = select.select(list(by_socket), [], [], max(wait, 0.0))
            for sock in readable:
                source = by_socket[sock]
                data, (_host, from_port) = sock.recvfrom(MAX_DATAGRAM)
                if from_port == self._ends[source].own_port:
                    continue
                for to in range(len(self._ends)):
                    if to != source:
                        count += 1
                        heapq.heappush(pending, _Pending(time.monotonic() + self.delay, count, to, data))
