"""The world_model node over real ROS: the single-robot world (nubot1 at (-2, 0), ball at (1, 2)) and its model."""

from __future__ import annotations

import threading
import time

import pytest

from nubot_tools.processes import wait_until

pytestmark = pytest.mark.integration

ROBOT, TEAM = "nubot1", "nubot"
CHAPTER_COMMAND = "\nMatchMode: 10\nMatchType: 0 "  # the chapter's rostopic pub argument, as printed


class WorldModelWatcher:
    """Records the world model's outputs with the sim time they arrived at."""

    def __init__(self) -> None:
        import rospy
        from rosgraph_msgs.msg import Clock

        from nubot_common.msg import TeamMessage, TeamMessages, WorldModelInfo

        self.lock = threading.Lock()
        self.clock = 0.0
        self.infos: list = []
        self.team: list = []
        self.subs = [
            rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10),
            rospy.Subscriber(f"/{ROBOT}/worldmodel/worldmodelinfo", WorldModelInfo, self._on_info, queue_size=200),
            rospy.Subscriber(f"/{ROBOT}/worldmodel/teammessage", TeamMessage, self._on_team, queue_size=200),
        ]
        self.mates_pub = rospy.Publisher(f"/{TEAM}/simulation_interface/teammates", TeamMessages, queue_size=10)

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()
        self.mates_pub.unregister()

    def _on_clock(self, msg) -> None:
        self.clock = msg.clock.to_sec()

    def _on_info(self, msg) -> None:
        with self.lock:
            self.infos.append((self.clock, msg))

    def _on_team(self, msg) -> None:
        with self.lock:
            self.team.append(msg)

    @property
    def latest(self):
        with self.lock:
            return self.infos[-1][1] if self.infos else None

    def wait_for(self, predicate, timeout: float = 20.0, what: str = "condition"):
        return wait_until(predicate, timeout, what, 0.01)

    def wait_sim(self, seconds: float, every_frame=None, rate: float = 30.0) -> None:
        """Let ``seconds`` of sim time pass, calling ``every_frame(sim_time)`` at ``rate`` Hz."""
        end = self.clock + seconds
        next_call = self.clock
        while self.clock < end:
            if every_frame is not None and self.clock >= next_call:
                every_frame(self.clock)
                next_call += 1.0 / rate
            time.sleep(0.002)


@pytest.fixture(scope="module")
def world(ros_master):
    """The single-robot world without the demo, and nubot1's world model; yields (world_model process, watcher)."""
    sim = ros_master.launch("wm_single_robot", ["roslaunch", "sim_visual", "single_robot.launch", "demo:=false"])
    watcher = WorldModelWatcher()
    processes = [sim]
    try:
        watcher.wait_for(lambda: watcher.clock > 0.1, timeout=60, what="the simulator's clock")
        node = ros_master.launch("world_model_nubot1", ["roslaunch", "world_model", "world_model.launch",
                                                        f"robot:={ROBOT}", f"team:={TEAM}"])
        processes.append(node)
        watcher.wait_for(lambda: not node.alive() or (watcher.latest is not None
                                                       and watcher.latest.robotinfo[0].isvalid),
                         timeout=60, what="the first valid WorldModelInfo")
        assert node.alive(), "world_model exited"
    except AssertionError:
        logs = "\n".join(p.log_text()[-3000:] for p in processes)
        watcher.close()
        for p in reversed(processes):
            p.stop()
        raise AssertionError(f"the world did not start:\n{logs}") from None
    yield node, watcher
    watcher.close()
    for p in reversed(processes):
        p.stop()
    time.sleep(0.5)  # let the master forget the stopped nodes before the next module launches its own


def test_world_model_info_at_30_hz_with_own_pose_and_fused_ball(world):
    node, watcher = world
    start = watcher.clock
    watcher.wait_sim(2.0)
    with watcher.lock:
        frames = [m for c, m in watcher.infos if c > start + 0.05]
        shared = list(watcher.team[-10:])
    stamps = [m.header.stamp.to_sec() for m in frames]
    assert (len(stamps) - 1) / (stamps[-1] - stamps[0]) == pytest.approx(30.0, rel=0.05)
    last = frames[-1]
    assert [r.AgentID for r in last.robotinfo] == [1, 2, 3, 4, 5]
    assert [r.isvalid for r in last.robotinfo] == [True, False, False, False, False], "no teammates here"
    me = last.robotinfo[0]
    assert (me.pos.x, me.pos.y) == pytest.approx((-2.0, 0.0), abs=0.15)
    ball = last.ballinfo[0]
    assert (ball.ballinfostate, ball.pos_known) == (1, True)
    assert (ball.pos.x, ball.pos.y) == pytest.approx((1.0, 2.0), abs=0.3)
    mean_v = [sum(getattr(m.ballinfo[0].velocity, a) for m in frames) / len(frames) for a in "xy"]
    assert mean_v == pytest.approx([0.0, 0.0], abs=0.15), "the ball lies still: the fitted velocity says so"
    assert (last.coachinfo.MatchMode, last.pass_cmd.is_valid) == (0, False), "STOPROBOT until the coach speaks"
    assert len(last.obstacleinfo.pos) == 0 and len(last.oppinfo.pos) == 0
    assert shared and all(m.robot.AgentID == 1 and m.robot.isvalid and m.ball.pos_known for m in shared)
    assert node.alive() and "Traceback" not in node.log_text()


