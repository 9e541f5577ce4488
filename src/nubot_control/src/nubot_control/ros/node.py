"""nubot_control's ROS adapter: ``ControlNode`` runs a ``Controller`` on the world it is given and sends what it
decides through the robot interface. The ``nubot_control`` node gives it the world from the world_model node's
topics; the ``robot`` node gives it the world of a ``WorldModelNode`` in the same process. This module imports
rospy; the controller it adapts does not."""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass, fields, replace
from typing import Any

import rospy

from nubot_common import NubotCommonError
from nubot_common import conversions as conv
from nubot_common.commands import RobotCommand
from nubot_common.msg import BallFlightInfo, PlannedPath, StrategyInfo, TargetInfo, VelCmd, WorldModelInfo
from nubot_common.naming import RobotNodeParams
from nubot_common.node_io import publisher, timer
from nubot_common.params import from_mapping, require_positive
from nubot_common.srv import BallHandle, Shoot
from nubot_common.team_play import StrategyReport
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from nubot_common.world_state import CoachCommand, WorldState
from nubot_control.agent import Controller, ControlStep
from nubot_control.motion import MotionController
from nubot_control.params import ControlParams
from nubot_control.planned_path import planned_path


@dataclass(frozen=True)
class ControlNodeParams(RobotNodeParams):
    """The node's own parameters; the rest of ~ is ``ControlParams``."""

    target_period: float = 0.1  # TargetInfo at most this often [s, sim time]
    flight_timeout: float = 0.3  # a BallFlightInfo this far from the WorldModelInfo's stamp is not used (the
    # world model's ball_timeout) [s, sim time]

    def __post_init__(self) -> None:
        super().__post_init__()
        require_positive(self, "target_period")
        require_positive(self, "flight_timeout")


