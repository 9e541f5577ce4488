"""omni_vision over real ROS: the single-robot demo plays on camera images alone, a recorded bag replays to the
same localization, and bad input is refused without a crash."""

from __future__ import annotations

import math
import re
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[4]
TABLE = ROOT / "docs" / "topics.md"
RECORDED = ["/nubot1/camera/image_raw", "/nubot1/nubotdriver/odoinfo", "/nubot1/imu/data",
            "/nubot1/omnivision/OmniVisionInfo"]


class VisionWatch:
    """Collects what the vision publishes: its frames (stamp -> pose) and the localization errors."""

    def __init__(self) -> None:
        import rospy
        from std_msgs.msg import String

        from nubot_common.msg import GoalEvent, LocalizationError, OmniVisionInfo

        self.lock = threading.Lock()
        self.poses: dict[float, tuple[float, float, float]] = {}
        self.errors: list = []
        self.goals: list = []
        self.states: list[str] = []
        self.subs = [
            rospy.Subscriber("/nubot1/omnivision/OmniVisionInfo", OmniVisionInfo, self._on_vision, queue_size=100),
            rospy.Subscriber("/nubot1/omnivision/localization_error", LocalizationError, self.errors.append,
                             queue_size=100),
            rospy.Subscriber("/sim_visual/goal", GoalEvent, self.goals.append, queue_size=10),
            rospy.Subscriber("/nubot1/demo/state", String, lambda m: self.states.append(m.data), queue_size=50),
        ]

    def _on_vision(self, msg) -> None:
        me = msg.robotinfo[0]
        with self.lock:
            self.poses[round(msg.header.stamp.to_sec(), 3)] = (me.pos.x, me.pos.y, me.heading.theta)

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


def _table_rows(section: str) -> list[list[str]]:
    text = TABLE.read_text().split(f"## {section}")[1].split("## ")[0]
    rows = [[c.strip().strip("`") for c in line.strip("|").split("|")] for line in text.splitlines()
            if line.startswith("| `")]
    return [[c.replace("<r>", "nubot1") for c in row] for row in rows]


@pytest.fixture(scope="module")
def vision_demo(ros_master, tmp_path_factory):
    """single_robot.launch perception:=vision with the demo, its vision inputs and outputs recorded."""
    watch = VisionWatch()
    bag = tmp_path_factory.mktemp("vision") / "camera.bag"
    recorder = ros_master.launch("vision_recorder", ["rosbag", "record", "-O", str(bag), *RECORDED,
                                                     "__name:=vision_recorder"])
    time.sleep(1.0)
    process = ros_master.launch("vision_demo", ["roslaunch", "sim_visual", "single_robot.launch",
                                                "perception:=vision", "demo:=true"])
    yield process, watch, recorder, bag
    watch.close()
    recorder.stop()
    process.stop()
    time.sleep(0.5)


def test_the_demo_scores_on_camera_images_alone_and_the_graph_matches_the_table(vision_demo, ros_master):
    process, watch, _, _ = vision_demo
    try:
        goal = wait_until(lambda: watch.goals and watch.goals[0], 90, "the demo's goal, seen through the camera")
    except AssertionError:
        raise AssertionError(f"states {watch.states}\n{process.log_text()[-4000:]}") from None
    assert goal.side == 1 and goal.last_touch == "nubot1"
    assert goal.header.stamp.to_sec() < 40.0, "scores within 40 s of sim time, as in truth mode (30 s) plus a margin"
    wait_until(lambda: len(watch.errors) >= 150, 30, "150 vision frames (5 s)")
    tracked = [e for e in watch.errors if e.localized]
    assert len(tracked) > 140, f"the vision localized {len(tracked)} of {len(watch.errors)} frames"
    assert np.mean([e.position_error for e in tracked]) < 0.06, "mean error under 6 cm (the chapter's figure)"
    assert np.mean([e.heading_error for e in tracked]) < math.radians(2.0)
    # The graph of a robot seeing through its camera: each topic of the table has its one producer.
    published = ros_master.graph().publishers
    for topic, _type, producer, *_ in _table_rows("Topics of a robot seeing through its camera"):
        if topic == "/nubot1/omnivision/debug_image":
            assert topic in published  # advertised; drawn only while someone subscribes
        nodes = set(re.findall(r"/[a-z_0-9]+(?:/[a-z_]+)?", producer))
        if topic == "/nubot1/camera/labels":
            assert topic not in published, "labels only with ~camera_labels"
            continue
        assert published.get(topic, set()) <= nodes and len(published.get(topic, ())) == 1, \
            f"{topic}: produced by {published.get(topic)}, the table says {producer}"


