"""Golden traces: a short recording of a lockstep match holds what a reproduction needs."""


import numpy as np
import pytest

from nubot_tools.golden import main, record_follow


def test_bad_options_are_refused(tmp_path, capsys):
    for options in (["--seeds", "0"], ["--seconds", "-1"], ["--calls", "0"], ["--trackers", "0"]):
        with pytest.raises(SystemExit) as exit_:
            main(["follow", "--out", str(tmp_path / "x.npz"), *options])
        assert exit_.value.code == 2
        assert "must be positive" in capsys.readouterr().err
    assert not (tmp_path / "x.npz").exists()


def test_a_motion_layer_s_recorded_sequence_holds_every_cycle_of_the_robots_kept():
    trace = record_follow([0], seconds=2.0, trackers=2)
    cycles = len(trace["kind"])
    assert set(trace["tracker"]) == {0, 1} and len(trace["params"]) == len(trace["dt"]) == 2
    assert 2 * 60 <= cycles <= 2 * 70  # every cycle of both at 33 Hz for 2 s
    for name, width in (("waypoints", 2), ("obstacles", 4), ("no_go", 4)):
        assert trace[name].shape[1] == width and len(trace[f"{name}_offsets"]) == cycles + 1
    assert trace["scalars"].shape == (cycles, 9) and trace["answers"].shape == (cycles, 8)
    follows = trace["kind"] == 0
    assert np.isfinite(trace["answers"][follows, :3]).all(), "every cycle's command"
