"""The goalie's whole software over real ROS against a lob: the simulator gives nubot2 (its team's goalie by the
simulator's ``goalies`` and robot.launch's ``goalie_id`` and ``goalie``, not AgentID 1) camera images and its two
RGB-D clouds; omni_vision, kinect_ball, world_model and nubot_control (``robot.launch perception:=vision``) see the
lob, announce its touchdown on ``/nubot2/worldmodel/ballflight``, plan a path to meet it on the lob line and take the
goalie there.

Whether this one lob is then kept out is not asserted: that is decided by hundredths of a second (in one process
without ROS the same lob was saved with the goalie's commands 0.1 s and 0.2 s late and scored with them 0.15 s late;
the cameras' early touchdowns stray up to 0.7 m from where it comes down), so it is a rate, bench_goalie's."""

from __future__ import annotations

import math
import threading
import time

import pytest

from nubot_common.processes import wait_until

pytestmark = pytest.mark.integration

GOALIE = "nubot2"
SETTLE = 2.0  # the goalie stands still this long, in its place, before the lob [s, sim time]
WATCH = 3.0  # a lob not scored this long after it is struck is saved [s, sim time]


class Watch:
    """The true ball and goalie, the goals, and the goalie's announced flights."""

    def __init__(self) -> None:
        import rospy

        from nubot_common.msg import BallFlightInfo, GoalEvent, ModelStates, PlannedPath

        self.lock = threading.Lock()
        self.states: list[tuple[float, tuple[float, ...], tuple[float, ...]]] = []  # (t, ball xyz, goalie x y v)
        self.goals: list = []
        self.flights: list = []
        self.paths: list[tuple[float, tuple[float, float]]] = []  # (stamp, where the path ends)
        self.subs = [rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=200),
                     rospy.Subscriber("/sim_visual/goal", GoalEvent, self._on_goal, queue_size=10),
                     rospy.Subscriber(f"/{GOALIE}/worldmodel/ballflight", BallFlightInfo, self._on_flight,
                                      queue_size=200),
                     rospy.Subscriber(f"/{GOALIE}/nubotcontrol/path", PlannedPath, self._on_path, queue_size=200)]

    def _on_states(self, msg) -> None:
        if "football" in msg.name and GOALIE in msg.name:
            b, g = msg.pose[msg.name.index("football")].position, msg.name.index(GOALIE)
            v = msg.twist[g].linear
            with self.lock:
                self.states.append((msg.header.stamp.to_sec(), (b.x, b.y, b.z),
                                    (msg.pose[g].position.x, msg.pose[g].position.y, math.hypot(v.x, v.y))))

    def _on_goal(self, msg) -> None:
        with self.lock:
            self.goals.append(msg)

    def _on_flight(self, msg) -> None:
        with self.lock:
            self.flights.append(msg)

    def _on_path(self, msg) -> None:
        if msg.points:
            with self.lock:
                self.paths.append((msg.header.stamp.to_sec(), (msg.points[-1].x, msg.points[-1].y)))

    def now(self) -> float:
        with self.lock:
            return self.states[-1][0] if self.states else 0.0

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()


def _service(name: str, kind):
    import rospy

    rospy.wait_for_service(name, timeout=30.0)
    return rospy.ServiceProxy(name, kind)


def _set_ball(x: float, y: float, z: float, vx: float = 0.0, vy: float = 0.0, vz: float = 0.0) -> None:
    from nubot_common.msg import ModelState
    from nubot_common.srv import SetModelState

    state = ModelState(model_name="football", reference_frame="world")
    state.pose.position.x, state.pose.position.y, state.pose.position.z = x, y, z
    state.pose.orientation.w = 1.0
    state.twist.linear.x, state.twist.linear.y, state.twist.linear.z = vx, vy, vz
    assert _service("/sim_visual/set_model_state", SetModelState)(state).success


