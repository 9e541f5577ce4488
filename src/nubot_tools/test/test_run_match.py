"""End to end: a short refereed 2 vs 2 match over ROS on the 22 x 14 field, recorded and reported from its bag."""

import json
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from nubot_tools.match_report import read_match

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[3]


def test_short_two_vs_two_match_on_the_22_by_14_field_is_recorded_and_reported(tmp_path, two_vs_two):
    """``--field 22x14`` reaches every node: the simulator, the robots (the goalie's kickoff spot is on the
    22 x 14 goal line), the referee, and the report, which reads the field from the bag."""
    result = subprocess.run([sys.executable, str(ROOT / "scripts" / "run_match.py"), "--half-seconds", "20",
                             "--halves", "1", "--field", "22x14", "--out", str(tmp_path / "matches"), *two_vs_two],
                            capture_output=True, text=True, timeout=400)
    assert result.returncode == 0, result.stdout[-3000:] + result.stderr[-3000:]
    assert "kickoff for nubot" in result.stdout, "the referee starts the match"
    assert "on the 22 x 14 m field" in result.stdout
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
    assert (report["field"]["length_m"], report["field"]["width_m"], report["field"]["source"]) == (22.0, 14.0, "bag")
    log = read_match(folder / "match.bag")
    kickoff = next(r.t for r in log.referee if r.running)  # STARTROBOT of the first kickoff
    goalie = log.tracks["nubot1"]
    x, y = goalie.xy[np.searchsorted(goalie.t, kickoff)]
    assert (x, y) == pytest.approx((-10.6, 0.0), abs=0.3), "the goalie waited on the 22 x 14 goal line"
