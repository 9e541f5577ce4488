"""Fixtures for integration tests: a private roscore on a free port, an in-process test node,
and the simulator launched with its real launch file."""

from __future__ import annotations

import os
import threading
import time
from pathlib import Path

import pytest

from nubot_common.geometry import quaternion_to_yaw
from nubot_common.processes import RosMaster, wait_until


class SimClient:
    """Watches the simulator's topics and wraps its services, in sim time."""

    def __init__(self, robot: str = "nubot1"):
        import rospy
        from rosgraph_msgs.msg import Clock

        from nubot_common.msg import GoalEvent, ModelStates, OmniVisionInfo

        self.robot = robot
        self.lock = threading.Lock()
        self.clock = 0.0
        self.states: dict[str, tuple] = {}
        self.goals: list = []
        self.vision: list = []
        self.subs = [
            rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10),
            rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=10),
            rospy.Subscriber("/sim_visual/goal", GoalEvent, self._on_goal, queue_size=10),
            rospy.Subscriber(f"/{robot}/omnivision/OmniVisionInfo", OmniVisionInfo, self._on_vision, queue_size=100),
        ]
        self.cmd_pub = None  # created on first use: the demo's world must have one velcmd producer

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()
        if self.cmd_pub is not None:
            self.cmd_pub.unregister()

    def _on_clock(self, msg) -> None:
        self.clock = msg.clock.to_sec()

    def _on_states(self, msg) -> None:
        with self.lock:
            for name, pose, twist in zip(msg.name, msg.pose, msg.twist):
                p, o, v, w = pose.position, pose.orientation, twist.linear, twist.angular
                self.states[name] = (p.x, p.y, p.z, quaternion_to_yaw(o.x, o.y, o.z, o.w), v.x, v.y, v.z, w.z)
            self.states_clock = self.clock

    def _on_goal(self, msg) -> None:
        self.goals.append(msg)

    def _on_vision(self, msg) -> None:
        self.vision.append((self.clock, msg))

    def state(self, name: str) -> tuple:
        with self.lock:
            return self.states[name]

    def wait_for(self, predicate, timeout: float = 30.0, what: str = "condition"):
        return wait_until(predicate, timeout, what, 0.01)

    def wait_sim(self, seconds: float, command=None, rate: float = 33.0) -> None:
        """Let ``seconds`` of sim time pass, publishing ``command`` (Vx, Vy, w) at ``rate`` Hz."""
        import rospy

        from nubot_common.msg import VelCmd

        if command is not None and self.cmd_pub is None:
            self.cmd_pub = rospy.Publisher(f"/{self.robot}/nubotcontrol/velcmd", VelCmd, queue_size=1)
            time.sleep(0.3)  # let the simulator connect before the first command
        end = self.clock + seconds
        next_cmd = self.clock
        while self.clock < end:
            if command is not None and self.clock >= next_cmd:
                self.cmd_pub.publish(VelCmd(*command))
                next_cmd += 1.0 / rate
            time.sleep(0.002)

    def service(self, name: str, srv_type):
        import rospy

        rospy.wait_for_service(name, timeout=20.0)
        return rospy.ServiceProxy(name, srv_type)

    @staticmethod
    def set_model(name: str, x: float, y: float, *, z: float = 0.0, yaw: float = 0.0) -> None:
        from nubot_common.node_io import set_model_state

        set_model_state(name, x, y, z, yaw)


def launch_sim(master: RosMaster, name: str, *args: str):
    process = master.launch(name, ["roslaunch", "sim_visual", "single_robot.launch", *args])
    return process


@pytest.fixture(scope="module")
def sim_launch(ros_master):
    """The single-robot world without the demo, at real time, noise-free perception off by default."""
    process = launch_sim(ros_master, "single_robot", "demo:=false", "real_time_factor:=1.0")
    client = SimClient()
    try:
        client.wait_for(lambda: "nubot1" in client.states and client.clock > 0.1, timeout=60,
                        what="the simulator's first model states")
    except AssertionError:
        process.stop()
        raise AssertionError(f"simulator did not start:\n{process.log_text()[-4000:]}") from None
    yield process, client
    client.close()
    process.stop()
    # Let the master forget the stopped nodes before the next module launches its own.
    time.sleep(0.5)


@pytest.fixture
def sim(sim_launch):
    """A freshly reset single-robot world: nubot1 at (-2, 0) facing +x, the ball at (1, 2)."""
    from std_srvs.srv import Empty

    process, client = sim_launch
    assert process.alive(), process.log_text()[-4000:]
    client.service("/sim_visual/reset_world", Empty)()
    client.wait_sim(0.1)
    client.goals.clear()
    client.vision.clear()
    return client


LOG_DIR = Path(os.environ.get("ROS_LOG_DIR", "/tmp"))


@pytest.fixture(scope="module")
def demo_launch(ros_master):
    """The single-robot world with the demo node, at real time; yields (process, client, states)."""
    import rospy
    from std_msgs.msg import String

    states: list[tuple[float, str]] = []
    client = SimClient()
    sub = rospy.Subscriber("/nubot1/demo/state", String, lambda m: states.append((client.clock, m.data)),
                           queue_size=50)
    process = launch_sim(ros_master, "single_robot_demo", "demo:=true", "real_time_factor:=1.0")
    yield process, client, states
    sub.unregister()
    client.close()
    process.stop()
    time.sleep(0.5)
