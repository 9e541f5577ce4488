"""bench_team_link's latency and delivery part, short, in a namespace of its own (root only; the node's CPU part
needs a roscore and is left to ``make bench``)."""

import json

import pytest

from nubot_comm import netns
from nubot_tools.bench import team_link as bench_team_link

pytestmark = [pytest.mark.integration,
              pytest.mark.skipif(netns.unavailable() is not None, reason=str(netns.unavailable()))]


def test_latency_and_delivery_are_measured_under_loss_and_plotted(tmp_path):
    with netns.NetNamespace("benchtest") as ns:
        clean = bench_team_link.measure_latency(ns, 0, seconds=0.5, rate=100.0)
        lossy = bench_team_link.measure_latency(ns, 30, seconds=0.5, rate=100.0)
    assert (clean["sent"], clean["delivered"], clean["delivery_ratio"]) == (50, 50, 1.0)
    assert 0.0 < clean["p50_ms"] <= clean["p99_ms"] <= clean["max_ms"] < 50.0
    assert 0.3 < lossy["delivery_ratio"] < 0.95, "about 70 % of the datagrams get through"
    bench_team_link.plot([clean, lossy], tmp_path / "team_link.png")
    assert (tmp_path / "team_link.png").stat().st_size > 1000
    json.dumps(clean)


def test_without_root_the_benchmark_says_why_and_writes_nothing(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr(netns, "unavailable", lambda: "network namespaces need root")
    assert bench_team_link.main(["--out", str(tmp_path), "--seconds", "1"]) == 0
    assert "skipped: network namespaces need root" in capsys.readouterr().out
    assert list(tmp_path.iterdir()) == []
