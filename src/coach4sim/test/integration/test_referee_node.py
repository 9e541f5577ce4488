"""The referee node and the coach CLI over real ROS, with the simulator: nubot1 against rival1."""

import subprocess
import time

import pytest

pytestmark = pytest.mark.integration

CLI_TIMEOUT = 30.0  # [s, wall]


def _coach(ros_master, *args: str) -> subprocess.CompletedProcess:
    return subprocess.run(["rosrun", "coach4sim", "coach", *args], env=ros_master.env, capture_output=True,
                          text=True, timeout=CLI_TIMEOUT, check=False)


def test_each_team_hears_its_own_view_every_30_ms_from_the_referee_alone(match_world, ros_master):
    watcher, _, referee = match_world
    assert 1 in watcher.modes_since("nubot", 0.0), "the match starts with nubot's kickoff"
    assert 2 in watcher.modes_since("rival", 0.0), "... which rival hears as OPP_KICKOFF"
    start = time.monotonic()
    time.sleep(1.0)
    assert 20 <= len(watcher.modes_since("nubot", start)) <= 40, "CoachInfo every 30 ms (33 a second)"
    graph = ros_master.graph()
    for topic in ("/nubot/receive_from_coach", "/rival/receive_from_coach", "/referee/state"):
        assert graph.publishers[topic] == {"/referee"}, f"{topic}: {graph.publishers[topic]}"
    assert graph.services["/referee/command"] == {"/referee"}
    assert "the first half begins: kickoff for nubot" in referee.log_text()


def test_ball_over_the_side_line_after_a_nubot_touch_is_a_throw_in_for_rival(match_world):
    from nubot_common.srv import BallHandle

    watcher, _, referee = match_world
    assert watcher.command("STARTROBOT").accepted
    watcher.wait_for(lambda: watcher.game.running, timeout=5, what="play on")
    touches = len(watcher.touches)
    watcher.set_model("football", -2.0 + 0.45, 0.0, z=0.11)  # in front of nubot1
    ball_handle = watcher.service("/nubot1/BallHandle", BallHandle)
    assert ball_handle(1).BallIsHolding == 1
    watcher.wait_for(lambda: "nubot1" in watcher.touches[touches:], timeout=5, what="nubot1's touch")
    ball_handle(0)
    time.sleep(0.2)  # the referee has seen the touch
    watcher.set_model("football", 2.0, 6.5, z=0.11)  # wholly over the side line at y = +6
    watcher.wait_for(lambda: (watcher.mode("nubot"), watcher.mode("rival")) == (4, 3), timeout=5,
                     what="OPP_THROWIN for nubot, OUR_THROWIN for rival")
    watcher.wait_for(lambda: abs(watcher.ball()[1] - 5.9) < 0.02, timeout=5, what="the ball back on the line")
    x, y, z = watcher.ball()
    assert (x, y, z) == pytest.approx((2.0, 5.9, 0.11), abs=0.02)
    watcher.wait_for(lambda: "throw-in for rival" in watcher.game.last_event, timeout=3, what="the state")
    assert "last touch nubot1" in watcher.game.last_event
    assert "throw-in for rival" in referee.log_text()


def test_goal_scores_and_the_conceding_team_kicks_off(match_world):
    watcher, _, _ = match_world
    assert watcher.command("STARTROBOT").accepted
    watcher.wait_for(lambda: watcher.game.running, timeout=5, what="play on")
    before = list(watcher.game.score)
    watcher.set_model("football", 9.5, 0.3, z=0.11)  # in the goal at +x, which nubot attacks
    watcher.wait_for(lambda: (watcher.mode("nubot"), watcher.mode("rival")) == (2, 1), timeout=5,
                     what="the kickoff for rival")
    watcher.wait_for(lambda: abs(watcher.ball()[0]) < 0.02, timeout=5, what="the ball on the centre spot")
    time.sleep(0.5)
    assert list(watcher.game.score) == [before[0] + 1, before[1]], "one goal for nubot, counted once"


