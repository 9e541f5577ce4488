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


def test_missed_cycles_count_each_robot_s_shortfall_and_a_robot_ahead_makes_up_for_nobody(tmp_path):
    """10 s of sim time at 33 Hz: 330 cycles expected of each robot. nubot1 made 331 (one just inside the window's
    edge), rival3 made 297: 33 missed, 5 % of the two robots' 660, not the 32 of the sum."""
    from nubot_common.msg import StrategyInfo
    from nubot_tools.ros.match_runner import PerfMonitor

    path = tmp_path / "match.bag"
    with rosbag.Bag(str(path), "w") as bag:
        for robot, cycles in (("nubot1", 331), ("rival3", 297)):
            for k in range(cycles):
                t = rospy.Time.from_sec(20.0 + k * 10.0 / cycles)
                bag.write(f"/{robot}/nubotcontrol/strategy", StrategyInfo(), t)
    monitor = PerfMonitor(["nubot1", "rival3"], launched=[], rate=33.0)
    monitor.start, monitor.end = (0.0, 20.0), (10.0, 30.0)
    monitor.samples = [{"robot_node": 0.5, "rss_mib": 100.0}, {"robot_node": 0.7, "rss_mib": 120.0}]

    figures = monitor.result(path)

    assert figures["missed_cycles"] == {"nubot1": 0, "rival3": 33}
    assert figures["missed_cycle_share"] == pytest.approx(33 / 660, abs=1e-4)
    assert figures["control_rate_min_hz"] == pytest.approx(29.7)
    assert (figures["cpu_cores_total"], figures["rss_mib_total"]) == (0.7, 120.0)  # the first look gives no CPU
