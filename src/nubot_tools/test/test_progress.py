"""SimProgress: a slow simulation is waited for, a stopped one is given up on."""

import pytest

from nubot_tools.progress import SimProgress


class Clock:
    def __init__(self):
        self.now = 0.0

    def __call__(self):
        return self.now


def test_a_simulation_at_a_tenth_of_real_time_is_never_stalled_a_stopped_one_is_after_the_patience():
    wall = Clock()
    progress = SimProgress(patience=60.0, wall=wall)
    sim = 0.0
    for _ in range(3000):  # 3000 s of wall time at 0.1 x real time, looked at every second
        wall.now += 1.0
        sim += 0.1
        assert not progress.stalled(sim)
    for _ in range(59):
        wall.now += 1.0
        assert not progress.stalled(sim)
    wall.now += 1.0
    assert progress.stalled(sim)
    assert "sim time at 300.0 s for 60 s of wall time" in progress.describe()
    wall.now += 1.0
    assert not progress.stalled(sim + 0.01), "moving again"


def test_patience_must_be_positive():
    with pytest.raises(ValueError, match="patience must be positive"):
        SimProgress(0.0)
