"""The front camera benchmark: a short run writes front_vision.json with plausible figures and its plot; the
figures but the times are deterministic for a seed. No ROS."""

import json
import os

import cv2

from nubot_tools.bench import front_vision as bf


def test_a_short_run_writes_plausible_deterministic_figures(tmp_path):
    before, threads = os.sched_getaffinity(0), cv2.getNumThreads()
    assert bf.main(["--balls", "40", "--seed", "2", "--out", str(tmp_path / "a")]) == 0
    assert os.sched_getaffinity(0) == before and cv2.getNumThreads() == threads  # both restored
    assert bf.main(["--balls", "40", "--seed", "2", "--out", str(tmp_path / "b"), "--cpu", "-1"]) == 0
    a, b = (json.loads((tmp_path / d / "front_vision.json").read_text()) for d in ("a", "b"))
    assert (tmp_path / "a" / "front_vision.png").stat().st_size > 10_000
    assert a["balls"] == 40 and len(a["samples"]) == 40 and a["seed"] == 2
    assert 0 < a["process_time_ms"]["median"] < 50 and isinstance(a["process_time_ms"]["met"], bool)
    near = a["error_within_1_5_m_cm"]
    assert near["samples"] == 0 or near["max"] < 5.0
    assert [b["from_m"] for b in a["bins"]] == list(bf.BINS[:-1])
    assert a["samples"] == b["samples"] and a["bins"] == b["bins"], "the same seed, the same figures"