def test_chapter_coach_command_sets_the_game_and_an_unknown_mode_is_refused(world, ros_master):
    node, watcher = world
    publisher = ros_master.launch("coach_pub_10", ["rostopic", "pub", "-r", "1", f"/{TEAM}/receive_from_coach",
                                                   "nubot_common/CoachInfo", CHAPTER_COMMAND])
    try:
        watcher.wait_for(lambda: watcher.latest.coachinfo.MatchMode == 10, timeout=20, what="MatchMode 10")
    finally:
        publisher.stop()
    assert watcher.latest.coachinfo.MatchType == 0
    bad = ros_master.launch("coach_pub_14", ["rostopic", "pub", "-r", "1", f"/{TEAM}/receive_from_coach",
                                             "nubot_common/CoachInfo", "{MatchMode: 14, MatchType: 10}"])
    try:
        watcher.wait_for(lambda: "MatchMode 14 is not a game command" in node.log_text(), timeout=20,
                         what="the refusal in the node's log")
    finally:
        bad.stop()
    watcher.wait_sim(0.2)
    coach = watcher.latest.coachinfo
    assert (coach.MatchMode, coach.MatchType) == (10, 0), "the previous game state is kept"
    assert "keeping OPP_CORNERKICK" in node.log_text()
    assert node.alive()


def _teammate_messages(sim_time: float):
    """Teammate 2 at (0.5, 2) seeing the ball at (1, 2), and this robot's own message relayed back (to ignore)."""
    import genpy

    from nubot_common.msg import Point2d, TeamMessage, TeamMessages

    messages = []
    for agent_id, pos, ball in ((2, (0.5, 2.0), (1.0, 2.0)), (1, (8.0, 5.0), (-7.0, -5.0))):
        m = TeamMessage()
        m.header.stamp = m.robot.header.stamp = m.ball.header.stamp = genpy.Time.from_sec(sim_time)
        m.robot.AgentID, m.robot.isvalid, m.robot.pos = agent_id, True, Point2d(*pos)
        m.ball.ballinfostate, m.ball.pos_known, m.ball.pos = 1, True, Point2d(*ball)
        messages.append(m)
    return TeamMessages(messages=messages)


def test_teammate_ball_is_used_when_the_robot_cannot_see_it_until_the_teammate_falls_silent(world):
    from dynamic_reconfigure.client import Client

    node, watcher = world
    reconfigure = Client("/sim_visual", timeout=20)
    reconfigure.update_configuration({"vision_range": 1.0})  # the ball is 3.6 m away
    try:
        watcher.wait_for(lambda: watcher.latest.ballinfo[0].ballinfostate == 0, timeout=10,
                         what="the own ball to go stale")
        watcher.wait_sim(1.0, every_frame=lambda t: watcher.mates_pub.publish(_teammate_messages(t)))
        last = watcher.latest
        ball = last.ballinfo[0]
        assert (ball.ballinfostate, ball.pos_known) == (2, True), "from a teammate"
        assert (ball.pos.x, ball.pos.y) == pytest.approx((1.0, 2.0), abs=1e-3)
        assert [r.isvalid for r in last.robotinfo] == [True, True, False, False, False]
        assert (last.robotinfo[0].pos.x, last.robotinfo[0].pos.y) == pytest.approx((-2.0, 0.0), abs=0.15), \
            "its own message, relayed back, is ignored"
        watcher.wait_sim(0.5)  # teammate 2 falls silent: after 0.3 s it is invalid, and so is its ball
        last = watcher.latest
        assert [r.isvalid for r in last.robotinfo] == [True, False, False, False, False]
        assert (last.ballinfo[0].ballinfostate, last.ballinfo[0].pos_known) == (0, False)
    finally:
        reconfigure.update_configuration({"vision_range": 0.0})
        reconfigure.close()
    watcher.wait_for(lambda: watcher.latest.ballinfo[0].ballinfostate == 1, timeout=10, what="the ball seen again")
    assert "Traceback" not in node.log_text()
