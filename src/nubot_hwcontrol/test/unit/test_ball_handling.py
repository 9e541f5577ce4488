import numpy as np
import pytest

from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.ball_handling import BallHandler, BallHandlingParams


def test_the_arms_settle_at_the_set_point_without_overshoot_after_the_ball_comes_in(rig):
    """Step response: the ball enters the handler (arms jump towards 0.35), the PD pulls it to 0.65."""
    r = rig(start=(-2.0, 0.0, 0.0), ball=(-1.2, 0.0))
    r.ctl.ball_handle(1)
    arms = []
    r.run(4.0, command=lambda t: (0.6, 0.0, 0.0) if t < 0.8 else (0.0, 0.0, 0.0),
          each=lambda t, rep: arms.append((t, *rep.state.arms)))
    arms = np.array(arms)
    captured = arms[np.argmax(arms[:, 1] > 0.2), 0]
    after = arms[arms[:, 0] > captured]
    peak = after[:, 1:].max()
    assert peak <= 0.65 + 0.05  # overshoot bound: 0.05 of arm travel (noise 0.004 std included)
    settled = after[np.all(np.abs(after[:, 1:] - 0.65) < 0.03, axis=1)][0, 0]
    assert settled - captured < 2.0
    tail = after[after[:, 0] > settled + 0.5, 1:]
    assert np.abs(tail - 0.65).max() < 0.03
    assert r.ctl.ball.holding


def test_holding_needs_both_arms_up_for_ten_cycles():
    handler = BallHandler(BallHandlingParams(holding_cycles=10))
    handler.enable(True)
    for _ in range(9):
        handler.update((0.6, 0.6), 0.0, 0.02)
    assert not handler.holding
    handler.update((0.6, 0.6), 0.0, 0.02)
    assert handler.holding
    handler.update((0.6, 0.4), 0.0, 0.02)  # one arm drops: the ball is no longer between them
    assert not handler.holding


def test_the_feedforward_pulls_harder_when_the_robot_drives_backwards():
    handler = BallHandler()
    handler.enable(True)
    forward = handler.update((0.65, 0.65), 1.0, 0.02)[0]
    handler.enable(False)
    handler.enable(True)
    backward = handler.update((0.65, 0.65), -1.0, 0.02)[0]
    assert forward < 0.0 < backward and abs(backward) > abs(forward)


def test_disabled_arms_do_not_turn_and_bad_inputs_are_refused():
    handler = BallHandler()
    assert handler.update((0.2, 0.2), 0.0, 0.02) == (0.0, 0.0)
    with pytest.raises(HardwareError, match="finite"):
        handler.update((float("nan"), 0.2), 0.0, 0.02)
    with pytest.raises(HardwareError, match="set_point"):
        BallHandlingParams(set_point=1.2)
