"""The refbox_client node over real ROS and a real loopback TCP link to the practice RefBox (coach4sim.refbox_server):
every box command reaches both teams as the right MatchMode (and MatchType), without a referee and through it;
our worldstate arrives at >= 10 Hz with the box's required keys; malformed input is survived; and when the box
goes away and comes back, the client reconnects by itself and goes on."""

from __future__ import annotations

import json
import threading
import time
from pathlib import Path

import pytest

from coach4sim.refbox_server import RefboxServer
from nubot_common.match_mode import MatchMode as M
from nubot_common.processes import free_port, wait_until

pytestmark = pytest.mark.integration

WORLD = Path(__file__).resolve().parents[3] / "nubot_common" / "config" / "world_18x12.yaml"
US, THEM = "224.16.32.53", "224.16.32.127"  # the box's addresses of nubot (ours) and of the other team
S, GO, DB, PARK = M.STOPROBOT, M.STARTROBOT, M.DROPBALL, M.PARKINGROBOT
KO, OKO, TI, OTI, PE, OPE = M.OUR_KICKOFF, M.OPP_KICKOFF, M.OUR_THROWIN, M.OPP_THROWIN, M.OUR_PENALTY, M.OPP_PENALTY
GK, OGK, CK, OCK, FK, OFK = (M.OUR_GOALKICK, M.OPP_GOALKICK, M.OUR_CORNERKICK, M.OPP_CORNERKICK, M.OUR_FREEKICK,
                             M.OPP_FREEKICK)

# (command, target, robotID, nubot's MatchMode, rival's MatchMode): every command of the box, set pieces for each
# side, in an order where each command that must change nothing follows one that changed something.
STEPS = [
    ("WELCOME", "", None, S, S),
    ("KICKOFF", US, None, KO, OKO),
    ("GOAL", US, None, KO, OKO),
    ("SUBGOAL", US, None, KO, OKO),
    ("START", "", None, GO, GO),
    ("YELLOW_CARD", THEM, 2, GO, GO),
    ("RED_CARD", US, 3, GO, GO),
    ("DOUBLE_YELLOW", THEM, 4, GO, GO),
    ("REPAIR", US, 1, GO, GO),
    ("SUBSTITUTION", THEM, 5, GO, GO),
    ("TESTMODE_ON", "", None, GO, GO),
    ("TESTMODE_OFF", "", None, GO, GO),
    ("FREEKICK", THEM, None, OFK, FK),
    ("FIRST_HALF", "", None, OFK, FK),
    ("GOALKICK", US, None, GK, OGK),
    ("SECOND_HALF", "", None, GK, OGK),
    ("THROWIN", THEM, None, OTI, TI),
    ("FIRST_HALF_OVERTIME", "", None, OTI, TI),
    ("CORNER", US, None, CK, OCK),
    ("SECOND_HALF_OVERTIME", "", None, CK, OCK),
    ("PENALTY", THEM, None, OPE, PE),
    ("KICKOFF", THEM, None, OKO, KO),
    ("FREEKICK", US, None, FK, OFK),
    ("GOALKICK", THEM, None, OGK, GK),
    ("THROWIN", US, None, TI, OTI),
    ("CORNER", THEM, None, OCK, CK),
    ("PENALTY", US, None, PE, OPE),
    ("KICKOFF", "", None, PE, OPE),  # a set piece for nobody: ignored
    ("DROP_BALL", "", None, DB, DB),
    ("PARK", "", None, PARK, PARK),
    ("END_PART", "", None, S, S),
    ("START", "", None, GO, GO),
    ("HALF_TIME", "", None, S, S),
    ("START", "", None, GO, GO),
    ("END_GAME", "", None, S, S),
    ("START", "", None, GO, GO),
    ("GAMEOVER", "", None, S, S),
    ("START", "", None, GO, GO),
    ("RESET", "", None, S, S),
]


class ClientWatch:
    """What the client says (~status) and what each team hears (CoachInfo: MatchMode, MatchType)."""

    def __init__(self) -> None:
        import rospy
        from std_msgs.msg import String

        from nubot_common.msg import CoachInfo

        self.lock = threading.Lock()
        self.status: dict = {}
        self.coach: dict[str, tuple[int, int]] = {}
        self.subs = [rospy.Subscriber("/refbox_client/status", String, self._on_status, queue_size=100)]
        self.subs += [rospy.Subscriber(f"/{t}/receive_from_coach", CoachInfo, self._on_coach, callback_args=t,
                                       queue_size=100) for t in ("nubot", "rival")]

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()

    def _on_status(self, msg) -> None:
        with self.lock:
            self.status = json.loads(msg.data)

    def _on_coach(self, msg, team: str) -> None:
        from nubot_common.conversions import char_value

        with self.lock:
            self.coach[team] = (char_value(msg.MatchMode), char_value(msg.MatchType))

    def get(self, key: str, default=None):
        with self.lock:
            return self.status.get(key, default)

    def heard(self) -> tuple[tuple[int, int] | None, tuple[int, int] | None]:
        with self.lock:
            return self.coach.get("nubot"), self.coach.get("rival")


