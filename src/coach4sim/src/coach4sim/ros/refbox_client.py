"""The RefBox client node's ROS side: ``RefboxLink`` (``coach4sim.refbox_link``) to the box, its game commands to
our team(s) through the referee when it runs, else as CoachInfo, and the team's picture for the box's worldstate."""

from __future__ import annotations

import json
import queue
import threading
import time

import rosgraph
import rospy
from std_msgs.msg import String

from coach4sim.console import COMMAND_SERVICE, coach_topic, worldmodel_topic
from coach4sim.refbox import CommandEffect, RefboxClientParams, team_book
from coach4sim.refbox_link import RefboxLink, TeamPicture
from nubot_common import conversions as shared
from nubot_common.match_mode import MatchMode
from nubot_common.msg import CoachInfo, StrategyInfo, WorldModelInfo
from nubot_common.node_io import publisher
from nubot_common.rejections import RefusalLog
from nubot_common.srv import CoachCommand


class GameCommander:
    """Gives our team(s) a game command: through the referee when it runs, else publishing CoachInfo itself."""

    def __init__(self, params: RefboxClientParams):
        self.params = params
        self.lock = threading.Lock()
        # our team(s) as the referee would hold them: each command to ours, its mirror to the other when ours too
        self.book = team_book(params.teams)
        self.pubs: dict[str, rospy.Publisher] = {}
        self.via_referee = False
        self.master = rosgraph.Master(rospy.get_name())
        self.refresh()

    def referee_running(self) -> bool:
        try:
            self.master.lookupService(COMMAND_SERVICE)
            return True
        except (rosgraph.MasterError, OSError):
            return False

    def refresh(self) -> None:
        """Follow the referee: publish CoachInfo only while it does not (each topic keeps one producer)."""
        running = self.referee_running()
        with self.lock:
            if running and (self.pubs or not self.via_referee):
                for pub in self.pubs.values():
                    pub.unregister()
                self.pubs = {}
                rospy.loginfo("refbox_client: the referee runs; commands go through %s", COMMAND_SERVICE)
            elif not running and not self.pubs:
                self.pubs = {team: publisher(coach_topic(team), CoachInfo) for team in self.params.teams}
                rospy.loginfo("refbox_client: no referee; publishing CoachInfo to %s every %.0f ms",
                              ", ".join(coach_topic(t) for t in self.params.teams), self.params.coach_period * 1000)
            self.via_referee = running

    def send(self, mode: MatchMode) -> str:
        """Put ``mode`` in force for our team (its mirror for the other team); return what happened in words."""
        p = self.params
        with self.lock:
            self.book.command(p.team, mode)
            via_referee = self.via_referee
        if not via_referee:
            self.publish()
            return "published to " + ", ".join(f"{t} {m.name}" for t, m in self.in_force().items())
        try:
            response = rospy.ServiceProxy(COMMAND_SERVICE, CoachCommand)(command=mode.name, team=p.team)
        except (rospy.ServiceException, rospy.ROSException) as exc:
            return f"the referee did not answer: {exc}"
        return f"referee {'accepted' if response.accepted else 'refused'}: {response.message}"

    def in_force(self) -> dict[str, MatchMode]:
        with self.lock:
            return {t.spec.prefix: t.mode for t in self.book.teams}

    def publish(self) -> None:
        with self.lock:  # one thread at a time writes to the topics' connections
            now = rospy.get_time()
            for team, pub in self.pubs.items():
                status = self.book.status(team)
                pub.publish(shared.coach_info_msg(status.mode, status.previous, now))


class RefboxClientNode:
    def __init__(self, params: RefboxClientParams):
        self.params = p = params
        self.lock = threading.Lock()
        self.counts = {"applied": 0, "no_game_command": 0}
        self.last_command, self.last_effect = "", ""
        self.commands: queue.Queue[CommandEffect | None] = queue.Queue()
        self.refusals = RefusalLog("refbox_client", rospy.logwarn)
        self.status_lock = threading.Lock()
        self.status_pub = publisher("~status", String)
        self.commander = GameCommander(p)
        self.picture = TeamPicture(p)
        for agent in range(1, p.team_size + 1):
            robot = f"{p.team}{agent}"
            rospy.Subscriber(worldmodel_topic(robot), WorldModelInfo, self.on_model, callback_args=agent, queue_size=1)
            rospy.Subscriber(f"/{robot}/nubotcontrol/strategy", StrategyInfo, self.on_strategy, callback_args=agent,
                             queue_size=1)
        self.link = RefboxLink(p, self.worldstate, self.commands.put, self.log, self.publish_status)
        rospy.on_shutdown(self.shutdown)
        rospy.loginfo("refbox_client: team %s (%s) as the box knows it: address %r, name %r; the RefBox at %s:%d; "
                      "worldstate at %.0f Hz", p.team, ", ".join(p.teams), p.team_address, p.team_name, p.host, p.port,
                      p.worldstate_rate)

    def on_model(self, msg: WorldModelInfo, agent: int) -> None:
        self.picture.on_model(agent, msg, time.monotonic())

    def on_strategy(self, msg: StrategyInfo, agent: int) -> None:
        self.picture.on_strategy(agent, msg, time.monotonic())

    def worldstate(self) -> dict:
        return self.picture.worldstate(self.commander.in_force()[self.params.team].name, time.monotonic())

    @staticmethod
    def log(level: str, line: str) -> None:
        (rospy.logwarn if level == "warn" else rospy.loginfo)("refbox_client: %s", line)

    def shutdown(self) -> None:
        self.link.shutdown()
        self.commands.put(None)

    def run_commands(self) -> None:
        """Apply the box's commands in order (the referee's service may take a moment; the link must not wait)."""
        while True:
            effect = self.commands.get()
            if effect is None:
                return
            if effect.mode is None:
                if effect.known:
                    rospy.loginfo("refbox_client: %s", effect.text)
                else:  # a box (or a peer) sending unknown commands: a line every few seconds with the count
                    self.refusals.refused("unknown command", effect.text)
                result = "nothing sent"
            else:
                result = self.commander.send(effect.mode)
                rospy.loginfo("refbox_client: %s; %s", effect.text, result)
            with self.lock:
                self.counts["applied"] += 1
                self.counts["no_game_command"] += effect.mode is None
                self.last_command, self.last_effect = str(effect.command), f"{effect.text}; {result}"
            self.publish_status()

    def run_publishing(self) -> None:
        """CoachInfo every ~coach_period while no referee does it; the referee looked for; the status."""
        p = self.params
        next_check = next_status = time.monotonic()
        while not self.link.stop.wait(p.coach_period):
            now = time.monotonic()
            if now >= next_check:
                self.commander.refresh()
                next_check = now + p.referee_check_period
            self.commander.publish()
            if now >= next_status:
                self.publish_status()
                next_status = now + p.status_period

    def publish_status(self) -> None:
        status = self.link.status()
        with self.lock:
            status.update(self.counts, last_command=self.last_command, last_effect=self.last_effect)
        status["via"] = "referee" if self.commander.via_referee else "topic"
        status["modes"] = {team: mode.name for team, mode in self.commander.in_force().items()}
        with self.status_lock:
            self.status_pub.publish(String(json.dumps(status, sort_keys=True)))

    def run(self) -> None:
        threads = [threading.Thread(target=target, name=name, daemon=True) for target, name in (
            (self.link.run, "refbox-link"), (self.run_commands, "refbox-commands"),
            (self.run_publishing, "refbox-publishing"))]
        for thread in threads:
            thread.start()
        rospy.spin()
        self.shutdown()
        for thread in threads:
            thread.join(timeout=3.0)
