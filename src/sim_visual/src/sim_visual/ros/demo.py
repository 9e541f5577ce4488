"""The single-robot demo's ROS side: the robot's percepts into DemoBehaviour (sim_visual.demo) and its
commands out through the robot interface. It only adapts."""

from __future__ import annotations

from dataclasses import replace

import rospy
from std_msgs.msg import String

from nubot_common import NubotCommonError
from nubot_common import conversions as conv
from nubot_common.msg import OmniVisionInfo, VelCmd
from nubot_common.node_io import publisher, timer
from nubot_common.params import from_mapping
from nubot_common.srv import BallHandle, Shoot
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from sim_visual.demo import DemoBehaviour, DemoParams


class SingleRobotDemo:
    def __init__(self) -> None:
        private = rospy.get_param("~", {})
        self.robot = private.pop("robot", "nubot1")
        rate = float(private.pop("rate", 33.0))
        try:
            field = world_from_params(rospy.get_param(WORLD_NAMESPACE, None)).field
            self.behaviour = DemoBehaviour(from_mapping(DemoParams, private, "~"), field)
        except NubotCommonError as exc:
            rospy.logfatal("single_robot_demo: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.frame: OmniVisionInfo | None = None
        self.cmd_pub = publisher(f"/{self.robot}/nubotcontrol/velcmd", VelCmd)
        self.state_pub = publisher(f"/{self.robot}/demo/state", String, latch=True)
        self.rate = rate
        self.holding, self.holding_time = False, -1.0

    def start(self) -> None:
        """Wait for the robot's services (outside the node's set-up: Ctrl-C ends the wait), then drive at ~rate."""
        for service in ("BallHandle", "Shoot"):
            rospy.wait_for_service(f"/{self.robot}/{service}")
        self.ball_handle = rospy.ServiceProxy(f"/{self.robot}/BallHandle", BallHandle, persistent=True)
        self.shoot = rospy.ServiceProxy(f"/{self.robot}/Shoot", Shoot, persistent=True)
        rospy.Subscriber(f"/{self.robot}/omnivision/OmniVisionInfo", OmniVisionInfo, self.on_vision, queue_size=1)
        self.state_pub.publish(String(self.behaviour.state.value))
        rospy.loginfo("single_robot_demo: driving %s, state %s", self.robot, self.behaviour.state.value)
        self.timer = timer(1.0 / self.rate, self.on_timer)

    def on_vision(self, msg: OmniVisionInfo) -> None:
        self.frame = msg

    def on_timer(self, _event: rospy.timer.TimerEvent) -> None:
        frame = self.frame
        if frame is None or not frame.robotinfo:
            return
        now = rospy.get_time()
        view = conv.robot_view(frame, now)
        # A BallHandle answer is newer than any vision frame taken before it.
        holding = view.robot.holding if view.stamp > self.holding_time else self.holding
        command, transitions = self.behaviour.step(replace(view, stamp=now, robot=replace(view.robot, holding=holding)))
        for before, after in transitions:
            rospy.loginfo("single_robot_demo: %s -> %s", before.value, after.value)
            self.state_pub.publish(String(after.value))
        self.cmd_pub.publish(conv.velcmd_msg(command.velocity))
        try:
            if command.ball_handle is not None:
                self.holding = bool(self.ball_handle(command.ball_handle).BallIsHolding)
                self.holding_time = rospy.get_time()
            if command.kick is not None:
                done = self.shoot(command.kick.strength, int(command.kick.kind)).ShootIsDone
                rospy.loginfo("single_robot_demo: %s kick, ShootIsDone=%d", command.kick.kind.name, done)
                self.holding, self.holding_time = False, rospy.get_time()
                if not done:
                    self.behaviour.kick_failed()
                    self.state_pub.publish(String(self.behaviour.state.value))
        except rospy.ServiceException as exc:
            rospy.logwarn("single_robot_demo: service call failed: %s", exc)
