"""node_io over a real roscore: a node told to stop while it sets itself up stops, at once once set up; a timer
keeps the period of sim time on the node's one /clock connection, and of wall time without sim time."""

from __future__ import annotations

import signal
import subprocess
import sys
import threading
import time

import pytest

pytestmark = pytest.mark.integration

# A set-up that is nothing but calls to the master from the main thread (as parameters, registrations and
# dynamic_reconfigure's are), so that a signal lands in the middle of one.
SETUP = """
import rospy
from nubot_common.node_io import starting_node

with starting_node("starting_up"):
    print("setting up", flush=True)
    for i in range(400):
        rospy.set_param("~step", i)
print("set up", flush=True)
rospy.spin()
print("stopped", flush=True)
"""


@pytest.mark.parametrize("sig", [signal.SIGINT, signal.SIGTERM])
def test_a_node_stopped_while_it_sets_itself_up_stops_once_set_up(ros_master, sig):
    node = subprocess.Popen([sys.executable, "-c", SETUP], env=ros_master.env, stdout=subprocess.PIPE, text=True)
    try:
        assert node.stdout.readline().strip() == "setting up"
        time.sleep(0.1)
        node.send_signal(sig)
        # rospy's own handler, run inside a call to the master, waited for that call's lock forever
        node.wait(timeout=20)
        assert node.stdout.read().split() == ["set", "up", "stopped"]
        assert node.returncode == 0
    finally:
        node.kill()
        node.wait()


TIMER = """
import rospy
from nubot_common.node_io import starting_node, timer

with starting_node("clock_timer"):
    timer(0.03, lambda e: print(f"cycle {rospy.Time.now().to_nsec()} {e.current_expected.to_nsec()}", flush=True))
print("ready", flush=True)
rospy.spin()
"""


def _cycles(lines: list[str]) -> list[tuple[int, int]]:
    return [(int(w[1]), int(w[2])) for w in (line.split() for line in lines) if w and w[0] == "cycle"]


class _Lines:
    """A child's output lines, read in a thread, so that the test can look at them while it runs."""

    def __init__(self, process: subprocess.Popen):
        self.lines: list[str] = []
        self._thread = threading.Thread(target=lambda: self.lines.extend(iter(process.stdout.readline, "")),
                                        daemon=True)
        self._thread.start()


def test_a_timer_on_sim_time_runs_every_period_of_the_clock_and_shares_the_nodes_clock_connection(ros_master):
    import rospy
    from rosgraph_msgs.msg import Clock

    from nubot_common.node_io import publisher
    from nubot_common.processes import wait_until

    previous = rospy.get_param("/use_sim_time", None)
    rospy.set_param("/use_sim_time", True)
    clock = publisher("/clock", Clock)
    node = subprocess.Popen([sys.executable, "-c", TIMER], env=ros_master.env, stdout=subprocess.PIPE, text=True)
    try:
        out = _Lines(node)
        wait_until(lambda: "ready\n" in out.lines and clock.get_num_connections() > 0, 20, "the node up")
        time.sleep(0.5)
        # rospy's own /clock subscription and the timer's are one connection: each tick is delivered once
        assert clock.get_num_connections() == 1

        def run(start_ms: int, ticks: int) -> None:
            for k in range(ticks):
                clock.publish(Clock(rospy.Time(nsecs=(start_ms + 10 * k) * 1_000_000)))
                time.sleep(0.01)

        run(1000, 61)  # 0.6 s of sim time in ticks of 10 ms
        time.sleep(0.3)
        first = _cycles(out.lines)
        assert 17 <= len(first) <= 20, f"one cycle every 30 ms of sim time: {first}"
        assert all(real >= expected for real, expected in first), "no cycle before it is due"
        expected = [e for _, e in first]
        assert all(b - a >= 30_000_000 for a, b in zip(expected, expected[1:])), expected
        # one period after the first tick it took (1.00 s, or a later one when rospy dropped it for a newer)
        assert 1_030_000_000 <= expected[0] <= 1_060_000_000, "the first cycle one period after the first tick"

        time.sleep(0.5)
        assert len(_cycles(out.lines)) == len(first), "no cycle while the clock stands still"

        run(200, 31)  # the clock went back (a simulator reset): the count starts again
        time.sleep(0.3)
        again = _cycles(out.lines)[len(first):]
        assert 8 <= len(again) <= 10, again
        assert 230_000_000 <= again[0][1] <= 260_000_000, again
    finally:
        node.terminate()
        node.wait(timeout=20)
        clock.unregister()
        _restore("/use_sim_time", previous)


def test_a_timer_on_wall_time_runs_without_a_clock(ros_master):
    import rospy

    from nubot_common.processes import wait_until

    previous = rospy.get_param("/use_sim_time", None)  # a launch file before this test may have set it
    rospy.set_param("/use_sim_time", False)
    node = subprocess.Popen([sys.executable, "-c", TIMER], env=ros_master.env, stdout=subprocess.PIPE, text=True)
    try:
        out = _Lines(node)
        wait_until(lambda: len(_cycles(out.lines)) >= 10, 20, "ten cycles on wall time")
        real = [r for r, _ in _cycles(out.lines)]
        assert all(b > a for a, b in zip(real, real[1:]))
    finally:
        node.terminate()
        node.wait(timeout=20)
        _restore("/use_sim_time", previous)


def _restore(name: str, value: object) -> None:
    import rospy

    if value is None:
        rospy.delete_param(name)
    else:
        rospy.set_param(name, value)
