"""Fixtures shared by every package's tests: one private roscore per test session; and the property-based tests'
settings (Hypothesis): the same examples on every run (derandomized), no example database left in the tree."""


import pytest
from hypothesis import HealthCheck, settings

from nubot_common.processes import RosMaster

settings.register_profile("nubot", derandomize=True, database=None, deadline=None, max_examples=150,
                          suppress_health_check=[HealthCheck.too_slow])
settings.load_profile("nubot")


@pytest.fixture(scope="session")
def ros_master(tmp_path_factory):
    """A roscore on a free port, and this process registered with it as a (wall-time) node."""
    with RosMaster(tmp_path_factory.mktemp("ros")) as master:
        master.use_in_this_process()
        import rospy  # after ROS_MASTER_URI points at the private master

        rospy.init_node("integration_tests", anonymous=True, disable_signals=True)
        yield master
        rospy.signal_shutdown("tests done")