def test_coach_cli_command_reaches_both_teams_mirrored(match_world, ros_master):
    watcher, _, _ = match_world
    assert watcher.command("STOPROBOT").accepted  # holds the automatic referee: no STARTROBOT can intervene
    since = time.monotonic()
    result = _coach(ros_master, "OUR_KICKOFF", "--team", "nubot")
    assert result.returncode == 0, result.stderr
    assert "by hand: OUR_KICKOFF for nubot" in result.stdout
    watcher.wait_for(lambda: 1 in watcher.modes_since("nubot", since) and 2 in watcher.modes_since("rival", since),
                     timeout=5, what="OUR_KICKOFF for nubot, OPP_KICKOFF for rival")
    with watcher.lock:
        previous = next(p for wall, m, p in watcher.coach["nubot"] if wall >= since and m == 1)
    assert previous == 0, "MatchType carries the command before (STOPROBOT)"


def test_unknown_command_through_the_cli_exits_2_and_changes_nothing(match_world, ros_master):
    watcher, _, referee = match_world
    assert watcher.command("STOPROBOT").accepted
    watcher.wait_for(lambda: watcher.game.last_event == "by hand: STOPROBOT", timeout=5, what="the stop")
    since = time.monotonic()
    result = _coach(ros_master, "OUR_KICKOF", "--team", "nubot")
    assert result.returncode == 2
    assert "unknown MatchMode name 'OUR_KICKOF'" in result.stderr
    refused = watcher.command("14")
    assert not refused.accepted and "refused: unknown MatchMode 14" in refused.message
    refused = watcher.command("STARTROBOT", team="blue")
    assert not refused.accepted and "unknown team 'blue'; teams: nubot, rival" in refused.message
    time.sleep(0.5)
    assert set(watcher.modes_since("nubot", since)) == {0} and set(watcher.modes_since("rival", since)) == {0}
    assert watcher.game.last_event == "by hand: STOPROBOT" and not watcher.game.running
    assert "command '14' for team 'nubot' refused" in referee.log_text()


def test_coach_console_sends_typed_commands_through_the_referee(match_world, ros_master):
    watcher, _, _ = match_world
    since = time.monotonic()
    result = subprocess.run(["rosrun", "coach4sim", "coach", "--console", "--team", "rival"], input="3\nbogus\n\nq\n",
                            env=ros_master.env, capture_output=True, text=True, timeout=CLI_TIMEOUT, check=False)
    assert result.returncode == 0, result.stderr
    assert "referee: by hand: OUR_THROWIN for rival" in result.stdout
    assert "unknown MatchMode name 'bogus'" in result.stdout
    assert "referee: by hand: STOPROBOT" in result.stdout, "an empty line sends STOPROBOT"
    assert 4 in watcher.modes_since("nubot", since) and 3 in watcher.modes_since("rival", since)
    watcher.wait_for(lambda: watcher.mode("nubot") == 0, timeout=5, what="the STOPROBOT")


def test_coach_watch_prints_a_robots_world_model_and_the_score(match_world, ros_master):
    import threading

    import rospy

    from nubot_common.msg import BallInfo, CoachInfo, Point2d, RobotInfo, WorldModelInfo

    wm = WorldModelInfo(coachinfo=CoachInfo(MatchMode=15, MatchType=1))
    wm.robotinfo = [RobotInfo(AgentID=1, isvalid=True, pos=Point2d(-2.0, 0.0))]
    wm.ballinfo = [BallInfo(pos=Point2d(1.0, 2.0), pos_known=True, ballinfostate=1)]  # seen by its own sensors
    pub = rospy.Publisher("/nubot1/worldmodel/worldmodelinfo", WorldModelInfo, queue_size=1)
    done = threading.Event()

    def publish() -> None:
        while not done.wait(0.1):
            pub.publish(wm)

    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    try:
        result = _coach(ros_master, "--watch", "nubot1", "--count", "2")
    finally:
        done.set()
        thread.join()
        pub.unregister()
    assert result.returncode == 0, result.stderr
    assert "mode STARTROBOT (before: OUR_KICKOFF)" in result.stdout
    assert "me (-2.00, +0.00) +0 deg | ball (+1.00, +2.00) (own)" in result.stdout
    assert "nubot - rival" in result.stdout, "the score from /referee/state"


