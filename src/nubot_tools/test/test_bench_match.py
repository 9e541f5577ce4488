"""The match benchmark's message traffic: what each message costs is paid once per subscribing node."""

import pytest
import rosbag
import rospy
from rosgraph_msgs.msg import Clock

from nubot_common.msg import VelCmd
from nubot_tools.ros.bench_match import message_traffic


def test_traffic_counts_each_message_once_per_subscriber_and_folds_robot_and_team_names(tmp_path):
    path = tmp_path / "match.bag"
    with rosbag.Bag(str(path), "w") as bag:
        for k in range(101):  # 10 s: /clock at 10 Hz, two robots' velcmd at 5 Hz
            t = rospy.Time.from_sec(100.0 + 0.1 * k)
            bag.write("/clock", Clock(clock=t), t)
            if k % 2 == 0:
                bag.write("/nubot1/nubotcontrol/velcmd", VelCmd(), t)
                bag.write("/rival3/nubotcontrol/velcmd", VelCmd(), t)
    subscribers = {"/clock": 20, "/nubot1/nubotcontrol/velcmd": 2, "/rival3/nubotcontrol/velcmd": 1}

    traffic = message_traffic(path, subscribers)

    assert traffic["seconds"] == pytest.approx(10.0)
    assert traffic["messages_per_second"] == pytest.approx(10.1 + 2 * 5.1, abs=0.05)
    assert traffic["deliveries_per_second"] == pytest.approx(10.1 * 20 + 5.1 * 2 + 5.1 * 1, abs=0.1)
    assert list(traffic["largest"]) == ["/clock", "/<robot>/nubotcontrol/velcmd"]  # the largest stream first
    assert traffic["largest"]["/<robot>/nubotcontrol/velcmd"]["messages_per_second"] == pytest.approx(10.2, abs=0.05)


def test_a_topic_nobody_subscribes_to_costs_no_delivery(tmp_path):
    path = tmp_path / "match.bag"
    with rosbag.Bag(str(path), "w") as bag:
        for k in range(11):
            t = rospy.Time.from_sec(1.0 + 0.1 * k)
            bag.write("/nubot/receive_from_coach", Clock(clock=t), t)
    traffic = message_traffic(path, {})
    assert traffic["messages_per_second"] == pytest.approx(11.0, abs=0.05)
    assert traffic["deliveries_per_second"] == 0.0
    assert list(traffic["largest"]) == ["/<team>/receive_from_coach"]
