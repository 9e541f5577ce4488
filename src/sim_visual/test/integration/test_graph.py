"""The running graph matches docs/topics.md: each topic has the one producer the table names."""

import re
from pathlib import Path

import pytest

pytestmark = pytest.mark.integration

TABLE = Path(__file__).resolve().parents[4] / "docs" / "topics.md"


def _rows(section: str) -> list[list[str]]:
    text = TABLE.read_text().split(f"## {section}")[1].split("## ")[0]
    rows = [[c.strip().strip("`") for c in line.strip("|").split("|")] for line in text.splitlines()
            if line.startswith("| `")]
    return [[c.replace("<r>", "nubot1") for c in row] for row in rows]


def test_running_graph_matches_the_topic_table(demo_launch, ros_master):
    process, sim, states = demo_launch
    sim.wait_for(lambda: states, timeout=60, what="the demo node")
    sim.wait_sim(0.5)
    graph = ros_master.graph()
    published, served = graph.publishers, graph.services
    for topic, _type, producer, *_ in _rows("Topics"):
        nodes = set(re.findall(r"/[a-z_]+", producer))
        assert topic in published, f"{topic} is in the table but nobody publishes it"
        assert len(published[topic]) == 1, f"{topic} has several producers: {published[topic]}"
        assert published[topic] <= nodes, f"{topic} is produced by {published[topic]}, table says {producer}"
    ours = {t for t, nodes in published.items() if nodes & {"/sim_visual", "/single_robot_demo"}}
    documented = {row[0] for row in _rows("Topics")}
    undocumented = {t for t in ours - documented if not t.startswith(("/rosout", "/sim_visual/parameter_"))}
    assert not undocumented, f"topics missing from docs/topics.md: {sorted(undocumented)}"
    for service, _type, server in _rows("Services"):
        assert served.get(service) == {server}, f"{service}: served by {served.get(service)}, table says {server}"
