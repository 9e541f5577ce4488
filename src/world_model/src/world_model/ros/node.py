"""The world model's ROS adapter: ``WorldModelNode`` feeds a ``WorldModel`` from its topics and publishes what it
decides. The ``world_model`` node runs one on its own timer; the ``robot`` node (nubot_control) runs one in the
same process as the robot's control, which calls ``cycle`` and ``on_own_strategy`` itself. This module imports
rospy; the model it adapts does not."""

from __future__ import annotations

import threading
from collections.abc import Mapping
from dataclasses import dataclass, fields
from typing import Any

import rospy

from nubot_common import NubotCommonError
from nubot_common import conversions as conv
from nubot_common.msg import (
    BallFlightInfo,
    BallInfo3d,
    CoachInfo,
    FrontBallInfo,
    OmniVisionInfo,
    StrategyInfo,
    TargetInfo,
    TeamMessage,
    TeamMessages,
    WorldModelInfo,
    simulation_strategy,
)
from nubot_common.naming import RobotNodeParams
from nubot_common.node_io import publisher, timer
from nubot_common.params import from_mapping, require_positive
from nubot_common.percepts import RobotView
from nubot_common.rejections import RefusalLog
from nubot_common.team_play import StrategyReport
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from nubot_common.world_state import WorldState
from world_model import WorldModelError
from world_model.params import WorldModelParams
from world_model.world_model import WorldModel

REFUSAL_REPORT_INTERVAL = 5.0  # [s, wall] between two log lines about one kind of refused input


@dataclass(frozen=True)
class WorldModelNodeParams(RobotNodeParams):
    """The node's own parameters; the rest of ~ is ``WorldModelParams``."""

    rate: float = 30.0  # WorldModelInfo and TeamMessage [Hz, sim time]

    def __post_init__(self) -> None:
        super().__post_init__()
        require_positive(self, "rate")


