"""The coach's way of sending a game command, shared by the nodes that send them (``coach``, ``viewer``,
``refbox_client``): through the referee's ``/referee/command`` when it runs, else publishing ``CoachInfo`` to
``/<team>/receive_from_coach`` itself. A ROS adapter (rospy), not a core: no decision lives here.
"""

from __future__ import annotations

import math
import threading
import time

import rospy

from coach4sim.console import COMMAND_SERVICE, coach_topic
from nubot_common import conversions as shared
from nubot_common.match_mode import MatchMode
from nubot_common.msg import CoachInfo
from nubot_common.node_io import publisher
from nubot_common.srv import CoachCommand

SERVICE_WAIT = 1.0  # [s, wall]
PREVIOUS_WAIT = 0.3  # listen this long for the command in force before publishing our own [s, wall]


class CommandSender:
    """Through the referee when it runs; else publishing CoachInfo to the team's topic every ``period``."""

    def __init__(self, team: str, period: float):
        self.team, self.period = team, period
        self.proxy = None
        self.pub = None
        self.mode = self.previous = MatchMode.STOPROBOT
        self.publishing = False
        self.lock = threading.Lock()
        try:
            rospy.wait_for_service(COMMAND_SERVICE, timeout=SERVICE_WAIT)
            self.proxy = rospy.ServiceProxy(COMMAND_SERVICE, CoachCommand)
        except rospy.ROSException:
            self.pub = publisher(coach_topic(team), CoachInfo)
            try:
                heard = rospy.wait_for_message(coach_topic(team), CoachInfo, timeout=PREVIOUS_WAIT)
                self.mode = MatchMode(heard.MatchMode)
            except (rospy.ROSException, ValueError):
                pass

    @property
    def via_referee(self) -> bool:
        return self.proxy is not None

    def send(self, mode: MatchMode) -> tuple[bool, str]:
        """Send ``mode``; return whether it is in force and what happened."""
        if self.proxy is not None:
            try:
                response = self.proxy(command=mode.name, team=self.team)
            except rospy.ServiceException as exc:
                return False, f"the referee did not answer: {exc}"
            return response.accepted, f"referee: {response.message}"
        with self.lock:
            if mode != self.mode:
                self.previous, self.mode = self.mode, mode
        return True, f"{mode.name} ({mode.value}) to {coach_topic(self.team)}"

    def publish_once(self) -> None:
        """Publish the command in force once (only without a referee: the referee publishes it then)."""
        if self.pub is None:
            raise RuntimeError("the referee publishes the team's commands: nothing to publish here")
        with self.lock:
            msg = shared.coach_info_msg(self.mode, self.previous, rospy.get_time())
        self.pub.publish(msg)

    def publish_for(self, duration: float | None) -> None:
        """Publish the command in force every ``period`` for ``duration`` [s] (None: until shutdown)."""
        end = math.inf if duration is None else time.monotonic() + duration
        next_time = time.monotonic()
        while not rospy.is_shutdown() and time.monotonic() < end:
            self.publish_once()
            next_time += self.period
            time.sleep(max(0.0, min(next_time, end) - time.monotonic()))  # the duration ends the run, not a period
