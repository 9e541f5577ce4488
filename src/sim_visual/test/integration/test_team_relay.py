"""The team relay (sim_interface) over real ROS: every member's latest TeamMessage and StrategyInfo reach the team's
two topics exactly as the members sent them, in member order; a member silent for max_age drops out; a publisher
of another type on a member's topic is refused."""

from __future__ import annotations

import subprocess
import threading
import time

import pytest

from nubot_common.processes import Launched, wait_until

pytestmark = pytest.mark.integration

TEAM, MAX_AGE = "relay", 0.6


def _team_message(agent: int, obstacles: int):
    from nubot_common.msg import Point2d, PPoint, TeamMessage

    msg = TeamMessage()
    msg.header.stamp.secs = 7
    msg.robot.AgentID, msg.robot.pos, msg.robot.current_role = agent, Point2d(agent + 0.25, -1.5), agent
    msg.ball.pos, msg.ball.pos_known = Point2d(3.0, agent * 0.5), True
    msg.obstacles.pos = [Point2d(k * 0.5, agent) for k in range(obstacles)]
    msg.obstacles.polar_pos = [PPoint(k * 0.25, 2.0) for k in range(obstacles)]
    return msg


def _strategy(agent: int):
    from nubot_common.msg import StrategyInfo

    msg = StrategyInfo(AgentID=agent, role=agent + 1, action=40 + agent, is_dribble=agent == 3)
    msg.pass_cmd.pass_id, msg.pass_cmd.catch_id, msg.pass_cmd.is_valid = agent, 2, True
    return msg


def _unsequenced(messages) -> list:
    """The messages but their header's seq, which a publisher sets anew on every publish."""
    for m in messages:
        m.header.seq = 0
    return list(messages)


@pytest.fixture
def relay(ros_master, tmp_path):
    import rospy
    from rosgraph_msgs.msg import Clock

    stop = threading.Event()
    clock = None
    if rospy.get_param("/use_sim_time", False):  # left on by an earlier test's simulator: the relay needs a clock
        clock = rospy.Publisher("/clock", Clock, queue_size=1)

        def tick() -> None:
            t = time.time()
            while not stop.is_set():
                clock.publish(Clock(rospy.Time.from_sec(time.time() - t + 1.0)))
                time.sleep(0.01)

        threading.Thread(target=tick, daemon=True).start()
    node = Launched(["rosrun", "sim_visual", "sim_interface", "__name:=relay_under_test", f"_team:={TEAM}",
                     "_team_size:=3", f"_max_age:={MAX_AGE}"], ros_master.env, tmp_path / "relay.log")
    try:
        yield node
    finally:
        stop.set()
        node.stop()
        if clock is not None:
            clock.unregister()


def test_the_relay_passes_every_members_latest_messages_on_unchanged(relay, ros_master):
    import rospy
    from std_msgs.msg import String

    from nubot_common.msg import StrategyInfo, TeamMessage, TeamMessages, simulation_strategy

    heard: dict[str, list] = {"team": [], "strategy": []}
    subs = [rospy.Subscriber(f"/{TEAM}/simulation_interface/teammates", TeamMessages, heard["team"].append),
            rospy.Subscriber(f"/{TEAM}/simulation_interface/strategy", simulation_strategy,
                             heard["strategy"].append)]
    pubs = {k: rospy.Publisher(f"/{TEAM}{k}/worldmodel/teammessage", TeamMessage, queue_size=1) for k in (1, 3)}
    strategy_pub = rospy.Publisher(f"/{TEAM}3/nubotcontrol/strategy", StrategyInfo, queue_size=1)
    wrong = rospy.Publisher(f"/{TEAM}2/worldmodel/teammessage", String, queue_size=1)  # not a TeamMessage
    relay_env = ros_master.env
    sent = {1: _team_message(1, 0), 3: _team_message(3, 4)}
    try:
        wait_until(lambda: all(p.get_num_connections() for p in (*pubs.values(), strategy_pub)), 30.0,
                   "the relay subscribing")
        wait_until(lambda: heard["team"], 30.0, "the relay publishing")
        # what the relay's subscriptions tell the master (rostopic, rqt_graph): the members' types, not "*"
        listed = subprocess.run(["rostopic", "type", f"/{TEAM}2/nubotcontrol/strategy"], env=relay_env,
                                capture_output=True, text=True, timeout=30)
        assert listed.stdout.strip() == "nubot_common/StrategyInfo", listed.stdout + listed.stderr

        def latest_with(count: int):
            for k, pub in pubs.items():
                pub.publish(sent[k])
            strategy_pub.publish(_strategy(3))
            wrong.publish(String("not a team message"))
            return heard["team"] and len(heard["team"][-1].messages) == count and heard["strategy"][-1].strategy_msgs

        wait_until(lambda: latest_with(2), 10.0, "both members' messages relayed", poll=0.05)
        out = heard["team"][-1]
        assert _unsequenced(out.messages) == _unsequenced([sent[1], sent[3]]), \
            "the members' messages, unchanged and in member order"
        assert out.header.stamp.to_sec() > 0.0 and heard["team"][-1].header.seq > heard["team"][0].header.seq
        assert _unsequenced(heard["strategy"][-1].strategy_msgs) == [_strategy(3)]
        assert wrong.get_num_connections() == 0, "the relay connected to a publisher of another type"

        pubs.pop(1).unregister()  # relay1 falls silent: after max_age only relay3 is relayed
        silent = time.monotonic()
        wait_until(lambda: latest_with(1), 10.0, "the silent member dropped", poll=0.05)
        assert time.monotonic() - silent >= MAX_AGE * 0.5
        assert _unsequenced(heard["team"][-1].messages) == _unsequenced([sent[3]])
    finally:
        for s in subs:
            s.unregister()
        for p in (*pubs.values(), strategy_pub, wrong):
            p.unregister()
    assert relay.alive(), relay.log_text()[-3000:]
    assert "Traceback" not in relay.log_text()