def test_a_ball_carried_over_3_m_is_called_and_the_recorded_bag_holds_the_call(match_world, ros_master, tmp_path):
    """RC-12.0.1 over real ROS: nubot1 takes the ball and is moved 4 m with it; the referee calls carrying on
    /referee/foul, gives rival a free kick, and a bag recorded meanwhile holds the call (as a match report reads
    it: nubot_match's test_bag)."""
    import rosbag
    import rospy

    from nubot_common.msg import RefereeCall
    from nubot_common.srv import BallHandle

    watcher, _, referee = match_world
    bag = tmp_path / "foul.bag"
    recorder = ros_master.launch("foul_recorder", [
        "rosbag", "record", "-O", str(bag), "/referee/foul", "/referee/state", "/sim_visual/model_states",
        "/sim_visual/ball_holder", "/sim_visual/ball_touch", "/sim_visual/world_description", "/clock",
        "__name:=foul_recorder"])
    calls = []
    sub = rospy.Subscriber("/referee/foul", RefereeCall, calls.append, queue_size=10)
    try:
        time.sleep(1.0)  # the recorder has subscribed
        assert watcher.command("STARTROBOT").accepted
        watcher.wait_for(lambda: watcher.game.running, timeout=5, what="play on")
        watcher.set_model("nubot1", -4.0, 1.0)
        watcher.set_model("football", -4.0 + 0.45, 1.0, z=0.11)  # in front of it
        assert watcher.service("/nubot1/BallHandle", BallHandle)(1).BallIsHolding == 1
        for k in range(1, 9):  # 4 m along +x, the held ball with it, at 2.5 m/s
            watcher.set_model("nubot1", -4.0 + 0.5 * k, 1.0)
            time.sleep(0.2)
            if calls:
                break
        watcher.wait_for(lambda: calls, timeout=5, what="the referee's call")
        call = calls[0]
        assert (call.kind, call.team, call.robot, call.rule) == ("carrying", "nubot", "nubot1", "RC-12.0.1")
        assert call.restart == "free kick for rival" and call.position.x > -3.6 + 3.0  # caught at x = -3.57
        watcher.wait_for(lambda: (watcher.mode("nubot"), watcher.mode("rival")) == (12, 11), timeout=5,
                         what="OPP_FREEKICK for nubot, OUR_FREEKICK for rival")
        watcher.wait_for(lambda: "carrying by nubot1" in watcher.game.last_event, timeout=3, what="the state")
        time.sleep(0.5)
    finally:
        sub.unregister()
        recorder.stop()
    with rosbag.Bag(str(bag)) as recorded:
        fouls = [m for _topic, m, _t in recorded.read_messages(topics=["/referee/foul"])]
    assert [(m.kind, m.team, m.robot, m.rule) for m in fouls] == [("carrying", "nubot", "nubot1", "RC-12.0.1")]
    assert "carrying by nubot1" in referee.log_text()


def test_without_a_referee_the_coach_publishes_the_command_itself(match_world, ros_master):
    """Stops the referee: keep this test last in the module."""
    watcher, _, referee = match_world
    referee.stop()
    watcher.wait_for(lambda: "/referee/command" not in ros_master.graph().services, timeout=10,
                     what="the referee gone")
    since = time.monotonic()
    result = _coach(ros_master, "OUR_PENALTY", "--team", "rival")
    assert result.returncode == 0, result.stderr
    assert ("no referee at /referee/command: publishing OUR_PENALTY (5) to /rival/receive_from_coach every 30 ms "
            "for 2 s") in result.stdout
    heard = watcher.modes_since("rival", since)
    assert set(heard) == {5} and len(heard) >= 20, f"about 2 s / 30 ms messages, heard {len(heard)}"
    assert watcher.modes_since("nubot", since) == [], "only the named team"

