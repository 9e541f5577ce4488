"""kinect_ball over real ROS: the simulator gives the goalie (seeing through its cameras) its two RGB-D clouds, a
rival lobs the ball at its goal, and BallInfo3d predicts where the ball comes down; bad clouds on the same topics
are logged and skipped, never a crash."""

from __future__ import annotations

import math
import threading
import time

import numpy as np
import pytest

from nubot_common.ball_flight import landing
from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

GOALIE = (-8.4, 0.2)  # world frame; nubot1 attacks +x, so its team frame is the world frame
SHOOTER = (-2.5, -1.0)  # rival2, lobbing at the goal at -x
RADIUS = 0.11


class Watch:
    def __init__(self) -> None:
        import rospy

        from nubot_common.msg import BallInfo3d, ModelStates

        self.lock = threading.Lock()
        self.infos: list = []
        self.ball: list[tuple[float, ...]] = []  # (t, x, y, z, vx, vy, vz) of the true ball
        self.subs = [rospy.Subscriber("/nubot1/kinect/ballinfo", BallInfo3d, self._on_info, queue_size=100),
                     rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=100)]

    def _on_info(self, msg) -> None:
        with self.lock:
            self.infos.append(msg)

    def _on_states(self, msg) -> None:
        if "football" in msg.name:
            k = msg.name.index("football")
            p, v = msg.pose[k].position, msg.twist[k].linear
            with self.lock:
                self.ball.append((msg.header.stamp.to_sec(), p.x, p.y, p.z, v.x, v.y, v.z))

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


def _service(name: str, kind):
    import rospy

    rospy.wait_for_service(name, timeout=30.0)
    return rospy.ServiceProxy(name, kind)


def _spawn(name: str, x: float, y: float, yaw: float, attack: int) -> None:
    from geometry_msgs.msg import Pose

    from nubot_common.srv import SpawnModel

    pose = Pose()
    pose.position.x, pose.position.y = x, y
    pose.orientation.z, pose.orientation.w = math.sin(yaw / 2), math.cos(yaw / 2)
    response = _service("/sim_visual/spawn_model", SpawnModel)(name, pose, attack)
    assert response.success, response.status_message


def _bad_clouds() -> list:
    """A NaN-filled cloud and one without colours, as a broken driver might send them."""
    import genpy
    from sensor_msgs.msg import PointCloud2, PointField

    from nubot_common.clouds import cloud_msg

    nan = cloud_msg(np.full((4, 5, 3), np.nan), np.zeros((4, 5, 3), np.uint8), PointCloud2, PointField,
                    genpy.Time(0, 1000), "nubot1/kinect_left")
    no_rgb = cloud_msg(np.zeros((4, 5, 3)), np.zeros((4, 5, 3), np.uint8), PointCloud2, PointField,
                       genpy.Time(0, 2000), "nubot1/kinect_left")
    no_rgb.fields = no_rgb.fields[:3]
    return [nan, no_rgb]


@pytest.fixture(scope="module")
def goalie_world(ros_master):
    """match.launch with nubot1 (its team's goalie) seeing through its cameras, the shooter rival2, and
    kinect_ball for nubot1 taking its pose from the simulator's truth (no omni_vision: a short test)."""
    sim = ros_master.launch("kinect_sim", ["roslaunch", "sim_visual", "match.launch", "vision:=nubot1",
                                           "clock_rate:=200"])
    node = None
    watch = Watch()
    try:
        _spawn("nubot1", *GOALIE, 0.0, 1)
        heading = math.atan2(0.3 - SHOOTER[1], -9.0 - SHOOTER[0])
        _spawn("rival2", SHOOTER[0] - 0.43 * math.cos(heading), SHOOTER[1] - 0.43 * math.sin(heading), heading, -1)
        node = ros_master.launch("kinect_ball", ["roslaunch", "kinect_ball", "kinect_ball.launch", "robot:=nubot1",
                                                 "pose:=/nubot1/sim_visual/truth"])
        wait_until(lambda: len(watch.infos) > 10, 30, "BallInfo3d from kinect_ball")
    except AssertionError:
        logs = "\n".join(p.log_text()[-3000:] for p in (sim, node) if p is not None)
        for p in (node, sim):
            if p is not None:
                p.stop()
        watch.close()
        raise AssertionError(f"the goalie's world did not start:\n{logs}") from None
    yield sim, node, watch
    watch.close()
    node.stop()
    sim.stop()
    time.sleep(0.5)


