"""Golden traces: a short recording of a lockstep match holds what a reproduction needs."""


import numpy as np
import pytest

from nubot_tools.golden import main, record_follow


def test_bad_options_are_refused(tmp_path, capsys):
    for options in (["--seeds", "0"], ["--seconds", "-1"], ["--trackers", "0"]):
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


def test_a_world_model_s_recorded_sequence_keeps_each_record_given_once_and_every_other_read():
    from nubot_tools.golden import record_world

    records = record_world([0], seconds=1.0, trackers=2)
    objects = [r for r in records if "object" in r]
    calls = [r for r in records if "call" in r]
    assert records[:len(objects)] == objects, "the records given come first"
    assert len({o["object"] for o in objects}) == len(objects)
    keys = {a["@"] for c in calls for a in c["args"] if isinstance(a, dict) and "@" in a}
    assert keys == {o["object"] for o in objects}, "every record given is kept, and only those"
    assert [c["call"] for c in calls if c["call"] == "__init__"] == ["__init__"] * 2
    for read in ("snapshot", "own_view"):
        results = [c["result"] for c in calls if c["call"] == read and c["robot"] == 0]
        assert results[0] is not None and results[1] is None and results[2] is not None, "every other read kept"
