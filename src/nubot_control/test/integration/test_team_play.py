"""Team play over real ROS: two teams of three spawned by the spawner, each robot's world model and nubot_control in
one node (/<r>/robot) for nubot and in two (/<r>/world_model, /<r>/nubot_control) for rival; rival3 plays a policy
file (the spawner's --policy) that turns on the spot in open play."""

import itertools
import math
import subprocess
import sys
import time
from pathlib import Path

import pytest
import yaml

from nubot_common.geometry import quaternion_to_yaw
from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

ROOT = Path(__file__).resolve().parents[4]
TEAM = {"robots": [{"x": -8.4, "y": 0.0, "theta": 0.0}, {"x": -1.5, "y": 1.0, "theta": 0.0},
                   {"x": -3.0, "y": -2.0, "theta": 0.0}], "goalie": 1}
PROCESSES = {"nubot": "one", "rival": "two"}  # the spawner's --processes for each team
SPIN = 4.0  # [rad/s] rival3's policy file turns at this rate whatever it sees


def spinning_policy(path: Path) -> Path:
    from nubot_common.policy import PolicyNet
    from nubot_control.policy_player import OBSERVABLE

    n = len(OBSERVABLE)
    return PolicyNet.constant([0.0, 0.0, SPIN, 0.0, 0.0], OBSERVABLE, [-50.0] * n, [50.0] * n,
                              [-5.0, -5.0, -12.0, 0.0, 0.0], [5.0, 5.0, 12.0, 1.0, 1.0]).save(path)


def robot_nodes(robot: str) -> set[str]:
    """The nodes of a robot's world model and control."""
    team = robot.rstrip("0123456789")
    return {f"/{robot}/robot"} if PROCESSES[team] == "one" else {f"/{robot}/world_model", f"/{robot}/nubot_control"}


class Watch:
    def __init__(self):
        import rospy

        from nubot_common.msg import ModelStates, StrategyInfo, WorldModelInfo

        self.poses, self.roles, self.mates = {}, {}, []
        self.yaw, self.turned = None, 0.0  # rival3's heading [rad] and how far it has turned in all [rad]
        self.subs = [rospy.Subscriber("/sim_visual/model_states", ModelStates, self._states, queue_size=1),
                     rospy.Subscriber("/nubot1/worldmodel/worldmodelinfo", WorldModelInfo,
                                      lambda m: setattr(self, "mates", list(m.robotinfo)), queue_size=1)]
        for name in ("nubot2", "nubot3"):
            self.subs.append(rospy.Subscriber(f"/{name}/nubotcontrol/strategy", StrategyInfo,
                                              lambda m, n=name: self.roles.__setitem__(n, (time.monotonic(), m.role)),
                                              queue_size=1))

    def _states(self, msg):
        self.poses = {n: (p.position.x, p.position.y) for n, p in zip(msg.name, msg.pose)}
        if "rival3" in msg.name:
            q = msg.pose[msg.name.index("rival3")].orientation
            yaw = quaternion_to_yaw(q.x, q.y, q.z, q.w)
            if self.yaw is not None:
                self.turned += abs(math.remainder(yaw - self.yaw, 2.0 * math.pi))
            self.yaw = yaw

    def wait(self, predicate, timeout, what):
        wait_until(predicate, timeout, f"{what}; poses {self.poses}, roles {self.roles}", poll=0.1)


@pytest.fixture(scope="module")
def match(ros_master, tmp_path_factory):
    import rospy

    folder = tmp_path_factory.mktemp("teams")
    sim = ros_master.launch("match_sim", ["roslaunch", "sim_visual", "match.launch"])
    rospy.wait_for_service("/sim_visual/spawn_model", timeout=60)
    teams = []
    for prefix, attack in (("nubot", 1), ("rival", -1)):
        path = folder / f"{prefix}.yaml"
        path.write_text(yaml.safe_dump({"name": prefix, "prefix": prefix, "attack": attack, **TEAM}))
        policy = ["--policy", str(spinning_policy(folder / "spin.npz")), "--policy-robots", "3"] \
            if prefix == "rival" else []
        teams.append(ros_master.launch(f"team_{prefix}", [sys.executable, "-m", "nubot_tools.ros.spawner",
                                                          str(path), "--processes", PROCESSES[prefix], *policy]))
    watch = Watch()
    from nubot_common.node_io import wait_for_robots

    silent = wait_for_robots([f"{p}{k}" for p in ("nubot", "rival") for k in (1, 2, 3)], timeout=120)
    assert not silent, f"robots without a world model: {silent}\n{teams[0].log_text()[-3000:]}"
    yield ros_master, watch
    for sub in watch.subs:
        sub.unregister()
    for process in (*teams, sim):
        process.stop()
    time.sleep(0.5)


