"""Golden traces: a short recording of the MPC's calls in a lockstep match holds what a reproduction needs."""

import json
import math

import numpy as np
import pytest

from nubot_control.mpc import LaguerreMpc, MpcParams
from nubot_tools.golden import main, record_mpc, record_states


def test_a_recorded_call_gives_its_command_again():
    trace = record_mpc([0], seconds=2.0, per_status=4)
    kept = len(trace["status"])
    assert 4 <= kept <= 4 * len(set(trace["status"]))  # at most 4 of each way the command was found
    assert trace["ref_positions"].shape == (kept, 21, 2) and trace["command"].shape == (kept, 2)
    mpc = LaguerreMpc(MpcParams(**json.loads(str(trace["params"]))))
    limits = [None if math.isnan(v) else float(v) for v in (trace["max_speed"][0], trace["max_accel"][0])]
    u = mpc.command(trace["position"][0], trace["previous"][0], trace["ref_positions"][0], trace["ref_velocities"][0],
                    *limits)
    np.testing.assert_array_equal(u, trace["command"][0])
    assert mpc.last_status == trace["status"][0]


def test_bad_options_are_refused(tmp_path, capsys):
    for options in (["--seeds", "0"], ["--seconds", "-1"], ["--per-status", "0"]):
        with pytest.raises(SystemExit) as exit_:
            main(["mpc", "--out", str(tmp_path / "x.npz"), *options])
        assert exit_.value.code == 2
        assert "must be positive" in capsys.readouterr().err
    assert not (tmp_path / "x.npz").exists()


def test_one_play_records_both_ways_a_plan_is_read_back_and_each_call_reads_back_again():
    from nubot_control.path_planning import _trajectory

    trace = record_states([0], seconds=2.0, calls=6)
    single = trace["single"]
    assert 0 < single.sum() < len(single) == 6  # 3 of states_at, 3 of state_at, from the one match
    for i in range(len(single)):
        def rows(name, i=i):
            return trace[name][trace[f"{name}_offsets"][i]:trace[f"{name}_offsets"][i + 1]]
        t = rows("t").reshape(-1)
        xy, _ = _trajectory(t, t.copy(), rows("xy"), rows("v"), ()).states_at(rows("times").reshape(-1))
        np.testing.assert_array_equal(xy, rows("out_xy"))


def test_a_motion_layer_s_recorded_sequence_holds_every_cycle_of_the_robots_kept():
    from nubot_tools.golden import record_follow

    trace = record_follow([0], seconds=2.0, trackers=2)
    cycles = len(trace["kind"])
    assert set(trace["tracker"]) == {0, 1} and len(trace["params"]) == len(trace["dt"]) == 2
    assert 2 * 60 <= cycles <= 2 * 70  # every cycle of both at 33 Hz for 2 s
    for name, width in (("waypoints", 2), ("obstacles", 4), ("no_go", 4)):
        assert trace[name].shape[1] == width and len(trace[f"{name}_offsets"]) == cycles + 1
    assert trace["scalars"].shape == (cycles, 9) and trace["answers"].shape == (cycles, 8)
    follows = trace["kind"] == 0
    assert np.isfinite(trace["answers"][follows, :3]).all(), "every cycle's command"
