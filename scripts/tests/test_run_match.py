"""End to end: a short refereed 2 vs 2 match over ROS, recorded and reported from its bag."""

import json
import subprocess
import sys
from pathlib import Path

import pytest
import yaml

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[2]


def test_short_two_vs_two_match_is_recorded_and_reported(tmp_path):
    teams = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = tmp_path / f"{prefix}.yaml"
        path.write_text(yaml.safe_dump({"name": prefix.title(), "prefix": prefix, "attack": attack, "goalie": 1,
                                        "robots": [{"x": -8.4, "y": 0.0}, {"x": -1.0, "y": 0.5}]}))
        teams += ["--team", str(path)]
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds", "20",
                             "--halves", "1", "--out", str(tmp_path / "matches"), *teams],
                            capture_output=True, text=True, timeout=400)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "kickoff for nubot" in result.stdout, "the referee starts the match"
    assert "end of the match" in result.stdout
    folder = next((tmp_path / "matches").iterdir())
    assert (folder / "match.bag").stat().st_size > 100_000
    report = json.loads((folder / "report.json").read_text())
    assert set(report["distance_run_m"]) == {"nubot1", "nubot2", "rival1", "rival2"}
    assert max(report["distance_run_m"].values()) > 5.0, "field players ran"
    assert report["score_agrees"]
    assert report["kicks"] or sum(report["score"].values()), "the ball was played: kicked or scored"
    assert report["possession"]["nobody"]["share"] < 0.5, "robots reach the ball"
    for png in ("heatmap.png", "trajectories.png"):
        assert (folder / png).stat().st_size > 10_000
