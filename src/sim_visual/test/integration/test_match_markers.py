"""match_markers in a running 2 vs 2 match (match.launch, both teams by the spawner): its tf2 frames agree with the
model states, the referee's half time turns the team frames, the robots' planned paths lead to their targets, and
the field and scene markers come."""

import math
import sys
import threading
import time
from collections import OrderedDict

import pytest
import yaml

from nubot_common.geometry import quaternion_to_yaw, wrap_angle
from nubot_common.processes import wait_until
from nubot_common.team_frame import TeamFrame

pytestmark = pytest.mark.integration

TEAMS = (("nubot", 1), ("rival", -1))
TEAM = {"goalie": 1, "robots": [{"x": -8.4, "y": 0.0, "theta": 0.0}, {"x": -4.0, "y": 3.0, "theta": 0.0}]}


class MatchWatch:
    """Model states by sim time, each robot's planned paths and targets, and a tf2 buffer, in this process."""

    def __init__(self):
        import rospy
        import tf2_ros

        from nubot_common.msg import ModelStates, PlannedPath, TargetInfo

        self.lock = threading.Lock()
        self.states: OrderedDict[float, dict] = OrderedDict()  # sim time -> name -> (x, y, z, yaw)
        self.paths: dict[str, list] = {}  # robot -> [(stamp, frame_id, points)]
        self.targets: dict[str, dict[float, tuple[float, float]]] = {}  # robot -> stamp -> target
        self.buffer = tf2_ros.Buffer(rospy.Duration(30.0))
        self.listener = tf2_ros.TransformListener(self.buffer)
        self.subs = [rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=20)]
        for robot in ("nubot2", "rival2"):
            self.paths[robot], self.targets[robot] = [], {}
            self.subs += [
                rospy.Subscriber(f"/{robot}/nubotcontrol/path", PlannedPath,
                                 lambda m, r=robot: self.paths[r].append(
                                     (m.header.stamp.to_sec(), m.header.frame_id, [(p.x, p.y) for p in m.points])),
                                 queue_size=20),
                rospy.Subscriber(f"/{robot}/nubotcontrol/targetinfo", TargetInfo,
                                 lambda m, r=robot: self.targets[r].__setitem__(
                                     m.header.stamp.to_sec(), (m.target[0].x, m.target[0].y)), queue_size=20)]

    def _on_states(self, msg):
        poses = {n: (p.position.x, p.position.y, p.position.z,
                     quaternion_to_yaw(p.orientation.x, p.orientation.y, p.orientation.z, p.orientation.w))
                 for n, p in zip(msg.name, msg.pose)}
        with self.lock:
            self.states[msg.header.stamp.to_sec()] = poses
            while len(self.states) > 1000:
                self.states.popitem(last=False)

    def state_at(self, t: float) -> dict:
        """The model states of sim time ``t`` (waiting a little: a frame may overtake its states)."""
        wait_until(lambda: t in self.states, 2.0, f"the model states of {t}", 0.01)
        with self.lock:
            return self.states[t]

    def nearest_state(self, t: float) -> dict:
        with self.lock:
            return self.states[min(self.states, key=lambda s: abs(s - t))]

    def close(self):
        for sub in self.subs:
            sub.unregister()
        self.listener.unregister()


class Coach:
    """The coach's command to each team, repeated at 10 Hz until stopped (as the referee repeats it)."""

    def __init__(self, modes: dict[str, int]):
        import rospy

        from nubot_common.msg import CoachInfo

        self.pubs = {team: (rospy.Publisher(f"/{team}/receive_from_coach", CoachInfo, queue_size=1), mode)
                     for team, mode in modes.items()}
        self.running = True
        self.thread = threading.Thread(target=self._run, daemon=True)
        self.thread.start()

    def _run(self):
        from nubot_common.msg import CoachInfo

        while self.running:
            for pub, mode in self.pubs.values():
                pub.publish(CoachInfo(MatchMode=mode, MatchType=0))
            time.sleep(0.1)

    def stop(self):
        self.running = False
        self.thread.join()
        for pub, _ in self.pubs.values():
            pub.unregister()


