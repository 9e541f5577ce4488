"""front_vision over real ROS: the simulator's front camera of a regular robot, the ball 1 m ahead of it, the
node's FrontBallInfo within 3 cm of the truth; the camera's CameraInfo; bad images answered, never a crash."""

from __future__ import annotations

import math
import threading
import time
from pathlib import Path

import numpy as np
import pytest

from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

LAUNCH = Path(__file__).with_name("front_ball.launch")
BALL_AHEAD = 1.0  # [m] the ball's distance straight ahead of nubot2 (front_ball.launch)


class Watch:
    def __init__(self) -> None:
        import rospy
        from sensor_msgs.msg import CameraInfo

        from nubot_common.msg import FrontBallInfo

        self.lock = threading.Lock()
        self.balls: list = []
        self.infos: list = []
        self.subs = [rospy.Subscriber("/nubot2/front_vision/FrontBallInfo", FrontBallInfo, self._on_ball,
                                      queue_size=100),
                     rospy.Subscriber("/nubot2/front_camera/camera_info", CameraInfo, self.infos.append,
                                      queue_size=10)]

    def _on_ball(self, msg) -> None:
        with self.lock:
            self.balls.append(msg)

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


@pytest.fixture(scope="module")
def front(ros_master):
    watch = Watch()
    process = ros_master.launch("front_ball", ["roslaunch", "--skip-log-check", str(LAUNCH)])
    try:
        wait_until(lambda: sum(m.pos_known for m in watch.balls) >= 15, 40, "15 FrontBallInfo with the ball")
    except AssertionError:
        process.stop()
        watch.close()
        raise AssertionError(process.log_text()[-4000:]) from None
    yield process, watch
    watch.close()
    process.stop()
    time.sleep(0.5)


def test_the_ball_ahead_is_seen_within_3_cm(front) -> None:
    _, watch = front
    with watch.lock:
        known = [m for m in watch.balls if m.pos_known]
    errors = [math.hypot(m.real_pos.radius * math.cos(m.real_pos.angle) - BALL_AHEAD,
                         m.real_pos.radius * math.sin(m.real_pos.angle)) for m in known]
    assert max(errors) < 0.03, f"errors [m]: {errors}"
    assert all(m.header.frame_id == "nubot2/base_link" and m.header.stamp.to_sec() > 0.0 for m in known)


def test_the_camera_info_carries_the_simulated_cameras_intrinsics(front) -> None:
    from nubot_common.camera_info import camera_intrinsics
    from nubot_common.camera_model import PinholeCamera

    _, watch = front
    wait_until(lambda: watch.infos, 10, "a CameraInfo")
    intrinsics = camera_intrinsics(watch.infos[-1])
    assert PinholeCamera(**intrinsics) == PinholeCamera(**PinholeCamera().intrinsics())
    assert watch.infos[-1].header.frame_id == "nubot2/front_camera"


@pytest.mark.parametrize("kind", ["wrong encoding", "NaN floats", "empty", "wrong size"])
def test_a_bad_image_is_answered_with_pos_known_false_and_the_node_lives_on(front, kind: str) -> None:
    import rospy
    from sensor_msgs.msg import Image

    process, watch = front
    pub = rospy.Publisher("/nubot2/front_camera/image_raw", Image, queue_size=1)
    time.sleep(0.5)  # let the node connect
    msg = Image(encoding="rgb8", height=240, width=320, step=960)
    msg.header.stamp = rospy.Time(5000 + len(kind))
    if kind == "wrong encoding":
        msg.encoding, msg.step, msg.data = "mono16", 640, bytes(240 * 640)
    elif kind == "NaN floats":
        msg.encoding, msg.step = "32FC3", 320 * 12
        msg.data = np.full((240, 320, 3), np.nan, np.float32).tobytes()
    elif kind == "empty":
        msg.height = msg.width = msg.step = 0
    else:
        msg.height, msg.width, msg.step, msg.data = 100, 100, 300, bytes(100 * 300)
    stamp = msg.header.stamp.to_sec()

    def answered() -> bool:
        with watch.lock:
            return any(m.header.stamp.to_sec() == stamp for m in watch.balls)

    wait_until(lambda: pub.publish(msg) or answered(), 10, f"an answer to the {kind} image", 0.2)
    pub.unregister()
    with watch.lock:
        answer = next(m for m in watch.balls if m.header.stamp.to_sec() == stamp)
    assert not answer.pos_known
    assert process.alive(), process.log_text()[-3000:]
    count = len(watch.balls)
    wait_until(lambda: len(watch.balls) > count + 3, 10, "FrontBallInfo again from the simulator's images")
    assert "image refused" in process.log_text()


def test_the_graph_matches_the_topic_table(front, ros_master) -> None:
    import re

    table = Path(__file__).resolve().parents[4] / "docs" / "topics.md"
    text = table.read_text().split("## Topics of a regular robot seeing through its cameras")[1].split("## ")[0]
    rows = [[c.strip().strip("`").replace("<r>", "nubot2") for c in line.strip("|").split("|")]
            for line in text.splitlines() if line.startswith("| `")]
    assert len(rows) == 3
    published = ros_master.graph().publishers
    for topic, _type, producer, *_ in rows:
        nodes = set(re.findall(r"/[a-z_0-9]+(?:/[a-z_]+)?", producer))
        assert published.get(topic) and published[topic] <= nodes and len(published[topic]) == 1, \
            f"{topic}: produced by {published.get(topic)}, the table says {producer}"
