"""The goalie benchmark: a quick run writes its figures and plot; every shot would score at an empty goal."""

import json

from nubot_tools.bench.goalie import main


def test_quick_run_saves_lobs_an_empty_goal_concedes_and_a_seed_gives_the_same_shots(tmp_path, capsys):
    assert main(["--quick", "--out", str(tmp_path), "--label", "test"]) == 0
    data = json.loads((tmp_path / "goalie_test.json").read_text())
    assert (tmp_path / "goalie_test.png").stat().st_size > 5000
    lob, ground = data["figures"]["lob"], data["figures"]["ground"]
    assert lob["shots"] == ground["shots"] == 10
    assert lob["saved"] >= 6, "the goalie meets lobs where they come down"
    assert lob["ci95"][0] <= lob["save_rate"] <= lob["ci95"][1]
    assert "lob:" in capsys.readouterr().out

    assert main(["--quick", "--out", str(tmp_path), "--label", "empty", "--no-goalie"]) == 0
    empty = json.loads((tmp_path / "goalie_empty.json").read_text())
    assert not any(s["saved"] for s in empty["shots"]), "every shot is aimed inside the goal mouth"
    assert [s["x"] for s in empty["shots"]] == [s["x"] for s in data["shots"]]

    assert main(["--quick", "--out", str(tmp_path), "--label", "again"]) == 0
    again = json.loads((tmp_path / "goalie_again.json").read_text())
    assert again["shots"] == data["shots"], "deterministic for a seed"


def test_a_goalie_seeing_through_its_rgbd_cameras_saves_a_seeded_lob_that_scores_at_an_empty_goal():
    from nubot_common.world_description import load_world
    from nubot_tools.bench.goalie import play_shot, seeded_shots

    world = load_world("18x12")
    shot = seeded_shots(1, 0, world)[0]
    assert shot["kind"] == "lob"
    assert not play_shot(0, shot, world, 0, goalie=False).saved
    saved = play_shot(0, shot, world, 0, vision=True)
    assert saved.saved, "kinect_ball's flight lets the goalie meet the lob"