@pytest.fixture(scope="module")
def match(ros_master, tmp_path_factory):
    folder = tmp_path_factory.mktemp("teams")
    sim = ros_master.launch("markers_match", ["roslaunch", "sim_visual", "match.launch"])
    teams = []
    watch = coach = None
    try:
        import rospy

        rospy.wait_for_service("/sim_visual/spawn_model", timeout=60)
        for prefix, attack in TEAMS:
            path = folder / f"{prefix}.yaml"
            path.write_text(yaml.safe_dump({"name": prefix, "prefix": prefix, "attack": attack, **TEAM}))
            teams.append(ros_master.launch(f"markers_team_{prefix}", [sys.executable, "-m", "nubot_tools.ros.spawner",
                                                                      str(path)]))
        watch = MatchWatch()
        from nubot_common.node_io import wait_for_robots

        silent = wait_for_robots([f"{p}{k}" for p, _ in TEAMS for k in (1, 2)], timeout=90)
        assert not silent, f"robots without a world model: {silent}\n{teams[0].log_text()[-3000:]}"
        coach = Coach({"nubot": 1, "rival": 2})  # our kick-off, theirs: every robot walks to its formation spot
        yield watch
    finally:
        if coach is not None:
            coach.stop()
        if watch is not None:
            watch.close()
        stopping = [threading.Thread(target=p.stop) for p in (*teams, sim)]  # each waits for its nodes: together
        for thread in stopping:
            thread.start()
        for thread in stopping:
            thread.join()
        time.sleep(0.5)


def lookup(watch, target: str, source: str):
    """The latest transform of ``source`` in ``target``: (sim time, x, y, z, yaw)."""
    import rospy

    wait_until(lambda: watch.buffer.can_transform(target, source, rospy.Time(0)), 20.0,
               f"tf2 to give {target} -> {source}", 0.05)
    tf = watch.buffer.lookup_transform(target, source, rospy.Time(0))
    t, r = tf.transform.translation, tf.transform.rotation
    return tf.header.stamp.to_sec(), t.x, t.y, t.z, quaternion_to_yaw(r.x, r.y, r.z, r.w)


def test_the_frames_agree_with_the_model_states(match):
    watch = match
    frames = TeamFrame(1), TeamFrame(-1)  # before any referee state: nubot (first alphabetically) attacks +x
    cases = [("world", "nubot1/base_link", None), ("world", "rival2/base_link", None),
             ("nubot", "rival2/base_link", frames[0]), ("rival", "nubot1/base_link", frames[1]),
             ("rival", "rival2/base_link", frames[1])]
    for target, source, frame in cases:
        t, x, y, _, yaw = lookup(watch, target, source)
        model = source.split("/")[0]
        wx, wy, _, wyaw = watch.state_at(t)[model]  # the frames carry the model states' own stamp
        if frame is not None:
            wx, wy = frame.point_to_team(wx, wy)
            wyaw = frame.heading_to_team(wyaw)
        assert math.dist((x, y), (wx, wy)) < 0.02, f"{target} -> {source} at {t}: ({x}, {y}), states ({wx}, {wy})"
        assert abs(wrap_angle(yaw - wyaw)) < 0.02
    t, x, y, z, _ = lookup(watch, "world", "ball")
    bx, by, bz, _ = watch.state_at(t)["football"]
    assert math.dist((x, y, z), (bx, by, bz)) < 0.02, "the ball at its height"