_PUBLISHERS = itertools.count()


def coach(master, team, mode):
    """The chapter's command line, as written (multi-line YAML), repeated at 10 Hz in the background."""
    return master.launch(f"coach_{team}_{mode}_{next(_PUBLISHERS)}",
                         ["rostopic", "pub", "-r", "10", f"/{team}/receive_from_coach", "nubot_common/CoachInfo",
                          f"\nMatchMode: {mode}\nMatchType: 0 "])


def stop(*processes):
    """SIGINT, then SIGKILL: a loaded machine once left `rostopic pub` ignoring SIGTERM for 10 s after a kill."""
    for p in processes:
        p.interrupt()
    for p in processes:
        p.stop()


def test_our_kickoff_by_rostopic_pub_gives_the_kickoff_formation(match):
    master, watch = match
    pubs = coach(master, "nubot", 1), coach(master, "rival", 2)
    try:
        def formed():
            p = watch.poses
            if not p:
                return False
            ours_home = all(p[f"nubot{k}"][0] < 0.05 for k in (1, 2, 3))
            taker = min(math.dist(p[f"nubot{k}"], p["football"]) for k in (2, 3)) < 0.8
            theirs_out = all(math.dist(p[f"rival{k}"], p["football"]) > 2.0 and p[f"rival{k}"][0] > 0
                             for k in (1, 2, 3))
            return ours_home and taker and theirs_out
        watch.wait(formed, 30, "the kickoff formation")

        def targets_reached():  # RobotInfo.target, as the goalie's world model shows its teammates
            targets = {f"nubot{r.AgentID}": (r.target.x, r.target.y) for r in watch.mates if r.isvalid}
            return len(targets) == 3 and all(math.dist(watch.poses[n], t) < 0.6 for n, t in targets.items())
        watch.wait(targets_reached, 10, f"RobotInfo.target at each robot's formation spot; mates {watch.mates}")
    finally:
        stop(*pubs)


def test_after_start_the_teams_play_the_ball_and_the_policy_file_drives_rival3(match):
    master, watch = match
    start = watch.poses["football"]
    turned_before = watch.turned
    pubs = coach(master, "nubot", 15), coach(master, "rival", 15)
    try:
        watch.wait(lambda: math.dist(watch.poses["football"], start) > 1.5, 40, "the ball to be played")
        # once the kick-off is taken the ball is in open play: rival3's policy turns it at SPIN
        watch.wait(lambda: watch.turned - turned_before > 4.0 * math.pi, 15,
                   f"rival3 to turn on the spot (turned {watch.turned - turned_before:.1f} rad)")
    finally:
        stop(*pubs)


def test_running_match_graph_matches_the_topic_table(match):
    import re

    master, watch = match
    text = (ROOT / "docs" / "topics.md").read_text().split("## Topics of a match")[1].split("## ")[0]
    rows = [[c.strip().strip("`") for c in line.strip("|").split("|")] for line in text.splitlines()
            if line.startswith("| `")]
    graph = master.graph()
    published, heard = graph.publishers, graph.subscribers
    assert {"/nubot1/robot"} <= heard.get("/nubot1/kinect/ballinfo", set()), "the goalie's 3-D ball"
    assert {"/rival1/world_model"} <= heard.get("/rival1/kinect/ballinfo", set()), "the goalie's 3-D ball"
    assert published.get("/nubot1/kinect/ballinfo") == {"/sim_visual"}
    assert {"/rival3/nubot_control"} <= heard.get("/rival3/worldmodel/ballflight", set())
    # in one process the robot's own decisions do not go back into it over ROS
    for topic in ("worldmodel/worldmodelinfo", "worldmodel/ballflight", "nubotcontrol/strategy",
                  "nubotcontrol/targetinfo"):
        assert "/nubot3/robot" not in heard.get(f"/nubot3/{topic}", set()), topic
    checked = 0
    for topic, _type, producer, *_ in rows:
        if topic.startswith(("/<T>/receive_from_coach", "/referee")):
            continue  # the referee is not part of this world
        for robot in ("nubot3", "rival2"):
            team = robot.rstrip("0123456789")
            name = topic.replace("<r>", robot).replace("<T>", team)
            want = {re.sub(r"<r>", robot, p).replace("<T>", team) for p in re.findall(r"/[<>a-zA-Z_/]+", producer)}
            if PROCESSES[team] == "one" and want & {f"/{robot}/world_model", f"/{robot}/nubot_control"}:
                want = {f"/{robot}/robot"}  # the table's two nodes are one node here (the paragraph above it)
            assert published.get(name) == want, f"{name}: published by {published.get(name)}, table says {want}"
            checked += 1
    assert checked == 24


