"""The Fig. 13 experiment over real ROS: nubot1 drives p0 -> p1 -> p2 -> p3 around two standing robots."""

import math
import threading

import pytest

from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

WAYPOINTS = [(-2.0, 2.0), (2.0, -2.0), (6.0, 2.0)]
HULL = 0.26


def test_mpc_drives_via_p1_and_p2_to_p3_without_touching_the_obstacles(ros_master):
    import rospy

    from nubot_common.msg import ModelStates, TrackingInfo

    lock = threading.Lock()
    path, rivals, finished = [], {}, []

    def on_states(msg):
        with lock:
            for name, pose in zip(msg.name, msg.pose):
                if name == "nubot1":
                    path.append((pose.position.x, pose.position.y))
                elif name.startswith("rival"):
                    rivals.setdefault(name, []).append((pose.position.x, pose.position.y))

    subs = [rospy.Subscriber("/sim_visual/model_states", ModelStates, on_states, queue_size=50),
            rospy.Subscriber("/nubot1/nubotcontrol/tracking", TrackingInfo,
                             lambda m: finished.append(m.header.stamp.to_sec()) if m.finished else None,
                             queue_size=10)]
    process = ros_master.launch("path_tracking", ["roslaunch", "nubot_control", "path_tracking.launch"])
    try:
        try:
            wait_until(lambda: finished, 60, "nubot1 to finish at p3", poll=0.1)
        except AssertionError as exc:
            raise AssertionError(f"{exc}; log:\n{process.log_text()[-3000:]}") from None
    finally:
        for sub in subs:
            sub.unregister()
        process.stop()
    with lock:
        assert math.dist(path[-1], WAYPOINTS[-1]) < 0.1, "stopped at p3"
        for point in WAYPOINTS[:2]:
            assert min(math.dist(p, point) for p in path) < 0.2, f"passed by {point}"
        for name, where in rivals.items():
            gap = min(math.dist(p, where[0]) for p in path) - 2 * HULL
            assert gap > 0.05, f"came within {gap:.3f} m of {name}'s hull"
            assert math.dist(where[0], where[-1]) < 0.01, f"{name} was pushed"
    assert "reached (" in process.log_text()
