"""The lockstep benchmark's smoke run: its cheap parts write lockstep.json with positive figures and the plot."""

import json
import os

import pytest

from nubot_tools.bench import lockstep as bench_lockstep


def test_quick_run_writes_positive_figures(tmp_path):
    before = os.sched_getaffinity(0)
    assert bench_lockstep.main(["--quick", "--only", "lockstep,physics,env", "--out", str(tmp_path)]) == 0
    assert os.sched_getaffinity(0) == before  # pinning ends with the measurement
    data = json.loads((tmp_path / "lockstep.json").read_text())
    assert data["machine"]["cpus"] >= 1 and len(data["machine"]["load_average_start"]) == 3
    assert "a loaded machine lowers them" in data["machine"]["note"]
    for tracker in ("mpc", "baseline"):
        case = data["lockstep"][tracker]
        for key in ("sim_seconds_per_wall_second", "agent_cycles_per_second", "us_per_agent_cycle",
                    "us_per_physics_step", "us_per_physics_step_ode"):
            assert case[key] > 0, (tracker, key)
        assert case["sim_seconds"] == pytest.approx(10.0, abs=0.01)
        assert case["agent_cycles"] == pytest.approx(10 * 33 * 10, rel=0.1)  # 10 robots at 33 Hz for 10 s
        assert case["agent_cycle_in_physics_steps"] == pytest.approx(
            case["us_per_agent_cycle"] / case["us_per_physics_step"], rel=0.02)
        # Without the robots' software the match runs faster, and its time per cycle is what the budget has to fit.
        share = case["wall_share"]
        rest = case["wall_seconds"] * (1.0 - share["agents"] - share["world_model_vision"]
                                       - share["world_model_other_inputs"])
        assert case["sim_seconds_per_wall_second_without_agents"] > case["sim_seconds_per_wall_second"]
        assert case["sim_seconds_per_wall_second_without_agents"] == pytest.approx(case["sim_seconds"] / rest,
                                                                                   rel=0.02)
        budget = 1e6 * (case["sim_seconds"] / case["target_sim_seconds_per_wall_second"] - rest) / case["agent_cycles"]
        # recomputed from rounded figures: three shares to 0.001 of the wall, the times to 1 ms, the budget to 0.1 us
        rounding = 1e6 * (3 * 0.0005 * case["wall_seconds"] + 2 * 0.0005) / case["agent_cycles"] + 0.05
        assert case["us_per_agent_cycle_budget_at_target"] == pytest.approx(budget, abs=rounding)
    physics = data["physics"]
    assert physics["simulator"]["steps_per_second"] > 0 and physics["simulator"]["robots"] == 10
    assert physics["simulator"]["samples_with_robot_contact_share"] > 0  # the robots do meet
    for case in ("pyode", "pyode_scrum"):
        assert physics[case]["steps_per_second"] > 0 and physics[case]["contacts_per_step"] > 1  # not just the ball
    crowd = "robot_pairs_in_contact_mean"
    assert physics["simulator_scrum"][crowd] > physics["simulator"][crowd]
    assert data["env"]["steps_per_second"] > 0
    assert "memory" not in data and "evaluate" not in data
    assert (tmp_path / "lockstep.png").stat().st_size > 0


def test_unknown_part_is_refused(capsys):
    with pytest.raises(SystemExit):
        bench_lockstep.main(["--only", "physics,warp"])
    err = capsys.readouterr().err
    assert "parts are lockstep, recording, physics, env, memory, evaluate; got 'physics,warp'" in err
