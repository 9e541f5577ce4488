"""Unit tests of the throttled refusal reports (nubot_common.rejections)."""

import re

import pytest

from nubot_common.rejections import RejectionReporter

_COUNT = re.compile(r"nubot1: velocity command rejected (\d+) time\(s\) since the last report")


def test_a_flood_gives_one_line_per_interval_that_counts_every_refusal():
    reporter = RejectionReporter(interval=5.0)
    lines = []
    for k in range(40_000):  # 20 s at 2000 Hz
        line = reporter.count("nubot1", "velocity command rejected", f"Vx=nan ({k})", k / 2000.0)
        lines += [line] if line else []
    lines += reporter.due(30.0)  # the flood's tail, once the interval has passed
    assert len(lines) == 5, lines
    assert sum(int(_COUNT.match(line)[1]) for line in lines) == 40_000
    assert lines[0].endswith("latest: Vx=nan (0)") and lines[-1].endswith("latest: Vx=nan (39999)")
    assert reporter.due(60.0) == [], "nothing left to report"


def test_robots_and_kinds_are_counted_apart_and_a_first_refusal_is_reported_at_once():
    reporter = RejectionReporter(interval=5.0)
    assert reporter.count("nubot1", "velocity command rejected", "nan", 0.0).startswith("nubot1: velocity command")
    assert reporter.count("nubot1", "velocity command rejected", "nan", 1.0) is None
    assert reporter.count("nubot2", "velocity command rejected", "inf", 1.0).startswith("nubot2:")
    assert "clamped 1 time(s)" in reporter.count("nubot1", "velocity command clamped", "(30, 40, 0)", 1.0)
    assert reporter.due(4.0) == []
    assert reporter.due(5.0) == ["nubot1: velocity command rejected 1 time(s) since the last report "
                                 "(at most one every 5 s); latest: nan"]
    assert reporter.due(20.0) == []
    assert reporter.count("nubot1", "velocity command rejected", "nan", 21.0) is not None, "quiet long enough"


def test_the_interval_must_be_positive():
    with pytest.raises(ValueError, match="interval must be positive, got 0"):
        RejectionReporter(0.0)


def test_a_nodes_refusal_log_says_the_first_at_once_and_the_rest_as_a_count():
    from nubot_common.rejections import RefusalLog

    now, lines = [0.0], []
    log = RefusalLog("omni_vision: nubot1", lines.append, interval=5.0, clock=lambda: now[0])
    for k in range(1000):
        log.refused("image refused", f"frame {k} is 3 x 3 px")
    assert lines == ["omni_vision: nubot1: image refused 1 time(s) since the last report (at most one every 5 s); "
                     "latest: frame 0 is 3 x 3 px"]
    now[0] = 6.0
    log.flush()
    assert len(lines) == 2 and "999 time(s)" in lines[1] and "frame 999" in lines[1]