class WorldModelNode:
    """``private``: the parameters (``WorldModelNodeParams`` and ``WorldModelParams``), named ``where`` in errors.
    ``standalone``: a node of its own, which takes its robot's strategy from nubot_control's topics and publishes
    on its own timer at ~rate; else its host calls ``on_own_strategy`` and ``cycle`` (~rate unused). A bad
    parameter raises ``NubotCommonError`` or ``ValueError``."""

    def __init__(self, private: Mapping[str, Any], where: str = "~", standalone: bool = True) -> None:
        private = dict(private)
        own = {f.name: private.pop(f.name) for f in fields(WorldModelNodeParams) if f.name in private}
        node = from_mapping(WorldModelNodeParams, own, where)
        world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))
        self.model = WorldModel(from_mapping(WorldModelParams, private, where), node.agent, world)
        self.rate = node.rate
        self.robot, team = node.robot, node.name.team
        self.lock = threading.Lock()
        self.refusals = RefusalLog(f"world_model: {self.robot}", rospy.logwarn, REFUSAL_REPORT_INTERVAL)
        self.target = (0.0, 0.0)
        self.valid: set[int] = set()  # the teammates valid at the last snapshot
        self.flight_shown = False  # the last BallFlightInfo published had a 3-D ball
        self.info_pub = publisher(f"/{self.robot}/worldmodel/worldmodelinfo", WorldModelInfo)
        self.team_pub = publisher(f"/{self.robot}/worldmodel/teammessage", TeamMessage)
        self.flight_pub = publisher(f"/{self.robot}/worldmodel/ballflight", BallFlightInfo)
        rospy.Subscriber(f"/{self.robot}/omnivision/OmniVisionInfo", OmniVisionInfo, self.on_vision, queue_size=1)
        rospy.Subscriber(f"/{self.robot}/front_vision/FrontBallInfo", FrontBallInfo, self.on_front_ball,
                         queue_size=1)
        rospy.Subscriber(f"/{self.robot}/kinect/ballinfo", BallInfo3d, self.on_ball3d, queue_size=1)
        rospy.Subscriber(f"/{team}/simulation_interface/teammates", TeamMessages, self.on_teammates, queue_size=1)
        rospy.Subscriber(f"/{team}/simulation_interface/strategy", simulation_strategy, self.on_team, queue_size=1)
        rospy.Subscriber(f"/{team}/receive_from_coach", CoachInfo, self.on_coach, queue_size=10)
        self.timer = None
        if standalone:
            rospy.Subscriber(f"/{self.robot}/nubotcontrol/strategy", StrategyInfo, self.on_strategy, queue_size=1)
            rospy.Subscriber(f"/{self.robot}/nubotcontrol/targetinfo", TargetInfo, self.on_target, queue_size=1)
            self.timer = timer(1.0 / node.rate, self.on_timer)
        rospy.loginfo("world_model: %s (agent %d, %d robots, field %s)%s", self.robot, self.model.agent_id,
                      self.model.params.team_size, world.name, f" at {node.rate:.0f} Hz" if standalone else "")

    def _apply(self, what: str, call, *args) -> None:  # noqa: ANN001
        try:
            with self.lock:
                call(*args)
        except (WorldModelError, NubotCommonError) as exc:
            self._refused(f"{what} ignored", str(exc))

    def _refused(self, kind: str, detail: str) -> None:
        """Log a refused input: the first, then a line every few seconds with the count and the latest reason."""
        self.refusals.refused(kind, detail)

    def on_vision(self, msg: OmniVisionInfo) -> None:
        self._apply("vision frame", lambda: self.model.on_vision(conv.robot_view(msg, rospy.get_time())))

    def on_front_ball(self, msg: FrontBallInfo) -> None:
        now = rospy.get_time()
        ball = conv.front_ball(msg, now)
        self._apply("front camera ball", self.model.on_front_ball, ball.stamp if ball else now,
                    ball.position if ball else None)

    def on_ball3d(self, msg: BallInfo3d) -> None:
        self._apply("3-D ball", self.model.on_ball3d, conv.ball3d_percept(msg, rospy.get_time()))

    def on_teammates(self, msg: TeamMessages) -> None:
        for view in conv.team_views(msg):
            self._apply("teammate packet", self.model.on_teammate, rospy.get_time(), view)

    def on_team(self, msg: simulation_strategy) -> None:
        for strategy in msg.strategy_msgs:
            self._apply("teammate strategy", self.model.on_teammate_strategy, rospy.get_time(),
                        conv.strategy_report(strategy))

    def on_target(self, msg: TargetInfo) -> None:
        self.target = conv.target_of(msg) or self.target

    def on_strategy(self, msg: StrategyInfo) -> None:
        self.on_own_strategy(rospy.get_time(), conv.strategy_report(msg, self.target))

    def on_own_strategy(self, now: float, report: StrategyReport) -> None:
        """The robot's own strategy decision (role, action, target) at ``now``."""
        self._apply("own strategy", self.model.on_strategy, now, report)

    def on_coach(self, msg: CoachInfo) -> None:
        try:
            with self.lock:
                before = self.model.game.command
                game = self.model.on_coach(rospy.get_time(), *conv.coach_fields(msg))
        except WorldModelError as exc:
            # The coach resends every 30 ms, and a peer may send any: counted, a line every few seconds.
            self._refused("coach command refused", f"{exc}; keeping {self.model.game.mode.name}")
            return
        if game.command != before:
            rospy.loginfo("world_model: %s: game command %s (previous %s)", self.robot, game.mode.name,
                          game.previous.name)

    def on_timer(self, _event: object) -> None:
        self.cycle(rospy.get_time())

    def cycle(self, now: float) -> WorldState:
        """Decide the world at ``now``, publish it (WorldModelInfo, BallFlightInfo, TeamMessage) and return it."""
        with self.lock:
            state = self.model.snapshot(now)
            view = self.model.own_view(now)
        self.publish(now, state, view)
        return state

    def publish(self, now: float, state: WorldState, view: RobotView | None) -> None:
        """Send the world decided at ``now`` and what the robot shares with its team (``view``, None: nothing)."""
        valid = {r.agent_id for r in state.teammates if r.valid}
        for gone in sorted(self.valid - valid):
            rospy.logwarn("world_model: %s: teammate %d is no longer valid (silent, lost or not playing); "
                          "the others take over its role", self.robot, gone)
        self.valid = valid
        self.refusals.flush()  # a flood's tail
        self.info_pub.publish(conv.world_model_info_msg(state))
        if state.flight is not None or self.flight_shown:  # a robot without RGB-D cameras sends none
            self.flight_pub.publish(conv.ball_flight_msg(state.flight, state.stamp))
            self.flight_shown = state.flight is not None
        if view is not None:
            self.team_pub.publish(conv.team_message_msg(view, now))