class Box:
    """The practice RefBox on a fixed free port, which a test may close and start again."""

    def __init__(self) -> None:
        self.port = free_port()
        self.lines: list[str] = []
        self.server = RefboxServer(port=self.port, log=self.lines.append).start()

    def restart(self) -> None:
        self.server = RefboxServer(port=self.port, log=self.lines.append).start()


def launch_client(ros_master, box: Box, other_team: str):
    client = ros_master.launch(f"refbox_client_{other_team or 'alone'}", [
        "roslaunch", "coach4sim", "refbox_client.launch", f"port:={box.port}", f"team_address:={US}",
        f"other_team:={other_team}"])
    try:
        box.server.wait_for(lambda: box.server.open_connections() == 1, 30.0, "the client's connection")
    except TimeoutError:
        client.stop()
        raise AssertionError(f"the client did not connect:\n{client.log_text()[-3000:]}") from None
    return client


def referee_serving() -> bool:
    import rosgraph

    try:
        rosgraph.Master("/refbox_test").lookupService("/referee/command")
        return True
    except rosgraph.MasterError:
        return False


@pytest.fixture(scope="module")
def box():
    box = Box()
    yield box
    box.server.close()


@pytest.fixture(scope="module")
def lone_client(ros_master, box):
    """The client for nubot and rival (both ours) with no referee running: it publishes CoachInfo itself."""
    wait_until(lambda: not referee_serving(), 10.0, "no referee from an earlier test")
    watch = ClientWatch()
    client = launch_client(ros_master, box, "rival")
    wait_until(lambda: watch.get("applied", 0) >= 1, 10.0, "the client's status after the box's WELCOME")
    yield watch, client
    watch.close()
    client.stop()
    time.sleep(0.5)  # the master forgets the node before the next one registers


def run_steps(box: Box, watch: ClientWatch) -> None:
    """Send every step; after the client has applied it, each team must hear its MatchMode and, as MatchType, the
    command before it (a command that changes nothing keeps both)."""
    nubot, rival = watch.heard()
    expected = {"nubot": nubot, "rival": rival}
    applied = watch.get("applied", 0)
    for command, target, robot, *modes in STEPS:
        for team, mode in zip(("nubot", "rival"), modes):
            if mode != expected[team][0]:
                expected[team] = (mode, expected[team][0])
        want = (expected["nubot"], expected["rival"])
        box.server.send(command, target, robot)
        applied += 1
        wait_until(lambda n=applied: watch.get("applied", 0) >= n, 5.0, f"the client applying {command}")
        try:
            wait_until(lambda w=want: watch.heard() == w, 3.0, "the teams' (MatchMode, MatchType)")
        except AssertionError:
            raise AssertionError(f"{command} for {target or 'both'}: heard {watch.heard()}, want {want} "
                                 f"(status: {watch.status})") from None
        time.sleep(0.07)  # two CoachInfo periods: nothing else changes it
        assert watch.heard() == want, f"{command} for {target or 'both'}"


def test_without_a_referee_every_box_command_reaches_both_our_teams(lone_client, box):
    watch, client = lone_client
    wait_until(lambda: watch.heard()[0] == (S, S) and watch.heard()[1] == (S, S), 10.0,
               "STOPROBOT for both teams before any command")
    assert watch.get("via") == "topic" and watch.get("connected") is True
    run_steps(box, watch)
    log = client.log_text()
    assert f"KICKOFF for {US} (us) -> OUR_KICKOFF" in log and f"PENALTY for {THEM} (them) -> OPP_PENALTY" in log
    assert "YELLOW_CARD for 224.16.32.127 robot 2: no game command" in log