def test_the_referee_turns_the_team_frames_at_half_time(match):
    import rospy

    from nubot_common.msg import GameState

    watch = match
    pub = rospy.Publisher("/referee/state", GameState, queue_size=1, latch=True)
    try:
        for attacks, want in (([-1, 1], math.pi), ([1, -1], 0.0)):  # half time, then back as the match began
            pub.publish(GameState(teams=["nubot", "rival"], attack=attacks, half=2))

            def turned(want=want):
                _, x, y, _, yaw = lookup(watch, "world", "nubot")
                return abs(wrap_angle(yaw - want)) < 1e-6 and math.hypot(x, y) < 1e-9
            wait_until(turned, 10.0, f"world -> nubot turned to {want}", 0.05)
            _, _, _, _, rival_yaw = lookup(watch, "world", "rival")
            assert abs(wrap_angle(rival_yaw - want - math.pi)) < 1e-6
    finally:
        pub.unregister()


@pytest.mark.parametrize(("robot", "attack"), [("nubot2", 1), ("rival2", -1)])
def test_the_path_leads_from_the_robot_to_its_target(match, robot, attack):
    watch = match
    frame = TeamFrame(attack)

    def long_paths():  # the robot more than a metre from its target (the target published in the same cycle)
        return [(stamp, frame_id, points) for stamp, frame_id, points in list(watch.paths[robot])
                if len(points) >= 3 and stamp in watch.targets[robot]
                and math.dist(points[0], watch.targets[robot][stamp]) > 1.0]
    wait_until(long_paths, 20.0, f"a long path of {robot} with its target; paths {watch.paths[robot][-3:]}", 0.1)
    stamp, frame_id, points = long_paths()[0]
    assert frame_id == robot.rstrip("0123456789")
    assert len(points) <= 20
    target = watch.targets[robot][stamp]
    wx, wy, _, _ = watch.nearest_state(stamp)[robot]
    assert math.dist(points[0], frame.point_to_team(wx, wy)) < 0.3, "the path starts at the robot (team frame)"
    far = math.dist(points[0], target)
    # The motion layer keeps a plan while its goal stays within keep_plan_goal_shift + keep_plan_goal_share * the
    # distance still to go of the target (0.05 m + 10 %): the path ends there.
    assert math.dist(points[-1], target) < 0.05 + 0.1 * far + 0.05, f"the path ends at the target {target}: {points}"
    to_target = [math.dist(p, target) for p in points]
    # it leads there: it ends nearer than it starts, and no point is nearer than that kept plan's end allows
    assert to_target[-1] < to_target[0] and to_target[-1] <= min(to_target) + 0.05 + 0.1 * far, to_target


def test_the_field_and_the_scene_are_drawn(match):
    import rospy
    from visualization_msgs.msg import Marker, MarkerArray

    fields, scenes = [], []
    subs = [rospy.Subscriber("/match_markers/field", MarkerArray, fields.append, queue_size=1),
            rospy.Subscriber("/match_markers/scene", MarkerArray, scenes.append, queue_size=5)]

    def paths_drawn():
        return scenes and {m.header.frame_id for m in scenes[-1].markers if m.type == Marker.LINE_STRIP} >= \
            {"nubot", "rival"}
    try:
        # a publisher answers new subscribers' handshakes one at a time (rospy), so a busy one can be slow to connect
        wait_until(lambda: fields, 30.0, "the latched field markers", 0.05)
        wait_until(paths_drawn, 15.0, "both teams' paths in the scene (subscribed once the scene is watched)", 0.1)
    finally:
        for sub in subs:
            sub.unregister()
    lines = [m for m in fields[0].markers if m.ns == "lines"]
    assert len(lines) == 1 and len(lines[0].points) == 2 * 17, "touch, goal, halfway lines, both areas' three each"
    scene = scenes[-1].markers
    assert scene[0].action == Marker.DELETEALL
    bodies = {m.header.frame_id for m in scene if m.type == Marker.CYLINDER}
    assert bodies == {f"{p}{k}/base_link" for p, _ in TEAMS for k in (1, 2)}
    assert [m.header.frame_id for m in scene if m.type == Marker.SPHERE] == ["ball"]
