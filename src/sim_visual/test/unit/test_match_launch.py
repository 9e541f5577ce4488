"""The match's viewing set-up, parsed (RViz is not installed here, so it is never started): match.launch runs
match_markers and includes RViz with rviz:=true; match_rviz.launch starts match_markers only when asked (for a bag);
the shipped RViz configuration shows the two marker topics and tf in the world frame; the bag leaves them out."""

from pathlib import Path

import pytest
import yaml

from nubot_common import launch_checks
from nubot_common.params import load_yaml
from sim_visual.markers import WORLD_FRAME, MatchMarkersParams

PACKAGE = Path(__file__).resolve().parents[2]


def launched(launch: str, *args: str) -> dict[str, dict]:
    return launch_checks.launched(PACKAGE / "launch" / launch, *args)


def test_every_match_runs_match_markers_and_rviz_only_when_asked():
    nodes = launched("match.launch")
    assert set(nodes) == {"/sim_visual", "/match_markers"}
    markers = nodes["/match_markers"]
    assert (markers["package"], markers["type"]) == ("sim_visual", "match_markers")
    assert MatchMarkersParams(markers["tf_rate"], markers["scene_rate"]) == load_yaml(
        MatchMarkersParams, PACKAGE / "config" / "match_markers.yaml")
    nodes = launched("match.launch", "rviz:=true")
    assert set(nodes) == {"/sim_visual", "/match_markers", "/rviz"}, "the match's own match_markers feeds RViz"
    assert (nodes["/rviz"]["package"], nodes["/rviz"]["type"]) == ("rviz", "rviz")
    assert nodes["/rviz"]["args"] == f"-d {PACKAGE / 'config' / 'match.rviz'}"


@pytest.mark.parametrize(("args", "nodes"), [((), {"/rviz"}), (("markers:=true",), {"/rviz", "/match_markers"})])
def test_match_rviz_starts_match_markers_for_a_bag_when_asked(args, nodes):
    assert set(launched("match_rviz.launch", *args)) == nodes


def test_the_rviz_configuration_shows_the_markers_and_tf_in_the_world_frame():
    config = yaml.safe_load((PACKAGE / "config" / "match.rviz").read_text())["Visualization Manager"]
    assert config["Global Options"]["Fixed Frame"] == WORLD_FRAME
    displays = {d["Class"]: d for d in config["Displays"]}
    assert {d.get("Marker Topic") for d in config["Displays"] if d["Class"] == "rviz/MarkerArray"} == \
        {"/match_markers/field", "/match_markers/scene"}
    assert displays["rviz/TF"]["Enabled"]