def original_type(name: str):
    """A message class built from the original NuBot nubot_common definition of ``name`` (as a node compiled
    against that package has it): its md5sum is the original's, not read from our generated code."""
    import genmsg
    import genmsg.msg_loader as loader
    import rospkg
    from genpy.dynamic import generate_dynamic

    originals = ROOT / "src" / "nubot_common" / "test" / "original_msgs"
    search = {"nubot_common": [str(originals)],
              "std_msgs": [str(Path(rospkg.RosPack().get_path("std_msgs")) / "msg")]}
    context = loader.MsgContext.create_default()
    spec = loader.load_msg_by_type(context, f"nubot_common/{name}", search)
    loader.load_depends(context, spec, search)
    return generate_dynamic(f"nubot_common/{name}", genmsg.compute_full_text(context, spec))[f"nubot_common/{name}"]


@pytest.mark.parametrize(("topic", "name"), [
    ("/nubot3/worldmodel/worldmodelinfo", "WorldModelInfo"),
    ("/nubot3/nubotcontrol/strategy", "StrategyInfo"),
    ("/nubot/simulation_interface/strategy", "simulation_strategy"),
    ("/rival2/omnivision/OmniVisionInfo", "OminiVisionInfo"),
    ("/rival2/nubotcontrol/targetinfo", "TargetInfo"),
])
def test_a_node_built_against_the_original_messages_hears_ours(match, topic, name):
    """ROS 1 connects only when md5sums agree: a subscriber of the original type receives our messages."""
    import rospy

    cls = original_type(name)
    received = []
    sub = rospy.Subscriber(topic, cls, received.append, queue_size=5)
    try:
        # a publisher answers new subscribers' handshakes one at a time (rospy), so a busy one can be slow to connect
        wait_until(lambda: received, 30.0, f"a {name} on {topic} for a subscriber of the original type")
    finally:
        sub.unregister()
    assert cls._md5sum == received[0]._md5sum


def test_only_the_nodes_that_keep_sim_time_take_the_clock(match):
    """Every /clock message costs each rospy node that takes it about 0.2 ms of CPU: the spawners, idle once their
    robots are spawned, are not nodes, so the clock goes only to the robots' software, the relays, the simulator,
    its markers and this test."""
    import rosgraph
    import rospy

    robots = set().union(*(robot_nodes(f"{p}{k}") for p in ("nubot", "rival") for k in (1, 2, 3)))
    others = {"/nubot/sim_interface", "/rival/sim_interface", "/sim_visual", "/match_markers", rospy.get_name()}

    def clock() -> set[str]:
        _pubs, subscribers, _services = rosgraph.Master("/test_team_play").getSystemState()
        return set(next((nodes for topic, nodes in subscribers if topic == "/clock"), []))

    wait_until(lambda: robots <= clock(), 60, f"every robot's nodes on /clock: {sorted(robots - clock())} missing")
    assert clock() <= robots | others, f"/clock goes also to {sorted(clock() - robots - others)}"


def test_killing_a_robot_node_hands_its_role_to_a_teammate(match):
    """Last in this module: it kills nubot2's or nubot3's node (world model and control in one), which the tests
    above listen to."""
    master, watch = match
    pubs = coach(master, "nubot", 15), coach(master, "rival", 15)
    try:
        watch.wait(lambda: any(r == 1 for _, r in watch.roles.values()), 20, "an ACTIVE robot")
        victim = next(n for n, (_, r) in watch.roles.items() if r == 1)
        other = "nubot3" if victim == "nubot2" else "nubot2"
        subprocess.run(["rosnode", "kill", f"/{victim}/robot"], env=master.env, check=True,
                       capture_output=True, timeout=20)
        killed = time.monotonic()
        watch.wait(lambda: watch.roles[other][1] == 1 and time.monotonic() - watch.roles[other][0] < 1.0, 20,
                   f"{other} to take over the ACTIVE role")
        time.sleep(1.0)
        # a message already on the wire may land just after the kill; none may come later
        assert watch.roles[victim][0] < killed + 0.5, "the killed node is silent"
        assert watch.roles[other][1] == 1, "the role stays"
    finally:
        stop(*pubs)
