"""The keyboard teleop's ROS side: keys read from a terminal into KeyTeleop (sim_visual.teleop), its velocity
commands and its BallHandle and Shoot calls to one robot. It only adapts."""

from __future__ import annotations

import codecs
import os
import select
import time

import rospy

from nubot_common import NubotCommonError
from nubot_common.commands import RobotCommand
from nubot_common.msg import VelCmd
from nubot_common.node_io import publisher
from nubot_common.params import from_mapping
from nubot_common.srv import BallHandle, Shoot
from sim_visual.teleop import KEYS, KeyTeleop, TeleopParams

NO_TTY_STATUS = 2


class KeyboardTeleop:
    def __init__(self) -> None:
        private = rospy.get_param("~", {})
        self.robot = private.pop("robot", "nubot1")
        self.rate = float(private.pop("rate", 20.0))
        if not self.rate > 0.0:
            rospy.logfatal("teleop_keyboard: ~rate must be positive, got %s", self.rate)
            raise SystemExit(2)
        try:
            self.teleop = KeyTeleop(from_mapping(TeleopParams, private, "~"))
        except NubotCommonError as exc:
            rospy.logfatal("teleop_keyboard: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.cmd_pub = publisher(f"/{self.robot}/nubotcontrol/velcmd", VelCmd)
        self.ball_handle = rospy.ServiceProxy(f"/{self.robot}/BallHandle", BallHandle)
        self.shoot = rospy.ServiceProxy(f"/{self.robot}/Shoot", Shoot)
        # Runs before rospy closes its topics, so a Ctrl-C or rosnode kill still stops the robot.
        rospy.on_shutdown(self.stop_robot)

    def stop_robot(self) -> None:
        self.teleop.stop()
        self.publish_command()
        time.sleep(0.1)  # wall time: let the queued zero command leave before the topic closes

    def publish_command(self) -> None:
        t = self.teleop
        self.cmd_pub.publish(VelCmd(Vx=t.vx, Vy=t.vy, w=t.w))

    def apply(self, command: RobotCommand) -> None:
        try:
            if command.ball_handle is not None:
                holding = self.ball_handle(command.ball_handle).BallIsHolding
                rospy.loginfo("teleop_keyboard: BallHandle enable %d, holding: %d", command.ball_handle, holding)
            if command.kick is not None:
                done = self.shoot(command.kick.strength, int(command.kick.kind)).ShootIsDone
                self.teleop.kick_result(bool(done))
                rospy.loginfo("teleop_keyboard: %s kick at %d m/s, ShootIsDone: %d", command.kick.kind.name,
                              command.kick.strength, done)
        except rospy.ServiceException as exc:
            rospy.logwarn("teleop_keyboard: service call failed: %s", exc)

    def run(self, fd: int) -> None:
        """Read keys from ``fd`` (already in cbreak mode) and publish until quit or shutdown."""
        decoder = codecs.getincrementaldecoder("utf-8")(errors="ignore")
        period = 1.0 / self.rate
        next_publish = time.monotonic()
        while not rospy.is_shutdown():
            ready, _, _ = select.select([fd], [], [], max(0.0, next_publish - time.monotonic()))
            if ready:
                data = os.read(fd, 64)
                if not data:  # end of input: the terminal went away
                    return
                for key in decoder.decode(data):
                    command = self.teleop.handle(key)
                    if command is None:
                        return
                    self.apply(command)
                    if key in KEYS:
                        print(self.teleop.status(), flush=True)
                self.publish_command()  # a key press takes effect now, not at the next tick
            now = time.monotonic()
            if now >= next_publish:
                self.publish_command()
                next_publish = max(next_publish + period, now)