def test_a_goalie_seeing_through_its_cameras_meets_a_lob_where_it_comes_down(ros_master):
    from geometry_msgs.msg import Pose

    from nubot_common.ball_flight import landing, time_to_x
    from nubot_common.params import load_yaml
    from nubot_common.srv import SpawnModel
    from nubot_common.world_description import load_world
    from nubot_control.behaviours import goalie_spot
    from nubot_control.params import ControlParams
    from nubot_match.config import CONFIG
    from nubot_tools.bench.goalie import LOB_LIFT, ball_launch, seeded_shots
    from sim_visual.params import SimNodeParams

    world = load_world("18x12")
    shot = seeded_shots(1, 0, world)[0]  # a lob that scores at an empty goal (test_bench_goalie)
    assert shot["kind"] == "lob"
    sim_config = load_yaml(SimNodeParams, CONFIG["sim"]).sim  # the simulator's shipped configuration
    launch = ball_launch(shot, world, sim_config.plugin, sim_config.physics.gravity)
    radius = world.ball.radius
    # At half real time: the test asks what the goalie's software does, not whether a machine busy with make test's
    # other suites keeps its camera pipeline within a frame of real time (a late start once let a lob in).
    sim = ros_master.launch("goalie_sim", ["roslaunch", "sim_visual", "match.launch", f"vision:={GOALIE}",
                                           f"goalies:={GOALIE},rival1", "clock_rate:=200", "real_time_factor:=0.5"])
    robot = coach = None
    watch = Watch()
    try:
        pose = Pose()
        pose.position.x, pose.orientation.w = -world.field.half_length + 0.4, 1.0
        assert _service("/sim_visual/spawn_model", SpawnModel)(GOALIE, pose, 1).success
        _set_ball(launch.x, launch.y, radius)
        robot = ros_master.launch("goalie", ["roslaunch", "nubot_control", "robot.launch", f"robot:={GOALIE}",
                                             "goalie_id:=2", "goalie:=true", "perception:=vision"])
        coach = ros_master.launch("coach", ["rostopic", "pub", "-r", "10", "/nubot/receive_from_coach",
                                            "nubot_common/CoachInfo", "\nMatchMode: 15\nMatchType: 0 "])

        def settled() -> bool:
            """The goalie sees the still ball: it has taken its place (``goalie_spot``: on the bisector of the angle
            its goal makes at the ball, play/goalie_line out) and stands there."""
            with watch.lock:
                recent = [s for s in watch.states if s[0] > watch.states[-1][0] - SETTLE] if watch.states else []
            return bool(recent) and recent[-1][0] - recent[0][0] > SETTLE - 0.1 and all(
                s[2][2] < 0.05 and math.hypot(s[2][0] - place[0], s[2][1] - place[1]) < 0.08 for s in recent)

        goal_x, play = -world.field.half_length, load_yaml(ControlParams, CONFIG["control"]).play
        place = goalie_spot((launch.x, launch.y), world.field, play.goalie_line)
        wait_until(settled, 60, f"the goalie standing in its place ({place[0]:.2f}, {place[1]:.2f})")
        struck_at = watch.now()
        _set_ball(launch.x, launch.y, radius + LOB_LIFT, launch.vx, launch.vy, launch.vz)
        wait_until(lambda: watch.now() > struck_at + WATCH, 20, f"{WATCH} s of sim time after the lob")
    except AssertionError as exc:
        logs = "\n".join(p.log_text()[-2500:] for p in (sim, robot) if p is not None)
        raise AssertionError(f"{exc}\n{logs}") from None
    finally:
        watch.close()
        for p in (coach, robot, sim):
            if p is not None:
                p.stop()
        time.sleep(0.5)

    free = landing(launch.x, launch.y, launch.z, launch.vx, launch.vy, launch.vz, radius)
    assert free.x < -world.field.half_length, "unhindered, the lob comes down in the goal"
    flights = [f for f in watch.flights if f.in_air and struck_at < f.header.stamp.to_sec() < struck_at + free.t]
    assert flights, "the goalie's world model announced the lob's flight"
    # Where the goalie's world model expected the lob to come down while it flew (the team frame is the world
    # frame: nubot2 attacks +x): near the free flight's touchdown, the goal behind the line stops it later.
    early = flights[len(flights) // 2]
    assert math.hypot(early.touchdown.x - free.x, early.touchdown.y - free.y) < 0.3, \
        f"announced touchdown ({early.touchdown.x:.2f}, {early.touchdown.y:.2f}), free flight's ({free.x:.2f}, " \
        f"{free.y:.2f})"
    # The lob comes down in the goal, so keep_goal meets it where it crosses the lob line (behind the goal line, where
    # a lob aimed under the bar is lowest).
    lob_x = goal_x + play.lob_line
    crossing = time_to_x(launch.x, launch.vx, lob_x)
    assert crossing is not None
    meet = (lob_x, launch.y + launch.vy * crossing)
    with watch.lock:
        before = [s for s in watch.states if s[0] <= struck_at][-1][2]
        at_crossing = [s for s in watch.states if s[0] <= struck_at + crossing][-1][2]
        track = [(round(s[0] - struck_at, 2), round(s[2][0], 2), round(s[2][1], 2)) for s in watch.states
                 if struck_at - 0.1 < s[0] < struck_at + free.t][::10]
        paths = [p for t, p in watch.paths if struck_at < t <= struck_at + crossing]
    outcome = f"scored after {watch.goals[0].header.stamp.to_sec() - struck_at:.2f} s" if watch.goals else "kept out"
    story = f"the lob crosses the lob line at ({meet[0]:.2f}, {meet[1]:.2f}) after {crossing:.2f} s; first announced " \
            f"at {flights[0].header.stamp.to_sec() - struck_at:.2f} s, touchdowns " \
            f"{[(round(f.touchdown.x, 2), round(f.touchdown.y, 2)) for f in flights[::5]]}; the paths end at " \
            f"{[(round(p[0], 2), round(p[1], 2)) for p in paths]}; the goalie (t, x, y): {track}; {outcome}"
    assert paths and math.hypot(paths[-1][0] - meet[0], paths[-1][1] - meet[1]) < 0.25, \
        f"the goalie's last path before the lob crossed the lob line ends where it crosses: {story}"
    start, end = (math.hypot(p[0] - meet[0], p[1] - meet[1]) for p in (before, at_crossing))
    assert end < start - 0.3, \
        f"the goalie went {start - end:.2f} m nearer the meeting point ({start:.2f} m away when the lob was struck), " \
        f"at least 0.3 m: {story}"
