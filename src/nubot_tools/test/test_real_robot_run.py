"""real_robot_run's odometry check: integrating /nubotdriver/odoinfo over the truth's time span."""

import math

import pytest

from nubot_tools.ros.real_robot_run import drift


@pytest.mark.parametrize("offset", [0.001, 0.01, 0.019])
def test_odometry_that_agrees_with_the_truth_drifts_nothing_whatever_its_phase(offset):
    """A robot circling at 2 m/s and 1.3 rad/s, the truth at 100 Hz, exact odometry at 50 Hz stamped ``offset`` s
    after the truth's samples: the whole span is integrated, its ends too."""
    speed, w = 2.0, 1.3

    def pose(t):
        return math.sin(w * t) * speed / w, (1.0 - math.cos(w * t)) * speed / w, w * t

    truth = [(t, *pose(t)) for t in (k / 100.0 for k in range(0, 1001))]
    odo = [(k / 50.0 + offset, speed, 0.0, w) for k in range(-5, 506)]
    result = drift(truth, odo)
    assert result["travelled"] == pytest.approx(20.0, rel=1e-3)
    assert abs(result["heading_error"]) < 1e-9
    assert result["position_error"] < 0.01
