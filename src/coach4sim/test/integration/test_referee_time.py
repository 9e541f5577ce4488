"""The automatic referee judges the simulator's model states at their own sim time (their stamp)."""

import time
from pathlib import Path

import pytest

from nubot_common.processes import ros_graph

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"


def subscribers(master_uri: str, topic: str) -> list[str]:
    return sorted(ros_graph(master_uri).subscribers.get(topic, ()))


def test_a_kickoff_set_up_before_the_referee_s_first_clock_tick_lasts_its_setup_time(ros_master, make_watcher):
    # Nobody publishes /clock here: the referee's own clock stays at 0 s, as it is when the simulator's first model
    # states reach it before its first /clock message (a race CI once lost: the kickoff's setup, begun "at 0 s",
    # ended at the next states, and the robots never took their kickoff places).
    import rospy
    from geometry_msgs.msg import Pose

    from nubot_common.match_mode import MatchMode
    from nubot_common.msg import ModelStates
    from nubot_common.node_io import publisher

    def states(t: float) -> ModelStates:
        msg = ModelStates(name=["football", "nubot1", "rival1"], pose=[Pose(), Pose(), Pose()])
        msg.header.stamp = rospy.Time.from_sec(t)
        msg.pose[0].position.z = 0.11
        msg.pose[1].position.x, msg.pose[2].position.x = -2.0, 2.0
        return msg

    watcher = make_watcher()
    pub = publisher("/sim_visual/model_states", ModelStates)
    referee = ros_master.launch("coach4sim_referee_time", ["roslaunch", "coach4sim", "referee.launch",
                                                           f"world:={WORLD}"])
    try:
        watcher.wait_for(lambda: watcher.mode("nubot") == MatchMode.STOPROBOT, timeout=30, what="the referee")
        watcher.wait_for(lambda: "/referee" in subscribers(ros_master.uri, "/sim_visual/model_states"), timeout=10,
                         what="the referee's subscription")
        watcher.wait_for(lambda: pub.publish(states(10.0)) or watcher.mode("nubot") == MatchMode.OUR_KICKOFF,
                         timeout=20, what="the first kickoff")
        for k in range(39):  # 3.9 s of sim time: the robots are still taking their places
            pub.publish(states(10.0 + 0.1 * k))
            time.sleep(0.02)
        time.sleep(0.3)
        assert (watcher.mode("nubot"), watcher.mode("rival")) == (MatchMode.OUR_KICKOFF, MatchMode.OPP_KICKOFF)
        watcher.wait_for(lambda: pub.publish(states(14.1)) or watcher.mode("nubot") == MatchMode.STARTROBOT,
                         timeout=10, what="STARTROBOT once the states are 4 s past the kickoff")
    except AssertionError as exc:
        raise AssertionError(f"{exc}\n{referee.log_text()[-3000:]}") from None
    finally:
        watcher.close()
        pub.unregister()
        referee.stop()
        time.sleep(0.5)
