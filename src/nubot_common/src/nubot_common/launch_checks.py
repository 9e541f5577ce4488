"""Checks of how nodes take their parameters over a real roscore, shared by the packages' tests (no rospy).

Provides ``run_refused`` (run a node with one bad private parameter: its exit status and output),
``refused_then_up`` (a launch with a typo in its YAML is refused; the same launch without it, on the
same roscore, then comes up: nothing the refused one loaded stays behind), ``launched`` (the nodes a launch
file starts, parsed by roslaunch with nothing started) and ``nested`` (a launched node's parameters as the node
reads them, for ``from_mapping``).
"""

from __future__ import annotations

import re
import subprocess
import time
import xmlrpc.client
from collections.abc import Callable, Sequence
from pathlib import Path
from typing import Any

from nubot_common.processes import RosMaster, wait_until

RUN_TIMEOUT = 30.0  # [s] for a node that must refuse its parameters and exit
UP_TIMEOUT = 60.0  # [s] for a launch to refuse or come up
LAUNCH_KEYS = ("package", "type", "args", "remap", "required")  # what ``launched`` tells besides a node's parameters


def run_refused(master: RosMaster, package: str, node: str, param: str, world: Path) -> tuple[int, str]:
    """Run ``node`` with the bad private ``param`` (``_key:=value``), ``world`` loaded into /world."""
    subprocess.run(["rosparam", "load", str(world), "/world"], env=master.env, check=True, timeout=30)
    name = "refused_" + re.sub(r"\W", "_", param.strip("_"))  # its own private namespace: no stale keys
    try:
        result = subprocess.run(["rosrun", package, node, param, f"__name:={name}"], env=master.env,
                                capture_output=True, text=True, timeout=RUN_TIMEOUT)
    except subprocess.TimeoutExpired:
        raise AssertionError(f"{node} {param} still runs after {RUN_TIMEOUT} s") from None
    return result.returncode, result.stdout + result.stderr


def refused_then_up(master: RosMaster, label: str, launch: Sequence[str], typo: Sequence[str],
                    is_up: Callable[[Any], bool]) -> str:
    """Start ``launch`` plus the ``typo`` arguments, wait for its refusal, then ``launch`` alone until ``is_up``
    (asked of the master). Returns the refused launch's log; raises AssertionError if the second is refused."""
    refused = master.launch(f"{label}_typo", [*launch, *typo])
    try:
        wait_until(lambda: "exit code" in refused.log_text(), UP_TIMEOUT, f"{label} to refuse the typo", 0.05)
        log = refused.log_text()
    finally:
        refused.stop()
    proxy: Any = xmlrpc.client.ServerProxy(master.uri)
    fixed = master.launch(f"{label}_fixed", list(launch))

    def outcome() -> str:
        if "exit code" in fixed.log_text():
            return "refused"
        return "up" if is_up(proxy) else ""

    try:
        result = wait_until(outcome, UP_TIMEOUT, f"{label} to come up or exit", 0.05)
        assert result == "up", f"{label}: a correct launch was refused:\n{fixed.log_text()[-3000:]}"
    finally:
        fixed.stop()
        time.sleep(0.5)  # let the master forget the stopped nodes before the next test launches its own
    return log


def publishes(topic: str, node: str) -> Callable[[Any], bool]:
    """``is_up`` for ``refused_then_up``: ``node`` publishes ``topic``."""
    return lambda master: dict(master.getSystemState("/t")[2][0]).get(topic) == [node]


def serves(service: str) -> Callable[[Any], bool]:
    """``is_up`` for ``refused_then_up``: someone serves ``service``."""
    return lambda master: bool(master.lookupService("/t", service)[0] == 1)


def launched(launch: Path, *args: str) -> dict[str, dict[str, Any]]:
    """The nodes a launch file starts with ``args``: namespaced name -> its package, type, command-line arguments,
    remappings, whether it is required (its end ends the launch) and private parameters (parsed by roslaunch; nothing
    is started and no master is needed)."""
    import roslaunch.config
    import roslaunch.xmlloader

    config = roslaunch.config.ROSLaunchConfig()
    roslaunch.xmlloader.XmlLoader().load(str(launch), config, argv=["roslaunch", *args], verbose=False)
    nodes = {}
    for node in config.nodes:
        name = f"{node.namespace.rstrip('/')}/{node.name}"
        private = {k[len(name) + 1:]: p.value for k, p in config.params.items() if k.startswith(name + "/")}
        nodes[name] = {"package": node.package, "type": node.type, "args": node.args, "remap": dict(node.remap_args),
                       "required": node.required, **private}
    return nodes


def nested(node: dict[str, Any], leave_out: Sequence[str] = ()) -> dict[str, Any]:
    """A ``launched`` node's private parameters as the nested mapping the node reads from ``~`` (``a/b: 1`` ->
    ``{a: {b: 1}}``), without the launch's own keys (package, type, args, remap) and those in ``leave_out``."""
    tree: dict[str, Any] = {}
    for key, value in node.items():
        if key in LAUNCH_KEYS or key in leave_out:
            continue
        *parents, leaf = key.split("/")
        branch = tree
        for parent in parents:
            branch = branch.setdefault(parent, {})
        branch[leaf] = value
    return tree
