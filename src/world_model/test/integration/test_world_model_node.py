"""The world_model node over real ROS: the single-robot world (nubot1 at (-2, 0), ball at (1, 2)) and its model."""

from __future__ import annotations

import threading
import time

import pytest

from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

ROBOT, TEAM = "nubot1", "nubot"
CHAPTER_COMMAND = "\nMatchMode: 10\nMatchType: 0 "  # the chapter's rostopic pub argument, as printed


class WorldModelWatcher:
    """Records the world model's outputs with the sim time they arrived at."""

    def __init__(self) -> None:
        import rospy
        from rosgraph_msgs.msg import Clock

        from nubot_common.msg import BallFlightInfo, TeamMessage, TeamMessages, WorldModelInfo

        self.lock = threading.Lock()
        self.clock = 0.0
        self.infos: list = []
        self.team: list = []
        self.flights: list = []
        self.subs = [
            rospy.Subscriber("/clock", Clock, self._on_clock, queue_size=10),
            rospy.Subscriber(f"/{ROBOT}/worldmodel/worldmodelinfo", WorldModelInfo, self._on_info, queue_size=200),
            rospy.Subscriber(f"/{ROBOT}/worldmodel/teammessage", TeamMessage, self._on_team, queue_size=200),
            rospy.Subscriber(f"/{ROBOT}/worldmodel/ballflight", BallFlightInfo, self._on_flight, queue_size=200),
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

    def _on_flight(self, msg) -> None:
        with self.lock:
            self.flights.append(msg)

    @property
    def flight(self):
        with self.lock:
            return self.flights[-1] if self.flights else None

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


def test_a_flood_of_distinct_bad_coach_commands_is_counted_in_a_line_or_two(world, ros_master):
    """Every distinct bad CoachInfo once had a log line of its own (1333 lines in 5 s)."""
    import rospy

    from nubot_common.msg import CoachInfo

    node, watcher = world
    start = len(node.log_text())
    pub = rospy.Publisher(f"/{TEAM}/receive_from_coach", CoachInfo, queue_size=500)
    try:
        watcher.wait_for(lambda: pub.get_num_connections() > 0, timeout=10, what="the world model to subscribe")
        for k in range(300):
            pub.publish(CoachInfo(MatchMode=28 + k % 200, MatchType=k % 27))  # 28 and up: no MatchMode
            time.sleep(0.002)
    finally:
        pub.unregister()
    watcher.wait_for(lambda: "coach command refused" in node.log_text()[start:], timeout=10, what="the line")
    time.sleep(0.5)
    lines = [line for line in node.log_text()[start:].splitlines() if "coach command refused" in line]
    assert 1 <= len(lines) <= 2, lines[:4]
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


def _move_ball(x: float, y: float) -> None:

    from nubot_common.node_io import set_model_state

    set_model_state("football", x, y, 0.11, timeout=10)


def test_teammate_ball_is_used_when_the_robot_cannot_see_it_until_the_teammate_falls_silent(world):
    from dynamic_reconfigure.client import Client

    node, watcher = world
    reconfigure = Client("/sim_visual", timeout=20)
    reconfigure.update_configuration({"vision_range": 1.0})  # the ball is 3.6 m away
    try:
        _move_ball(-6.0, -3.0)  # and out of the goalie's RGB-D cameras' view (behind it)
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
        _move_ball(1.0, 2.0)
    watcher.wait_for(lambda: watcher.latest.ballinfo[0].ballinfostate == 1, timeout=10, what="the ball seen again")
    assert "Traceback" not in node.log_text()


LOB_FROM, LOB_VELOCITY = (-1.0, 1.0, 1.2), (-2.0, 0.5, 2.0)  # team frame [m], [m/s]


def _lob(t0: float, t: float):
    """BallInfo3d of the ball lobbed from LOB_FROM at ``t0`` as the RGB-D cameras see it at ``t`` [s]."""
    import genpy

    from nubot_common.ball_flight import GRAVITY
    from nubot_common.msg import BallInfo3d, Point3d

    dt = t - t0
    (x, y, z), (vx, vy, vz) = LOB_FROM, LOB_VELOCITY
    msg = BallInfo3d(pos=Point3d(x + vx * dt, y + vy * dt, z + vz * dt + 0.5 * GRAVITY * dt * dt),
                     velocity=Point3d(vx, vy, vz + GRAVITY * dt), pos_known_3d=True, pos_known_2d=True,
                     velocity_known=True)
    msg.header.stamp = genpy.Time.from_sec(t)
    return msg


def test_the_front_camera_s_and_the_rgbd_ball_are_fused_and_the_flight_is_published(world):
    """nubot1 is its team's goalie: the simulator gives it the 3-D ball; then, with the ball out of every own
    view, a front camera ball is the fused ball, and a lofted 3-D ball is, with its touchdown."""
    import math

    import genpy
    import rospy
    from dynamic_reconfigure.client import Client

    from nubot_common.ball_flight import landing
    from nubot_common.msg import BallInfo3d, FrontBallInfo, PPoint

    node, watcher = world
    watcher.wait_for(lambda: watcher.flight is not None and watcher.flight.ball.pos_known_3d, timeout=10,
                     what="the simulator's 3-D ball of the goalie")
    ground = watcher.flight
    assert not ground.in_air and (ground.ball.pos.x, ground.ball.pos.y, ground.ball.pos.z) == pytest.approx(
        (1.0, 2.0, 0.11), abs=0.05), "the ball lying at (1, 2)"
    front_pub = rospy.Publisher(f"/{ROBOT}/front_vision/FrontBallInfo", FrontBallInfo, queue_size=10)
    ball3d_pub = rospy.Publisher(f"/{ROBOT}/kinect/ballinfo", BallInfo3d, queue_size=10)
    reconfigure = Client("/sim_visual", timeout=20)
    try:
        _move_ball(-6.0, -3.0)  # behind the robot: out of its RGB-D cameras' view
        reconfigure.update_configuration({"vision_range": 1.0})  # and out of its omni camera's
        watcher.wait_for(lambda: watcher.latest.ballinfo[0].ballinfostate == 0
                         and not watcher.flight.ball.pos_known_3d, timeout=10, what="no own ball any more")
        watcher.wait_for(lambda: front_pub.get_num_connections() and ball3d_pub.get_num_connections(), timeout=10,
                         what="world_model to subscribe")

        def front(t: float) -> None:
            msg = FrontBallInfo(real_pos=PPoint(0.3, 0.8), pos_known=True)
            msg.header.stamp = genpy.Time.from_sec(t)
            front_pub.publish(msg)

        watcher.wait_sim(0.5, every_frame=front)
        with watcher.lock:  # a robot without a 3-D ball sends no flights: one to say it went, then none
            last_known = max(i for i, f in enumerate(watcher.flights) if f.ball.pos_known_3d)
            after = watcher.flights[last_known + 1:]
        assert [f.ball.pos_known_3d for f in after] == [False], "once without the 3-D ball, then nothing"
        info = watcher.latest
        me, ball = info.robotinfo[0], info.ballinfo[0]
        theta = me.heading.theta
        want = (me.pos.x + 0.8 * math.cos(theta + 0.3), me.pos.y + 0.8 * math.sin(theta + 0.3))
        assert (ball.ballinfostate, ball.pos_known) == (1, True)
        assert (ball.pos.x, ball.pos.y) == pytest.approx(want, abs=0.12), "0.8 m ahead, 0.3 rad to the left" \
            " (of a pose with 2 cm of noise a frame)"

        t0 = watcher.clock
        watcher.wait_sim(0.3, every_frame=lambda t: ball3d_pub.publish(_lob(t0, t)))
        watcher.wait_sim(0.1)
        with watcher.lock:  # the last flight that has its WorldModelInfo (the two topics arrive in either order)
            infos = {m.header.stamp: m for _, m in watcher.infos[-10:]}
            flight = next(f for f in reversed(watcher.flights) if f.header.stamp in infos and f.ball.pos_known_3d)
            info = infos[flight.header.stamp]
        assert flight.in_air and flight.header.stamp.to_sec() >= t0 + 0.2
        down = landing(*LOB_FROM, *LOB_VELOCITY, 0.11)
        assert (flight.touchdown.x, flight.touchdown.y) == pytest.approx((down.x, down.y), abs=0.01)
        assert flight.touchdown_time == pytest.approx(t0 + down.t, abs=0.005)
        ball = info.ballinfo[0]
        assert (ball.ballinfostate, ball.pos_known) == (1, True)
        assert (ball.pos.x, ball.pos.y) == pytest.approx((flight.ball.pos.x, flight.ball.pos.y), abs=1e-4), \
            "the ball in the air is the RGB-D cameras' (the front camera's is stale)"
    finally:
        front_pub.unregister()
        ball3d_pub.unregister()
        reconfigure.update_configuration({"vision_range": 0.0})
        reconfigure.close()
        _move_ball(1.0, 2.0)
    watcher.wait_for(lambda: watcher.latest.ballinfo[0].ballinfostate == 1, timeout=10, what="the ball seen again")
    assert "Traceback" not in node.log_text()
