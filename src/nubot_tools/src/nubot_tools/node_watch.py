"""Watch the nodes of a ROS graph on this machine: which ones died, which ones came back (no rospy here).

Provides ``NodeWatch(master_uri, nodes)``: ``nodes`` maps each node name (e.g. ``/sim_visual``) to
``True`` when the match cannot go on without it. ``poll()`` returns what changed since the last call
as ``NodeEvent``s: a node ``up`` (it registered with the master and answered with its process id),
``died`` (its process is gone) or ``back`` (a new process took its name). A node
that never came up is not reported here: the caller decides how long to wait for it
(``missing()`` lists them). The master itself is watched too, under the name ``/master``, and is
always critical. Liveness is the node's process (``/proc``), so the nodes must run on this machine.
"""

from __future__ import annotations

import xmlrpc.client
from dataclasses import dataclass
from pathlib import Path
from typing import Any

MASTER = "/master"
_CALLER = "/match_runner_watch"
_TIMEOUT = 2.0  # [s] for one XML-RPC call


@dataclass(frozen=True)
class NodeEvent:
    node: str
    change: str  # "up", "died" or "back"
    critical: bool
    detail: str = ""

    def describe(self) -> str:
        what = {"up": "is up", "died": "died", "back": "is back"}[self.change]
        kind = "required node" if self.critical else "node"
        return f"{kind} {self.node} {what}" + (f" ({self.detail})" if self.detail else "")


def _process_alive(pid: int) -> bool:
    """True while ``pid`` runs (a zombie does not)."""
    try:
        state = Path(f"/proc/{pid}/stat").read_text().rsplit(")", 1)[1].split()[0]
    except (OSError, IndexError):
        return False
    return state != "Z"


class _TimeoutTransport(xmlrpc.client.Transport):
    def make_connection(self, host):  # noqa: ANN001, ANN201 - xmlrpc's signature
        connection = super().make_connection(host)
        connection.timeout = _TIMEOUT
        return connection


def _ask(uri: str, method: str, *args: object) -> Any:
    """One ROS XML-RPC API call, as the caller ``_CALLER``: its (code, message, value) answer."""
    return getattr(xmlrpc.client.ServerProxy(uri, transport=_TimeoutTransport()), method)(_CALLER, *args)


def node_pid(master_uri: str, node: str) -> int | None:
    """The process id of ``node`` as the master knows it now, or None (not registered, not answering)."""
    try:
        code, _msg, uri = _ask(master_uri, "lookupNode", node)
        if code != 1:
            return None
        code, _msg, pid = _ask(uri, "getPid")
    except (OSError, xmlrpc.client.Error):  # OSError includes a timeout: a hung node counts as not answering
        return None
    return int(pid) if code == 1 else None


class NodeWatch:
    def __init__(self, master_uri: str, nodes: dict[str, bool]):
        self.master_uri = master_uri
        self.nodes = dict(nodes)
        self.pids: dict[str, int] = {}  # the process of each node seen up
        self.dead: set[str] = set()
        self.master_alive = True

    def _pid_of(self, node: str) -> int | None:
        return node_pid(self.master_uri, node)

    def _master_answers(self) -> bool:
        try:
            code, _msg, _uri = _ask(self.master_uri, "getUri")
        except (OSError, xmlrpc.client.Error):
            return False
        return code == 1

    def poll(self) -> list[NodeEvent]:
        events: list[NodeEvent] = []
        if self.master_alive and not self._master_answers():
            self.master_alive = False
            events.append(NodeEvent(MASTER, "died", True, f"{self.master_uri} does not answer"))
        for node, critical in self.nodes.items():
            pid = self.pids.get(node)
            if pid is not None and node not in self.dead:
                if _process_alive(pid):
                    continue
                self.dead.add(node)
                events.append(NodeEvent(node, "died", critical, f"process {pid} ended"))
                continue
            if not self.master_alive:
                continue
            new = self._pid_of(node)
            if new is None or not _process_alive(new) or new == pid:
                continue
            self.pids[node] = new
            if node in self.dead:
                self.dead.discard(node)
                events.append(NodeEvent(node, "back", critical, f"process {new}"))
            else:
                events.append(NodeEvent(node, "up", critical, f"process {new}"))
        return events

    def missing(self) -> list[str]:
        """Nodes that never came up."""
        return sorted(set(self.nodes) - set(self.pids))
