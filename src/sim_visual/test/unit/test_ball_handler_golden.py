"""The compiled ball-handler rules against the golden trace of the Python ones they replaced.

``golden/ball_handler.npz`` holds every call of the simulator's ``grip_holds``, ``dribble_condition`` and
``held_ball_position`` / ``held_ball_velocity`` over 2 x 30 s of seeded lockstep matches (seeds 0 and 1), and seeded
draws about their edges (2000 body velocities, 3000 balls within 0.8 m of a robot, 1000 held balls), as the Python
functions answered them (``python -m nubot_tools.golden ball_handler``): 4995 grip checks (1682 slipping), 8345
dribble checks (128 in reach), 4018 held balls. The compiled functions answer the same: the same operations in order
(tolerance 0; a ball exactly at the dribble distance could differ, since Python's hypot and the C library's may
differ in the last bit, and none of the trace's is)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nubot_common.geometry import Pose2D
from sim_visual import _kernels
from sim_visual.params import PluginParams
from sim_visual.rules import dribble_condition, grip_holds, held_ball_position, held_ball_velocity

TRACE = Path(__file__).resolve().parents[1] / "golden" / "ball_handler.npz"


@pytest.fixture(scope="module")
def trace():
    with np.load(TRACE) as data:
        return {k: data[k] for k in data.files}


def test_the_grip_holds_as_recorded(trace):
    rows = trace["grip"]
    assert len(rows) == 4995 and int((rows[:, 7] == 0).sum()) == 1682
    for vx, vy, w, forward, backward, sideways, turn, holds in rows:
        assert _kernels.grip_holds(vx, vy, w, forward, backward, sideways, turn) == bool(holds)
        params = PluginParams(hold_forward_speed=forward, hold_backward_speed=backward,
                              hold_sideways_speed=sideways, hold_turn_rate=turn)
        assert grip_holds(vx, vy, w, params) == bool(holds)


def test_the_ball_is_in_reach_as_recorded(trace):
    rows = trace["dribble"]
    assert len(rows) == 8345 and int(rows[:, 9].sum()) == 128
    for x, y, theta, bx, by, bz, radius, distance, half_angle, reach in rows:
        assert _kernels.dribble_condition(x, y, theta, bx, by, bz, radius, distance, half_angle) == bool(reach)
    params = PluginParams()
    default = rows[(rows[:, 7] == params.dribble_distance) & (rows[:, 8] == params.dribble_half_angle)]
    assert len(default) == len(rows)
    for x, y, theta, bx, by, bz, radius, *_rest, reach in default[::7]:
        assert dribble_condition(Pose2D(x, y, theta), bx, by, bz, radius, params) == bool(reach)


def test_the_held_ball_sits_and_moves_as_recorded(trace):
    rows = trace["held"]
    assert len(rows) == 4018
    for x, y, theta, vx, vy, w, hold, *recorded in rows:
        assert tuple(_kernels.held_ball(x, y, theta, vx, vy, w, hold)) == tuple(recorded)  # to the last bit
    params = PluginParams()
    for x, y, theta, vx, vy, w, _hold, hx, hy, hvx, hvy in rows[rows[:, 6] == params.hold_distance][::5]:
        assert held_ball_position(Pose2D(x, y, theta), params) == (hx, hy)
        assert held_ball_velocity(Pose2D(x, y, theta), vx, vy, w, params) == (hvx, hvy)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), float("-inf")])
def test_values_that_are_not_numbers_are_refused_by_name(bad):
    # The Python rules answered False for a NaN and raised "math domain error" for an infinite heading.
    params = PluginParams()
    for k in range(3):
        velocity = [0.5, 0.0, 0.0]
        velocity[k] = bad
        with pytest.raises(ValueError, match="body velocity must be finite"):
            grip_holds(*velocity, params)
    for k in range(6):
        values = [0.0, 0.0, 0.0, 0.3, 0.0, 0.11]
        values[k] = bad
        with pytest.raises(ValueError, match="(pose|position) must be finite"):
            dribble_condition(Pose2D(*values[:3]), *values[3:], 0.11, params)
    with pytest.raises(ValueError, match="state must be finite"):
        held_ball_velocity(Pose2D(0.0, 0.0, 0.0), bad, 0.0, 0.0, params)
