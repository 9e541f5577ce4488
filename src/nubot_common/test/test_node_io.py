"""node_io over a real roscore: a node told to stop while it sets itself up stops, at once once set up."""

from __future__ import annotations

import signal
import subprocess
import sys
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