def wm_message(agent: int, *, pose, role: int, holding: bool, ball=None, opponents=()):
    """Robot ``agent``'s world model as world_model publishes it (team frame), with itself valid."""
    import rospy

    from nubot_common.msg import BallInfo, Point2d, RobotInfo, WorldModelInfo

    msg = WorldModelInfo()
    msg.header.stamp = rospy.Time.from_sec(time.time())
    msg.robotinfo = [RobotInfo(AgentID=i) for i in range(1, 6)]
    msg.ballinfo = [BallInfo() for _ in range(5)]
    me = msg.robotinfo[agent - 1]
    me.header.stamp = msg.header.stamp
    me.isvalid, me.isdribble, me.current_role = True, holding, role
    me.pos, me.heading.theta = Point2d(pose[0], pose[1]), pose[2]
    me.vtrans, me.vrot = Point2d(1.0, -0.5), 0.25
    me.target = Point2d(3.0, -1.0)
    if ball is not None:
        own = msg.ballinfo[agent - 1]
        own.header.stamp = msg.header.stamp
        own.ballinfostate, own.pos_known, own.pos, own.velocity_known, own.velocity = 1, True, Point2d(*ball), True, \
            Point2d(0.5, 0.0)
    msg.obstacleinfo.pos = [Point2d(*p) for p in opponents]
    msg.oppinfo.pos = [Point2d(*p) for p in opponents]
    return msg


def test_our_worldstate_arrives_at_20_hz_with_the_required_keys_in_the_box_axes(lone_client, box):
    import rospy

    from nubot_common.msg import StrategyInfo, WorldModelInfo

    watch, _ = lone_client
    pubs = {a: rospy.Publisher(f"/nubot{a}/worldmodel/worldmodelinfo", WorldModelInfo, queue_size=1) for a in (1, 2)}
    strategy = rospy.Publisher("/nubot1/nubotcontrol/strategy", StrategyInfo, queue_size=1)
    stop = threading.Event()

    def publish() -> None:  # the two robots' world models at 30 Hz, nubot1's strategy too
        while not stop.wait(1 / 30):
            pubs[1].publish(wm_message(1, pose=(-2.0, 1.0, 0.5), role=2, holding=False, ball=(3.0, -1.0),
                                       opponents=[(4.0, 2.0)]))
            pubs[2].publish(wm_message(2, pose=(-8.0, 0.0, 0.0), role=0, holding=False, opponents=[(4.1, 2.1)]))
            strategy.publish(StrategyInfo(AgentID=1, role=1, is_dribble=True))

    thread = threading.Thread(target=publish, daemon=True)
    thread.start()
    try:
        server = box.server
        wait_until(lambda: len((server.last_worldstate() or {}).get("robots", [])) == 2, 10.0, "both robots reported")
        before = server.stats()[-1]
        time.sleep(2.0)
        stats = server.stats()[-1]
        message = server.last_worldstate()
    finally:
        stop.set()
        thread.join()
        for pub in (*pubs.values(), strategy):
            pub.unregister()
    print(f"worldstate rate at the box: {stats.rate:.1f} Hz ({stats.valid - before.valid} in 2 s)")
    assert stats.rate >= 10.0, f"the box requires 10 Hz, got {stats.rate:.1f}"
    assert 15.0 <= (stats.valid - before.valid) / 2.0 <= 25.0, "about the configured 20 Hz"
    assert (stats.invalid, stats.malformed) == (0, 0) and server.errors == []
    assert message["teamName"] == "NuBot" and message["intention"] == "STOPROBOT"
    assert 0 <= message["ageMs"] < 200
    first, second = message["robots"]
    assert first == {"id": 1, "pose": [-1.0, -2.0, 0.5], "targetPose": [1.0, 3.0, 0.5], "velocity": [0.5, 1.0, 0.25],
                     "intention": "ACTIVE", "batteryLevel": 100.0, "ballEngaged": 1}, "strategy: role, dribbling"
    assert (second["id"], second["pose"], second["intention"], second["targetPose"]) == \
        (2, [0.0, -8.0, 0.0], "GOALIE", [0.0, -8.0, 0.0]), "no strategy: the world model's role, no target"
    assert message["balls"] == [{"position": [1.0, 3.0, 0.0], "velocity": [0.0, 0.5, 0.0], "confidence": 1.0}]
    [obstacle] = message["obstacles"]
    assert obstacle["position"] == pytest.approx([-2.05, 4.05]) and obstacle["confidence"] == 1.0
    assert watch.get("robots") == [1, 2] and watch.get("worldstate_rate") >= 10.0