def test_a_recorded_bag_replays_to_the_same_localization(vision_demo, ros_master, tmp_path):
    """rosbag play of the camera, odometry and inertial topics into a fresh omni_vision gives the poses the live
    node gave (the same frames, the same order of inputs)."""
    process, watch, recorder, bag = vision_demo
    wait_until(lambda: len(watch.errors) > 200, 60, "200 vision frames recorded")
    recorder.stop()
    process.stop()
    time.sleep(1.0)
    live = dict(watch.poses)
    assert bag.exists() and bag.stat().st_size > 10_000_000, "the camera's images are in the bag"
    with watch.lock:
        watch.poses.clear()
    replay_vision = ros_master.launch("replay_vision", [
        "roslaunch", "omni_vision", "omni_vision.launch", "robot:=nubot1",
        f"world:={ROOT / 'src' / 'nubot_common' / 'config' / 'world_18x12.yaml'}"])
    try:
        wait_until(lambda: "omni_vision: nubot1" in replay_vision.log_text() or _node_up("/nubot1/omni_vision"),
                   30, "the replaying omni_vision node")
        # the first 8 s: global localization, the chase and the goal
        player = ros_master.launch("player", ["rosbag", "play", "--clock", "-u", "8", str(bag),
                                              "/nubot1/omnivision/OmniVisionInfo:=/recorded/OmniVisionInfo"])
        wait_until(lambda: not player.alive(), 120, "rosbag play to finish")
        time.sleep(0.5)
        replayed = dict(watch.poses)
    finally:
        replay_vision.stop()
    common = sorted(set(live) & set(replayed))
    assert len(common) > 100, f"{len(common)} frames in common of {len(live)} live, {len(replayed)} replayed"
    later = common[len(common) // 4:]  # once both have localized
    gaps = [math.hypot(live[t][0] - replayed[t][0], live[t][1] - replayed[t][1]) for t in later]
    # Camera, odometry and inertial messages come on three topics, each in its own thread, live and replayed: an
    # odometry message handled just after an image instead of just before it moves that frame's prediction, and its
    # pose differs by a few centimetres (measured: all 168 frames compared followed the same frame in both runs,
    # median 0.8 mm, p95 2.0 cm, max 3.9 cm; CI saw a p95 of 3.1 cm).
    p95 = float(np.percentile(gaps, 95))
    assert np.median(gaps) < 0.01 and p95 < 0.05 and max(gaps) < 0.15, \
        f"median {np.median(gaps):.3f} m, p95 {p95:.3f} m, max {max(gaps):.3f} m"


def _node_up(name: str) -> bool:
    import rosnode

    return name in rosnode.get_node_names()


def test_bad_images_are_logged_and_skipped_and_a_bad_table_file_is_fatal(ros_master, tmp_path):
    import rospy
    from sensor_msgs.msg import Image

    world = ROOT / "src" / "nubot_common" / "config" / "world_18x12.yaml"
    empty = tmp_path / "empty.npz"
    empty.write_bytes(b"")
    bad = ros_master.launch("bad_table", ["roslaunch", "omni_vision", "omni_vision.launch", "robot:=nubot3",
                                          f"color_table:={empty}", f"world:={world}", "output:=screen"])
    wait_until(lambda: not bad.alive(), 30, "the node with an empty table file to exit")
    assert f"colour table {empty}: the file is empty" in bad.log_text()

    node = ros_master.launch("vision_bad_input", ["roslaunch", "omni_vision", "omni_vision.launch", "robot:=nubot2",
                                                   f"world:={world}", "output:=screen"])
    try:
        wait_until(lambda: _node_up("/nubot2/omni_vision"), 30, "omni_vision for nubot2")
        pub = rospy.Publisher("/nubot2/camera/image_raw", Image, queue_size=10)
        wait_until(lambda: pub.get_num_connections() > 0, 10, "omni_vision to subscribe")
        for width, height, encoding in ((640, 480, "rgb8"), (480, 480, "mono8")):
            msg = Image(width=width, height=height, encoding=encoding, step=width * (3 if encoding == "rgb8" else 1))
            msg.data = bytes(msg.step * height)
            pub.publish(msg)
        wait_until(lambda: "image refused" in node.log_text(), 10, "the refusal in the log")
        assert node.alive()
        # the first refusal is logged (the others within a few seconds are not): it names what is wrong
        assert "640" in node.log_text() or "'mono8' unsupported" in node.log_text()
        pub.unregister()
    finally:
        node.stop()