def test_bad_clouds_are_logged_and_skipped(goalie_world):
    import rospy
    from sensor_msgs.msg import PointCloud2

    _, node, watch = goalie_world
    pub = rospy.Publisher("/nubot1/kinect/left/points", PointCloud2, queue_size=10)
    wait_until(lambda: pub.get_num_connections() > 0, 10, "kinect_ball subscribed")
    for msg in _bad_clouds():
        pub.publish(msg)
    count = len(watch.infos)
    wait_until(lambda: "left cloud refused: a cloud needs fields x, y, z and rgb" in node.log_text(), 10,
               "the refusal in kinect_ball's log")
    wait_until(lambda: len(watch.infos) > count + 10, 10, "BallInfo3d still coming")
    assert node.alive()
    pub.unregister()


def test_a_lob_at_the_goalie_is_predicted_to_come_down_where_it_lands(goalie_world):
    """The ball lobbed from 6.5 m: the touchdown BallInfo3d predicts 0.3 s before the ball lands (the latest
    message by then) lies within 15 cm of where it comes down (from the simulator's true states)."""
    import dynamic_reconfigure.client

    from nubot_common.node_io import set_model_state
    from nubot_common.srv import BallHandle, Shoot

    _, node, watch = goalie_world
    set_model_state("football", *SHOOTER, RADIUS)
    assert _service("/rival2/BallHandle", BallHandle)(1).BallIsHolding == 1
    with watch.lock:
        kicked_at = watch.ball[-1][0]
    # the lob unscattered: 5 % off its speed, one from 6.5 m can hit the bar or the goalie and never cross the line
    client = dynamic_reconfigure.client.Client("/sim_visual", timeout=10)
    try:
        client.update_configuration({"kick_speed_std": 0.0, "kick_direction_std_deg": 0.0})
        assert _service("/rival2/Shoot", Shoot)(0, 1).ShootIsDone == 1
    finally:
        client.update_configuration({"kick_speed_std": 0.05, "kick_direction_std_deg": 1.5})
        client.close()

    def over_the_line():
        with watch.lock:
            track = [b for b in watch.ball if b[0] > kicked_at + 0.1]
        return track if track and track[-1][1] < -9.0 else None

    try:
        track = wait_until(over_the_line, 10, "the lob crossing the goal line")
    except AssertionError:
        raise AssertionError(node.log_text()[-3000:]) from None
    # The lob comes down behind the goal line, where the net stops it: the truth is its free flight (the last
    # true state in front of the line) continued down to the ground.
    t, x, y, z, vx, vy, vz = [b for b in track if b[1] > -8.95][-1]
    free = landing(x, y, z, vx, vy, vz, RADIUS)
    truth = (t + free.t, free.x, free.y)
    with watch.lock:
        made = [m for m in watch.infos if m.velocity_known and m.header.stamp.to_sec() <= truth[0] - 0.3
                and m.header.stamp.to_sec() > kicked_at]
    assert made, f"no BallInfo3d with a velocity by 0.3 s before the landing at {truth[0]:.2f} s"
    m = made[-1]
    assert m.pos_known_3d and m.pos_known_2d
    down = landing(m.pos.x, m.pos.y, m.pos.z, m.velocity.x, m.velocity.y, m.velocity.z, RADIUS)
    error = math.hypot(down.x - truth[1], down.y - truth[2])
    assert error < 0.15, f"predicted ({down.x:.2f}, {down.y:.2f}), landed ({truth[1]:.2f}, {truth[2]:.2f})"
    assert abs(m.header.stamp.to_sec() + down.t - truth[0]) < 0.05, "and when"


def test_the_graph_matches_the_topic_table(goalie_world, ros_master):
    """Each row of docs/topics.md's goalie table has its one producer in the running graph."""
    import re
    from pathlib import Path

    table = (Path(__file__).resolve().parents[4] / "docs" / "topics.md").read_text()
    section = table.split("## Topics of the goalie seeing through its cameras")[1].split("\n## ")[0]
    rows = [[c.strip().strip("`") for c in line.strip("|").split("|")] for line in section.splitlines()
            if line.startswith("| `")]
    assert len(rows) == 3
    published = ros_master.graph().publishers
    for topic, _type, producer, *_ in rows:
        topic = topic.replace("<r>", "nubot1")
        nodes = {n.replace("<r>", "nubot1") for n in re.findall(r"/[<>a-z_0-9]+(?:/[a-z_]+)?", producer)}
        assert len(published.get(topic, ())) == 1 and published[topic] <= nodes, \
            f"{topic}: produced by {published.get(topic)}, the table says {producer}"