class ControlNode:
    """``private``: the parameters (``ControlNodeParams`` and ``ControlParams``). ``standalone``: a node of its
    own, which decodes the world model's topics and runs ``cycle`` on its own timer at ControlParams.rate; else
    its host calls ``cycle`` with the world. A bad parameter raises ``NubotCommonError`` or ``ValueError``."""

    def __init__(self, private: Mapping[str, Any], standalone: bool = True) -> None:
        private = dict(private)
        own = {f.name: private.pop(f.name) for f in fields(ControlNodeParams) if f.name in private}
        node = from_mapping(ControlNodeParams, own, "~")
        params = from_mapping(ControlParams, private, "~")
        if not 1 <= node.agent <= params.play.team_size:
            raise NubotCommonError(f"~agent_id (default: the one in ~robot) must lie in "
                                   f"1..{params.play.team_size} (~play/team_size), got {node.agent}")
        world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))
        self.controller = Controller(params, world, node.agent)  # loads ~strategy, a strategy of the user's own
        self.robot, self.agent_id, self.target_period = node.robot, node.agent, node.target_period
        self.flight_timeout = node.flight_timeout
        self.team = node.name.team
        self.world: WorldModelInfo | None = None
        self.decoded: tuple[WorldModelInfo, WorldState] | None = None  # the latest message and its WorldState
        self.flight: BallFlightInfo | None = None  # the latest
        self.mode: CoachCommand | None = None  # the last game command acted on
        self.target_sent = -1.0  # sim time of the last TargetInfo [s]
        self.stale = False
        self.path_shown = False  # the last path published has points
        self.cmd_pub = publisher(f"/{self.robot}/nubotcontrol/velcmd", VelCmd)
        self.strategy_pub = publisher(f"/{self.robot}/nubotcontrol/strategy", StrategyInfo)
        self.target_pub = publisher(f"/{self.robot}/nubotcontrol/targetinfo", TargetInfo)
        self.path_pub = publisher(f"/{self.robot}/nubotcontrol/path", PlannedPath)
        self.ball_handle = rospy.ServiceProxy(f"/{self.robot}/BallHandle", BallHandle, persistent=True)
        self.shoot = rospy.ServiceProxy(f"/{self.robot}/Shoot", Shoot, persistent=True)
        self.timer = None
        if standalone:
            rospy.Subscriber(f"/{self.robot}/worldmodel/worldmodelinfo", WorldModelInfo,
                             lambda msg: setattr(self, "world", msg), queue_size=1)
            rospy.Subscriber(f"/{self.robot}/worldmodel/ballflight", BallFlightInfo,
                             lambda msg: setattr(self, "flight", msg), queue_size=1)
            self.timer = timer(1.0 / params.rate, self.on_timer)
        rospy.loginfo("nubot_control: %s (agent %d, field %s) at %.0f Hz", self.robot, self.agent_id, world.name,
                      params.rate)

    def on_timer(self, _event: object) -> None:
        msg = self.world
        if msg is None:
            return
        if self.decoded is None or self.decoded[0] is not msg:
            try:
                self.decoded = (msg, conv.world_state(msg, self.agent_id))
            except NubotCommonError as exc:
                rospy.logwarn_throttle(5.0, f"nubot_control: {self.robot}: world model ignored: {exc}")
                return
        self.cycle(rospy.get_time(), self.with_flight(self.decoded[1], self.flight))

    def cycle(self, now: float, world: WorldState) -> StrategyReport | None:
        """One control cycle at ``now`` on ``world``: decide, send; the strategy report (None while stale)."""
        return self.act(now, world, self.controller.step(now, world))

    def act(self, now: float, world: WorldState, step: ControlStep) -> StrategyReport | None:
        """Send the control stage's decision ``step`` on ``world`` at ``now``: the velocity, the path and target
        now and then, the ball handler's and kicker's requests, the strategy; its report (None while stale)."""
        if world.game.command != self.mode:
            self.mode = world.game.command
            rospy.loginfo("nubot_control: %s game command %s (previous %s)", self.robot, world.game.mode.name,
                          world.game.previous.name)
        self.cmd_pub.publish(conv.velcmd_msg(step.command.velocity))
        if step.stale != self.stale:
            self.stale = step.stale
            if step.stale:
                rospy.logerr("nubot_control: %s: world model stale (last one %.1f s old, limit %.1f s): standing "
                             "still and out of play", self.robot, now - world.stamp,
                             self.controller.params.world_model_timeout)
            else:
                rospy.logwarn("nubot_control: %s: world model back; playing again", self.robot)
        due = not 0.0 <= now - self.target_sent < self.target_period  # wanted now and then, not at 33 Hz
        if due or step.output is None:
            self.publish_path(now, step.output is not None)
        if step.stale:
            return None
        self.call_services(step.command)
        self.strategy_pub.publish(conv.strategy_info_msg(step.report))
        if due:
            self.target_pub.publish(conv.target_info_msg(step.report))
            self.target_sent = now
        return step.report

    def with_flight(self, world: WorldState, flight: BallFlightInfo | None) -> WorldState:
        """``world`` with the world model's flight of the same moment (within ~flight_timeout), else none."""
        if flight is None or abs(conv.seconds(flight.header.stamp) - world.stamp) > self.flight_timeout:
            return world
        return replace(world, flight=conv.ball_flight(flight))

    def publish_path(self, now: float, playing: bool) -> None:
        """The motion layer's path while the robot follows one; an empty path once when it has none."""
        motion = getattr(self.controller.strategy, "motion", None)  # a strategy of the user's own may have none
        points = planned_path(motion) if playing and isinstance(motion, MotionController) else []
        if points or self.path_shown:
            self.path_pub.publish(conv.planned_path_msg(points, now, self.team))
            self.path_shown = bool(points)

    def call_services(self, command: RobotCommand) -> None:
        try:
            if command.ball_handle is not None:
                self.ball_handle(command.ball_handle)
            if command.kick is not None:
                done = self.shoot(command.kick.strength, int(command.kick.kind)).ShootIsDone
                rospy.loginfo("nubot_control: %s %s at %d m/s, ShootIsDone=%d", self.robot, command.kick.kind.name,
                              command.kick.strength, done)
        except rospy.ServiceException as exc:
            rospy.logwarn_throttle(5.0, f"nubot_control: {self.robot}: service call failed: {exc}")
