"""The compiled stuck detection against the golden trace of the Python one it replaced.

``golden/stuck.npz`` holds every update of the robots' stuck detection (the simulator's RobotInfo.isstuck) over 20 s
of a seeded lockstep match (seed 0) and 20 s of robots pushed into the goal, a side wall and each other and backing
off in turns (1202 of the 15,000 updates stuck), as the Python ``Simulator._update_stuck`` made them: the command,
the robot's position, the update's time and the detector's state before and after. The compiled update gives the same
state to the last bit (the same operations in order; tolerance 0)."""

from __future__ import annotations

import math
from pathlib import Path

import numpy as np
import pytest

from sim_visual import _kernels
from sim_visual.simulator import _STUCK_FILTER_TIME, _STUCK_MIN_COMMAND

TRACE = Path(__file__).resolve().parents[1] / "golden" / "stuck.npz"


def _state(row: np.ndarray) -> tuple:
    has_last, x, y, vx, vy, slow_since, stuck = row
    return bool(has_last), float(x), float(y), float(vx), float(vy), float(slow_since), bool(stuck)


def _same(a: tuple, b: tuple) -> bool:
    return all(x == y or (isinstance(x, float) and math.isnan(x) and math.isnan(y)) for x, y in zip(a, b))


@pytest.fixture(scope="module")
def trace():
    with np.load(TRACE) as data:
        return data["given"], data["gave"]


def test_every_recorded_update_comes_back_to_the_last_bit(trace):
    given, gave = trace
    assert len(given) == 15000 and int(gave[:, 6].sum()) == 1202
    for row, after in zip(given, gave):
        time, _robot, cvx, cvy, x, y, dt, stuck_time = row[:8]
        got = _kernels.update_stuck(_state(row[8:15]), cvx, cvy, x, y, dt, time, _STUCK_MIN_COMMAND,
                                    _STUCK_FILTER_TIME, stuck_time)
        assert _same(got, _state(after)), (row, after, got)


def test_the_updates_of_each_robot_follow_on_from_each_other(trace):
    # The detector run over a robot's recorded updates from its first one, feeding its own answers back.
    given, gave = trace
    for robot in np.unique(given[:, 1])[:3]:
        rows = np.flatnonzero(given[:, 1] == robot)
        state = _state(given[rows[0], 8:15])
        for i in rows:
            time, _robot, cvx, cvy, x, y, dt, stuck_time = given[i, :8]
            if not _same(_state(given[i, 8:15]), state):
                break  # another simulator's robot of the same name (the next match): start again from the trace
            state = _kernels.update_stuck(state, cvx, cvy, x, y, dt, time, _STUCK_MIN_COMMAND, _STUCK_FILTER_TIME,
                                          stuck_time)
            assert _same(state, _state(gave[i]))
