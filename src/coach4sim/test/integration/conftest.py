"""Fixtures for the referee's integration tests: the single-robot world plus rival1, and the referee node
launched with its real launch file, watched from this (already initialised) test node in wall-clock time."""

from __future__ import annotations

import threading
import time

import pytest

from nubot_common.processes import wait_until


class MatchWatcher:
    """Records what the referee tells each team and what the simulator reports."""

    def __init__(self, teams: tuple[str, ...] = ("nubot", "rival")):
        import rospy

        from nubot_common.msg import BallTouch, CoachInfo, GameState, ModelStates

        self.lock = threading.Lock()
        self.coach: dict[str, list[tuple[float, int, int]]] = {t: [] for t in teams}  # (wall, mode, previous)
        self.states: dict[str, tuple[float, float, float]] = {}
        self.game: GameState | None = None
        self.touches: list[str] = []
        self.subs = [rospy.Subscriber(f"/{t}/receive_from_coach", CoachInfo, self._on_coach, callback_args=t,
                                      queue_size=100) for t in teams]
        self.subs += [
            rospy.Subscriber("/sim_visual/model_states", ModelStates, self._on_states, queue_size=1),
            rospy.Subscriber("/referee/state", GameState, self._on_game, queue_size=10),
            rospy.Subscriber("/sim_visual/ball_touch", BallTouch, lambda m: self.touches.append(m.robot),
                             queue_size=10),
        ]

    def close(self) -> None:
        for sub in self.subs:
            sub.unregister()

    def _on_coach(self, msg, team: str) -> None:
        with self.lock:
            self.coach[team].append((time.monotonic(), msg.MatchMode, msg.MatchType))

    def _on_states(self, msg) -> None:
        with self.lock:
            for name, pose in zip(msg.name, msg.pose):
                self.states[name] = (pose.position.x, pose.position.y, pose.position.z)

    def _on_game(self, msg) -> None:
        self.game = msg

    def mode(self, team: str) -> int | None:
        with self.lock:
            return self.coach[team][-1][1] if self.coach[team] else None

    def modes_since(self, team: str, since: float) -> list[int]:
        with self.lock:
            return [mode for wall, mode, _ in self.coach[team] if wall >= since]

    def ball(self) -> tuple[float, float, float]:
        with self.lock:
            return self.states["football"]

    @staticmethod
    def wait_for(predicate, timeout: float = 20.0, what: str = "condition"):
        return wait_until(predicate, timeout, what, 0.02)

    @staticmethod
    def service(name: str, srv_type):
        import rospy

        rospy.wait_for_service(name, timeout=20.0)
        return rospy.ServiceProxy(name, srv_type)

    @staticmethod
    def set_model(name: str, x: float, y: float, *, z: float = 0.0, yaw: float = 0.0) -> None:
        from nubot_common.node_io import set_model_state

        set_model_state(name, x, y, z, yaw)

    def command(self, command: str, team: str = "nubot"):
        from nubot_common.srv import CoachCommand

        return self.service("/referee/command", CoachCommand)(command=command, team=team)


@pytest.fixture(scope="module")
def make_watcher():
    """The ``MatchWatcher`` class, for modules that start their own nodes."""
    return MatchWatcher


def launch_match_world(ros_master, *referee_args: str):
    """nubot1 at (-2, 0) and rival1 at (4, -3) in the simulator, and the automatic referee launched with
    ``referee_args``; returns (watcher, sim process, referee process) once the first kickoff is given."""
    from geometry_msgs.msg import Pose

    from nubot_common.srv import SpawnModel

    sim = ros_master.launch("coach4sim_sim", ["roslaunch", "sim_visual", "single_robot.launch", "demo:=false"])
    referee = None
    watcher = MatchWatcher()
    try:
        watcher.wait_for(lambda: "nubot1" in watcher.states, timeout=60, what="the simulator's model states")
        pose = Pose()
        pose.position.x, pose.position.y = 4.0, -3.0
        pose.orientation.z, pose.orientation.w = 1.0, 0.0  # facing -x
        assert watcher.service("/sim_visual/spawn_model", SpawnModel)("rival1", pose, -1).success
        referee = ros_master.launch("coach4sim_referee", ["roslaunch", "coach4sim", "referee.launch", *referee_args])
        watcher.wait_for(lambda: watcher.game is not None and watcher.game.half == 1, timeout=30,
                         what="the referee's first kickoff")
        watcher.wait_for(lambda: watcher.mode("nubot") is not None and watcher.mode("rival") is not None,
                         timeout=10, what="CoachInfo for both teams")
    except AssertionError:
        logs = "\n".join(p.log_text()[-3000:] for p in (sim, referee) if p is not None)
        stop_match_world(watcher, sim, referee)
        raise AssertionError(f"the match world did not start:\n{logs}") from None
    return watcher, sim, referee


def stop_match_world(watcher, sim, referee) -> None:
    watcher.close()
    for process in (referee, sim):
        if process is not None:
            process.stop()
    time.sleep(0.5)  # let the master forget the stopped nodes before another module launches its own


@pytest.fixture(scope="module")
def match_world(ros_master):
    """The match world with the referee's default rules; yields (watcher, sim process, referee process)."""
    world = launch_match_world(ros_master)
    yield world
    stop_match_world(*world)


@pytest.fixture(scope="module")
def world_launcher():
    """(launch_match_world, stop_match_world), for modules that need the referee with other rules."""
    return launch_match_world, stop_match_world
