"""The viewer node's ROS side for a live match: ``LiveBackend`` gives the page's server (``coach4sim.viewer_server``)
the match as the topics tell it (through ``Scene``) and sends its commands through the referee, or straight to the
teams while no referee runs."""

from __future__ import annotations

import json
import threading
from typing import Any

import rospy

from coach4sim import CoachError
from coach4sim.console import COMMAND_SERVICE
from coach4sim.ros.sender import CommandSender
from coach4sim.scene import Scene, field_layout
from nubot_common.match_mode import MatchMode
from nubot_common.msg import GameState, ModelStates, PlannedPath, TeamMessages, WorldModelInfo
from nubot_common.naming import is_robot_name, parse_robot_name
from nubot_common.world_description import WorldDescription


def referee_running() -> bool:
    try:
        rospy.wait_for_service(COMMAND_SERVICE, timeout=0.05)
    except rospy.ROSException:
        return False
    return True


class LiveBackend:
    """The match as the topics tell it; commands through the referee."""

    def __init__(self, world: WorldDescription, sim_namespace: str):
        self.scene = Scene(world)
        self.world = world
        self.lock = threading.Lock()
        self.senders: dict[str, CommandSender] = {}
        self.watched: dict[str, rospy.Subscriber] = {}
        self.known: set[str] = set()
        rospy.Subscriber(f"{sim_namespace}/model_states", ModelStates, self._on_states, queue_size=1)
        rospy.Subscriber("/referee/state", GameState, self._locked(self.scene.on_referee), queue_size=10)

    def _locked(self, handler):
        def call(*args: Any) -> None:
            with self.lock:
                handler(*args)
        return call

    def _on_states(self, msg: ModelStates) -> None:
        with self.lock:
            self.scene.on_model_states(msg)
        for name in msg.name:
            if name not in self.known and is_robot_name(name):
                self._subscribe_robot(name)

    def _subscribe_robot(self, name: str) -> None:
        self.known.add(name)
        team = parse_robot_name(name).team
        if team not in self.known:
            self.known.add(team)
            rospy.Subscriber(f"/{team}/simulation_interface/teammates", TeamMessages,
                             self._locked(lambda m, t=team: self.scene.on_teammates(t, m)), queue_size=1)
        rospy.Subscriber(f"/{name}/nubotcontrol/path", PlannedPath,
                         self._locked(lambda m, r=name: self.scene.on_path(r, m)), queue_size=1)

    def hello(self) -> dict[str, Any]:
        with self.lock:
            teams = self.scene.teams
        return {"mode": "live", "title": self.world.name, "field": field_layout(self.world), "teams": teams}

    def frame(self, watch: str) -> str | None:
        if watch and watch not in self.watched and is_robot_name(watch) and watch in self.known:
            self.watched[watch] = rospy.Subscriber(f"/{watch}/worldmodel/worldmodelinfo", WorldModelInfo,
                                                   self._locked(lambda m, r=watch: self.scene.on_world_model(r, m)),
                                                   queue_size=1)
        with self.lock:
            return json.dumps(self.scene.frame(watch), separators=(",", ":"))

    def command(self, command: MatchMode, team: str) -> tuple[bool, str]:
        with self.lock:
            teams = self.scene.teams
        team = team or (teams[0] if teams else "nubot")
        if teams and team not in teams:
            return False, f"unknown team {team!r}: the match has {', '.join(teams)}"
        sender = self.senders.get(team)
        if sender is None or (not sender.via_referee and referee_running()):  # the referee may start later
            sender = self.senders[team] = CommandSender(team, period=0.03)
        accepted, text = sender.send(command)
        if accepted and not sender.via_referee:
            sender.publish_once()
        return accepted, text

    def control(self, message: dict[str, Any]) -> None:
        raise CoachError("a live match cannot be paused or wound: replay a bag for that")
