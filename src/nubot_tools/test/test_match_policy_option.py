"""make match POLICY=<file>: a policy file the robots could not play is refused before anything starts."""

import pytest

from nubot_common.policy import PolicyNet
from nubot_tools.ros.match_runner import play


def refused(argv, capsys) -> str:
    with pytest.raises(SystemExit) as exit_info:
        play(argv)
    assert exit_info.value.code == 2
    return capsys.readouterr().err


def test_a_missing_policy_file_is_refused_before_the_match_starts(tmp_path, capsys):
    assert "no policy file" in refused(["--policy", str(tmp_path / "gone.npz"), "--out", str(tmp_path)], capsys)
    assert not list(tmp_path.glob("match-*")), "no match folder for a match that never started"


def test_a_policy_reading_what_a_robot_does_not_know_and_bad_robots_are_refused(tmp_path, capsys):
    names = ("x", "mate3_x")
    path = PolicyNet.constant([0.0] * 5, names, [-1.0, -1.0], [1.0, 1.0], [-5, -5, -12, 0, 0], [5, 5, 12, 1, 1]) \
        .save(tmp_path / "team.npz")
    assert "reads mate3_x, which a robot in a match does not know" in refused(["--policy", str(path)], capsys)
    good = PolicyNet.constant([0.0] * 5, ("x",), [-1.0], [1.0], [-5, -5, -12, 0, 0], [5, 5, 12, 1, 1]) \
        .save(tmp_path / "good.npz")
    assert "AgentIDs are whole numbers" in refused(["--policy", str(good), "--policy-robots", "two"], capsys)
    assert "7 is not one of the robots 1..5" in refused(["--policy", str(good), "--policy-robots", "7"], capsys)
