"""The compiled omni vision against the golden trace of the Python one it replaced.

``golden/sensing.npz`` holds every vision frame of 8 s of a seeded lockstep match (seed 0, 2400 frames) as the
Python ``sensing.observe`` made them: what each was given, the normal numbers it drew and what it gave
(``python -m nubot_tools.golden sensing``). Fed the same numbers, the compiled frames are the same to the last bit:
the arithmetic is the same operations in the same order on the same libm (tolerance 0)."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from nubot_common.team_frame import TeamFrame
from sim_visual.params import NoiseParams
from sim_visual.sensing import RobotFlags, observe, observe_all
from sim_visual.world import BallState, RobotState

TRACE = Path(__file__).resolve().parents[1] / "golden" / "sensing.npz"


class RecordedNormals:
    """The normal numbers the recorded frames drew, handed out in order (the generator they came from is gone)."""

    def __init__(self, numbers: np.ndarray):
        self.numbers, self.used = numbers, 0

    def normal(self, loc: float, scale: float, size: int) -> np.ndarray:
        assert (loc, scale) == (0.0, 1.0)
        out = self.numbers[self.used:self.used + size]
        assert len(out) == size, "the frame asked for more numbers than it drew"
        self.used += size
        return out


@pytest.fixture(scope="module")
def trace():
    with np.load(TRACE) as data:
        return {k: data[k] for k in data.files}


def _part(trace, name, i):
    offsets = trace[f"{name}_offsets"]
    return trace[name][offsets[i]:offsets[i + 1]]


def _inputs(trace, i):
    row = trace["frame"][i]
    me = RobotState(*row[1:7])
    flags = RobotFlags(*(bool(v) for v in row[9:13]))
    ball = BallState(row[13], row[14], 0.11, row[15], row[16], 0.0)
    others = [RobotState(*r) for r in _part(trace, "others", i)]
    return row[0], me, TeamFrame(int(row[7])), int(row[8]), flags, ball, others, NoiseParams(*row[17:22])


def _recorded(trace, i):
    seen, *ball = trace["ball"][i]
    return tuple(trace["robot"][i]), tuple(ball) if seen else None, [tuple(o) for o in _part(trace, "obstacles", i)]


def _made(view):
    r = view.robot
    ball = (view.ball.x, view.ball.y, view.ball.vx, view.ball.vy) if view.ball is not None else None
    return (r.pose.x, r.pose.y, r.pose.theta, r.vx, r.vy, r.w), ball, list(view.obstacles)


def test_every_recorded_frame_comes_back_to_the_last_bit(trace):
    frames = len(trace["frame"])
    assert frames == 2400
    for i in range(frames):
        stamp, me, frame, agent_id, flags, ball, others, noise = _inputs(trace, i)
        normals = RecordedNormals(_part(trace, "normals", i)[:, 0])
        view = observe(stamp, me, frame, agent_id, flags, ball, others, noise, normals)
        assert normals.used == len(normals.numbers), i
        assert _made(view) == _recorded(trace, i), i
        assert (view.stamp, view.robot.agent_id, view.robot.valid, view.robot.stuck, view.robot.holding,
                view.robot.kicking) == (stamp, agent_id, flags.valid, flags.stuck, flags.holding, flags.kicking)
        assert view.ball is None or (view.ball.stamp == stamp and view.ball.velocity_known)


def test_all_robots_at_once_give_the_frames_one_by_one(trace):
    # The simulator's robots each observed at one instant: the same robots in the same order, each robot's own
    # frame one of them; one call for all draws the numbers the frames drew one after the other.
    stamps = trace["frame"][:, 0]
    groups = [np.flatnonzero(stamps == t) for t in np.unique(stamps)]
    assert len(groups) == 240 and all(len(g) == 10 for g in groups)
    for group in groups:
        inputs = [_inputs(trace, i) for i in group]
        robots = [*inputs[0][6]]
        robots.insert(0, inputs[0][1])
        for k, (_, me, *_rest, others, _noise) in enumerate(inputs):
            assert [*others[:k], me, *others[k:]] == robots
        normals = RecordedNormals(np.concatenate([_part(trace, "normals", i)[:, 0] for i in group]))
        stamp, noise, ball = inputs[0][0], inputs[0][7], inputs[0][5]
        views = observe_all(stamp, robots, range(len(group)), [x[2] for x in inputs], [x[3] for x in inputs],
                            [x[4] for x in inputs], ball, noise, normals)
        assert normals.used == len(normals.numbers)
        assert [_made(v) for v in views] == [_recorded(trace, i) for i in group]


@pytest.mark.parametrize("bad", [float("nan"), float("inf")])
def test_a_state_that_is_not_a_number_is_refused_by_name(bad):
    me = RobotState(1.0, 2.0, 0.0, 0.0, 0.0, 0.0)
    ball = BallState(0.0, 0.0, 0.11, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="robot states must be finite"):
        observe(0.0, me, TeamFrame(1), 1, RobotFlags(), ball, [RobotState(bad, 0.0, 0.0, 0.0, 0.0, 0.0)],
                NoiseParams(), np.random.default_rng(0))
    with pytest.raises(ValueError, match="ball's state must be finite"):
        observe(0.0, me, TeamFrame(1), 1, RobotFlags(), BallState(0.0, bad, 0.11, 0.0, 0.0, 0.0), [], NoiseParams(),
                np.random.default_rng(0))


def test_an_observer_that_is_not_one_of_the_robots_is_refused():
    me = RobotState(1.0, 2.0, 0.0, 0.0, 0.0, 0.0)
    ball = BallState(0.0, 0.0, 0.11, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="observer 1 is not one of the 1 robots"):
        observe_all(0.0, [me], [1], [TeamFrame(1)], [1], [RobotFlags()], ball, NoiseParams(),
                    np.random.default_rng(0))
