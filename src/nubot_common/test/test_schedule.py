import pytest

from nubot_common import NubotCommonError
from nubot_common.schedule import Periodic


def test_a_periodic_task_fires_once_per_period_without_drifting():
    task = Periodic(1.0 / 33.0)
    fired = [k * 0.005 for k in range(200_000) if task.due(k * 0.005)]  # 1000 s of 5 ms steps
    assert fired[0] == 0.0
    assert len(fired) == pytest.approx(1000 * 33, abs=1)  # 33 Hz over 1000 s, not 1000 / 0.035
    assert all(b - a in (pytest.approx(0.030), pytest.approx(0.035)) for a, b in zip(fired, fired[1:]))
    with pytest.raises(NubotCommonError, match="period must be positive"):
        Periodic(0.0)


def test_a_period_of_whole_steps_fires_on_every_one_of_its_steps_though_the_step_sums_drift():
    # 0.005 s steps summed as k * 0.005 fall a hair below or above multiples of 0.01: the task must still fire
    # every second step, 100 times a second, not every third step now and then.
    task = Periodic(0.010)
    fired = [k for k in range(20_000) if task.due(k * 0.005)]
    assert fired == list(range(0, 20_000, 2))


def test_a_late_call_fires_once_and_the_schedule_catches_up_without_a_burst():
    task = Periodic(0.030)
    assert task.due(0.0)
    assert task.due(0.200)  # six due times passed: one firing
    assert not task.due(0.205)
    assert task.next == pytest.approx(0.210)
