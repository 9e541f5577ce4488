"""Pure cores: no module under src/<pkg>/src/ imports rospy (STYLE.md practice 1); scripts stay two lines;
launch files clear each node's private parameters before loading its own.

Three kinds of places may import rospy, and no robot or simulator decision lives in any: ``nubot_tools.ros``,
tools that drive a ROS graph from outside (the match runner, the spawner, the benchmarks), as ``rostopic`` does;
``nubot_common.node_io``, the rospy plumbing the nodes share; and a package's ``<pkg>.ros``, the ROS side of its
nodes (parameters, topics, services, timers, conversions; e.g. ``world_model.ros`` and ``nubot_control.ros``: the
two nodes' classes, which the robot node runs together; ``coach4sim.ros.sender``: the way of sending a game command
that the coach, the viewer and the RefBox client share). No core module imports an adapter.
"""

import ast
import xml.etree.ElementTree as ElementTree
from pathlib import Path

WORKSPACE_SRC = Path(__file__).resolve().parents[2]


def test_core_modules_never_import_rospy():
    offenders = []
    adapters = sorted(WORKSPACE_SRC.glob("*/src/*/ros/*.py"))
    cores = sorted(p for p in WORKSPACE_SRC.glob("*/src/*/**/*.py") if p not in adapters and p.name != "node_io.py")
    assert cores and adapters, "no core modules or no adapters found"
    for path in cores:
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(n == "rospy" or n.startswith("rospy.") or ".ros." in f"{n}." for n in names):
                offenders.append(f"{path.relative_to(WORKSPACE_SRC)}:{node.lineno}")
    assert not offenders, f"core modules import rospy or a node's adapter: {offenders}"


def test_scripts_are_two_lines_around_a_package_module():
    """Every script in scripts/ calls one module's ``main``: the logic lives in a package, no sys.path edits. A
    script whose workers start in fresh processes (forkserver, which imports the script again) guards the call."""
    scripts = sorted((WORKSPACE_SRC.parent / "scripts").glob("*.py"))
    assert scripts, "no scripts found"
    for path in scripts:
        code = [line.split("#")[0].rstrip() for line in path.read_text().splitlines()
                if line.strip() and not line.startswith("#")]
        tools = code[0].startswith(("from nubot_tools", "from nubot_match")) if code else False
        plain = len(code) == 2 and code[1] == "raise SystemExit(main())"
        guarded = code[1:] == ['if __name__ == "__main__":', "    raise SystemExit(main())"]
        assert (plain or guarded) and tools and "sys.path" not in path.read_text(), f"{path.name}: {code}"


def test_every_launch_clears_what_it_loads_before_loading_it():
    """A key left on a shared roscore by an earlier launch (a typo the node refused) must not refuse the next one:
    each node's private namespace and /world are cleared before a launch loads them."""
    launches = sorted(WORKSPACE_SRC.glob("*/launch/*.launch"))
    assert launches, "no launch files found"
    keeping = []
    for path in launches:
        root = ElementTree.parse(path).getroot()
        keeping += [f"{path.name}: node {node.get('name')}" for node in root.iter("node")
                    if node.get("clear_params") != "true"]
        keeping += [f"{path.name}: /world" for group in root.iter("group")
                    if group.get("ns") == "/world" and group.get("clear_params") != "true"]
        keeping += [f"{path.name}: /world" for rosparam in root.iter("rosparam") if rosparam.get("ns") == "/world"]
    assert not keeping, f"loaded without clear_params=\"true\": {keeping}"


def test_nodes_publish_through_the_shared_synchronous_publisher():
    """rospy's queued publishers cost a thread switch per message and subscriber connection; in a 5 vs 5 match they
    took a third of the control cycles (``nubot_common.node_io``). Every node publishes through ``publisher``."""
    nodes = sorted(WORKSPACE_SRC.glob("*/nodes/*"))
    assert nodes, "no nodes found"
    queued = [f"{path.relative_to(WORKSPACE_SRC)}:{n}" for path in nodes
              for n, line in enumerate(path.read_text().splitlines(), 1) if "rospy.Publisher(" in line]
    assert not queued, f"publishers created with rospy.Publisher instead of nubot_common.node_io.publisher: {queued}"