def test_malformed_and_oversized_messages_from_the_box_are_counted_and_the_link_goes_on(lone_client, box):
    watch, client = lone_client
    server = box.server
    malformed, connections = watch.get("malformed"), watch.get("connections")
    server.send("STOP")
    server.send_raw(b'{"command": "KICKOFF", "targetTeam": \0')  # cut short
    server.send_raw(b"x" * 150_000 + b"\0")  # longer than the box's own 100 kB limit
    server.send_raw(b'["KICKOFF"]\0{"targetTeam": "224.16.32.53"}\0{"command": "KICKOFF", "robotID": "one"}\0')
    server.send("KICKOFF", US)
    wait_until(lambda: watch.heard()[0] is not None and watch.heard()[0][0] == KO, 5.0, "the KICKOFF after the junk")
    wait_until(lambda: watch.get("malformed") == malformed + 5, 3.0, "five dropped messages counted")
    assert watch.get("connections") == connections and watch.get("connected") is True
    assert [s.open for s in server.stats()].count(True) == 1
    log = client.log_text()
    assert "message from the box dropped" in log and "malformed JSON" in log


def test_a_flood_of_unknown_commands_is_counted_in_a_line_or_two(lone_client, box):
    """Every unknown RefBox command once had a log line of its own."""
    watch, client = lone_client
    start = len(client.log_text())
    commands = watch.get("commands")
    for k in range(100):  # changes no team's command: the next test finds the game as the one before left it
        box.server.send(f"DANCE_{k}")
    wait_until(lambda: watch.get("commands") >= commands + 100, 10.0, "every command taken")
    time.sleep(0.3)
    lines = [line for line in client.log_text()[start:].splitlines() if "unknown command" in line]
    assert 1 <= len(lines) <= 2, lines[:4]


def test_the_client_reconnects_when_the_box_goes_away_and_comes_back(lone_client, box):
    watch, client = lone_client
    outages = watch.get("outages")
    box.server.close()
    wait_until(lambda: watch.get("connected") is False, 5.0, "the client noticing the box is gone")
    time.sleep(1.2)  # a failed attempt or two (after 0.5 s, then 1 s later)
    box.restart()
    box.server.wait_for(lambda: box.server.open_connections() == 1, 10.0, "the reconnection")
    box.server.wait_for(lambda: box.server.stats()[0].valid >= 5, 5.0, "worldstates again")
    wait_until(lambda: watch.get("connected") is True, 5.0, "the client's status")
    box.server.send("PENALTY", THEM)
    wait_until(lambda: watch.heard() == ((OPE, KO), (PE, OKO)), 5.0, "a command after the reconnection")
    assert watch.get("outages") == outages + 1
    log = client.log_text()
    assert log.count("lost the RefBox at") == 1, "one line for the outage"
    assert log.count("cannot reach the RefBox") == 0, "the failed attempts within it stay quiet"
    assert "failed attempt" in log.split("lost the RefBox at", 1)[1], "the reconnection says how long it took"


def test_through_the_referee_every_box_command_reaches_both_teams(ros_master, box, lone_client):
    """With the referee running the client sends through /referee/command, as `rosrun coach4sim coach` does, and
    the referee (teams nubot and rival) publishes each team's view."""
    _, lone = lone_client
    lone.stop()  # a team runs one client; this one speaks for nubot alone
    box.server.wait_for(lambda: box.server.open_connections() == 0, 5.0, "the first client gone")
    referee = ros_master.launch("refbox_referee", ["roslaunch", "coach4sim", "referee.launch", "auto:=false",
                                                   f"world:={WORLD}"])
    watch = ClientWatch()
    client = None
    try:
        try:
            wait_until(referee_serving, 30.0, "the referee's service")
        except AssertionError:
            raise AssertionError(f"the referee did not start:\n{referee.log_text()[-2000:]}") from None
        client = launch_client(ros_master, box, "")
        wait_until(lambda: watch.get("via") == "referee", 10.0, "the client finding the referee")
        wait_until(lambda: None not in watch.heard(), 10.0, "the referee's CoachInfo")
        run_steps(box, watch)
        publishers = ros_master.graph().publishers
        for topic in ("/nubot/receive_from_coach", "/rival/receive_from_coach"):
            assert publishers[topic] == {"/referee"}, f"one producer of {topic}"
        assert "referee accepted: OUR_KICKOFF for nubot" in client.log_text()
    finally:
        watch.close()
        for process in (client, referee):
            if process is not None:
                process.stop()
        time.sleep(0.5)


def test_the_box_rejected_none_of_our_worldstates_in_this_module(box):
    assert [line for line in box.lines if "rejected" in line] == []
    assert sum("connected from" in line for line in box.lines) == 3, "the first client twice, the second once"
