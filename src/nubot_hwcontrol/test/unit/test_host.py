"""The hardware control node's core: the loop's timing as the status reports it, the status once a second, and a
Shoot that waits for the cycle firing the kicker (from the callback thread, as the node's Shoot service runs)."""

import threading

import pytest

from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.host import HardwareHost, LoopTiming


def test_periods_and_overruns_on_the_nodes_clock():
    timing = LoopTiming(50.0)
    for t in (0.0, 0.02, 0.04, 0.06, 0.10, 0.12):  # one cycle late (40 ms)
        timing.tick(t)
    timing.tick(0.12)  # the same time again (a sim clock standing): not a period
    assert timing.overruns == 1
    p50, p99 = timing.take()
    assert p50 == pytest.approx(0.02) and p99 == pytest.approx(0.04, abs=0.002)
    assert timing.take() == (0.0, 0.0)  # taken: the next status starts afresh


def test_the_status_comes_once_a_second_with_the_controllers_state(rig):
    r = rig()
    host = HardwareHost(r.ctl, status_rate=1.0, start=0.0)
    statuses = []
    t = 0.0
    while t < 2.05:
        host.command_velocity(t, 0.5, 0.0, 0.0)
        done = host.cycle(t)
        assert done is not None
        _report, status = done
        if status is not None:
            statuses.append((t, status))
        for _ in range(4):
            r.sim.step()
        t = round(t + 0.02, 6)
    assert [round(t, 2) for t, _ in statuses] == [1.0, 2.0]
    first = statuses[0][1]
    assert first.backend == "sim" and first.power_on and first.overruns == 0
    assert first.loop_period_p50 == pytest.approx(0.02) and len(first.wheel_set_points) == 4
    assert any(abs(v) > 0.1 for v in first.wheel_speeds)  # the wheels turn for the 0.5 m/s command
    last = round(t - 0.02, 6)
    assert host.cycle(last) is None and host.skipped == 1  # the timer woke twice in one clock tick: no fault
    with pytest.raises(HardwareError):
        host.cycle(t - 1.0)  # a cycle before the previous one (the clock went back): refused


def test_a_shot_waits_for_the_cycle_that_fires_it(rig):
    r = rig(start=(-2.0, 0.0, 0.0), ball=(-1.2, 0.0))
    host = HardwareHost(r.ctl, status_rate=1.0, start=0.0)
    assert host.shoot(0.0, 6.0, -1) is False  # no ball held: refused at once
    host.ball_handle(1)
    r.run(2.5, command=lambda t: (0.6, 0.0, 0.0) if t < 0.8 else (0.0, 0.0, 0.0))
    answer: list[bool] = []
    caller = threading.Thread(target=lambda: answer.append(host.shoot(r.sim.time, 6.0, -1)))
    caller.start()
    while not answer and caller.is_alive():  # the timer's cycles go on while the caller waits
        host.cycle(r.sim.time)
        for _ in range(4):
            r.sim.step()
    caller.join(5.0)
    assert answer == [True] and r.ctl.shots == 1
