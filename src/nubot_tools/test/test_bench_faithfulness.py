"""The faithfulness bench's comparison of lockstep and ROS matches: what counts as agreeing."""

import math

import pytest

from nubot_tools.ros.bench_faithfulness import compare, figures, new_report


def match(goals: int, shots: int, collisions: int, minutes: float = 3.0, completion: float = 0.8) -> dict:
    """One match's compared figures, as ``figures`` gives them."""
    return {"goals_per_minute": goals / minutes, "shots_per_minute": shots / minutes, "passes_completed": 30.0,
            "pass_completion": completion, "possession_share": 0.5, "collisions_per_minute": collisions / minutes,
            "fouls_per_minute": 0.0, "running_share": 0.65, "running_time_s": 60.0 * minutes, "goals": float(goals),
            "shots": float(shots), "collisions": float(collisions), "fouls": 0.0}


def test_one_goal_in_each_of_four_matches_is_not_apart_from_none_in_four():
    """Identical counts give a Student-t interval of zero width; the count itself is still only known to within
    its Poisson noise, so 4 goals and 0 in 12 running minutes each are not told apart."""
    comparison = compare([match(1, 3, 2) for _ in range(4)], [match(0, 3, 2) for _ in range(4)])
    goals = comparison["goals_per_minute"]
    assert goals["lockstep"]["mean"] == pytest.approx(1 / 3, abs=1e-4)
    assert goals["lockstep"]["low"] < goals["lockstep"]["mean"] < goals["lockstep"]["high"]
    assert goals["ros"]["low"] == 0.0 and goals["ros"]["high"] == pytest.approx(3.689 / 12.0, abs=1e-3)
    assert goals["intervals_overlap"] is True


def test_rates_far_apart_are_still_apart_and_shares_keep_their_t_interval():
    comparison = compare([match(0, 2, 1) for _ in range(8)], [match(0, 2, 20) for _ in range(8)])
    assert comparison["collisions_per_minute"]["intervals_overlap"] is False  # 8 against 160 in 24 minutes
    shares = compare([match(1, 3, 2, completion=c) for c in (0.80, 0.82, 0.81)],
                     [match(1, 3, 2, completion=c) for c in (0.60, 0.62, 0.61)])
    assert shares["pass_completion"]["intervals_overlap"] is False  # a share is no count: no Poisson widening
    one = compare([match(2, 3, 2)], [match(2, 3, 2)])["goals_per_minute"]  # one match: the Poisson interval alone
    assert not math.isnan(one["lockstep"]["low"]) and one["intervals_overlap"] is True


def test_figures_carry_the_counts_behind_the_rates():
    report = {"running_time_s": 120.0, "stopped_time_s": 60.0, "score": {"nubot": 2, "rival": 1},
              "shot_report": {"counts": {"nubot": {"shots": 4}, "rival": {"shots": 2}}},
              "passes": {"nubot": {"tried": 10, "completed": 8}, "rival": {"tried": 10, "completed": 6}},
              "fouls": {"nubot": {"charging": 1}, "rival": {}}, "possession": {"nubot": {"share": 0.6}},
              "collisions": {"total": 5, "per_minute": 2.5}}
    f = figures(report)
    assert (f["goals"], f["shots"], f["collisions"], f["fouls"]) == (3.0, 6.0, 5.0, 1.0)
    assert f["goals_per_minute"] == 1.5 and f["shots_per_minute"] == 3.0
    assert f["running_share"] == pytest.approx(2 / 3, abs=1e-4)


def test_a_report_an_earlier_run_left_in_the_seed_s_folder_is_not_taken_for_this_run_s(tmp_path):
    old = tmp_path / "match-20260101-000000" / "report.json"
    old.parent.mkdir()
    old.write_text("{}")
    earlier = set(tmp_path.glob("match-*/report.json"))
    assert new_report(tmp_path, earlier) is None, "this run made no report: none, not the old one"
    made = tmp_path / "match-20260102-000000" / "report.json"
    made.parent.mkdir()
    made.write_text("{}")
    assert new_report(tmp_path, earlier) == made
