"""The hardware control node's ROS side: ``HardwareHost`` (``nubot_hwcontrol.host``) behind the robot interface,
and the simulated drive's world over sim_visual's topics. It only adapts: parameters, topics, the cycle's timer and
the messages."""

from __future__ import annotations

import numpy as np
import rospy
from std_msgs.msg import Bool

from nubot_common import NubotCommonError
from nubot_common.commands import KickKind
from nubot_common.kinematics import WheelLayout
from nubot_common.msg import DriveFeedback, HardwareStatus, OdoInfo, VelCmd, WheelSpeeds
from nubot_common.node_io import publisher, timer
from nubot_common.srv import BallHandle, BallHandleResponse, Shoot, ShootResponse
from nubot_hwcontrol import HardwareError
from nubot_hwcontrol.backend import make_backend
from nubot_hwcontrol.controller import HardwareController
from nubot_hwcontrol.host import HardwareHost
from nubot_hwcontrol.params import HwNodeParams


class RosSimWorld:
    """The simulated drive's world: robot ``name`` of the sim_visual node, over its topics and services."""

    def __init__(self, name: str):
        self.name = name
        self.feedback: DriveFeedback | None = None
        self.wheel_pub = publisher(f"/{name}/nubotdriver/wheel_speeds", WheelSpeeds, queue_size=1)
        rospy.Subscriber(f"/{name}/sim_visual/drive_feedback", DriveFeedback, self.on_feedback, queue_size=1)
        self.ball_handle = rospy.ServiceProxy(f"/{name}/BallHandle", BallHandle)
        self.shoot = rospy.ServiceProxy(f"/{name}/Shoot", Shoot)

    def on_feedback(self, msg: DriveFeedback) -> None:
        self.feedback = msg

    def drive(self, layout: WheelLayout, rim_speeds: np.ndarray) -> None:
        msg = WheelSpeeds(wheel_angles=np.radians(layout.wheel_angles_deg).tolist(),
                          wheel_distance=layout.wheel_distance, speeds=np.asarray(rim_speeds).tolist())
        msg.header.stamp = rospy.Time.now()
        self.wheel_pub.publish(msg)

    def ground_speeds(self, layout: WheelLayout) -> np.ndarray:
        fb = self.feedback
        if fb is None or len(fb.ground_speeds) != layout.wheels:
            return np.zeros(layout.wheels)
        return np.asarray(fb.ground_speeds, dtype=float)

    def ball_in_handler(self) -> bool:
        return self.feedback is not None and self.feedback.ball_in_handler

    def set_dribbling(self, on: bool) -> None:
        try:
            self.ball_handle(int(on))
        except (rospy.ServiceException, rospy.ROSException) as exc:
            rospy.logwarn_throttle(5.0, f"nubot_hwcontrol: simulator's BallHandle of {self.name} failed: {exc}")

    def kick(self, speed: float, lob: bool) -> bool:
        try:
            return bool(self.shoot(int(round(speed)), KickKind.LOB if lob else KickKind.GROUND).ShootIsDone)
        except (rospy.ServiceException, rospy.ROSException) as exc:
            rospy.logwarn(f"nubot_hwcontrol: simulator's Shoot of {self.name} failed: {exc}")
            return False


class HwControlNode:
    def __init__(self, params: HwNodeParams):
        """Raises ``NubotCommonError`` or ``HardwareError`` for bad parameters or hardware that cannot be opened."""
        control = params.control
        layout = control.layout(params.goalie)
        if params.backend == "sim":
            backend = make_backend("sim", world=RosSimWorld(params.sim_robot), layout=layout,
                                   params=params.sim_drive, seed=params.seed)
        else:
            backend = make_backend("ethercat", layout=layout, params=params.ethercat)
        self.host = HardwareHost(HardwareController(control, backend, params.goalie), params.status_rate,
                                 rospy.get_time())
        self.odo_pub = publisher("nubotdriver/odoinfo", OdoInfo)
        self.holding_pub = publisher("nubotdriver/ballholding", Bool)
        self.status_pub = publisher("nubotdriver/status", HardwareStatus)
        rospy.Subscriber("nubotcontrol/velcmd", VelCmd, self.on_velcmd, queue_size=1)
        rospy.Service("BallHandle", BallHandle,
                      lambda req: BallHandleResponse(BallIsHolding=int(self.host.ball_handle(int(req.enable)))))
        rospy.Service("Shoot", Shoot, self.on_shoot)
        rospy.on_shutdown(self.host.close)
        # node_io's timer: under sim time its thread wakes only when a cycle is due, not at every /clock
        self.timer = timer(1.0 / control.rate, self.cycle)
        rospy.loginfo("nubot_hwcontrol: %s backend, %s wheel layout at %s deg, %.0f Hz", backend.name,
                      "goalie" if params.goalie else "regular", layout.wheel_angles_deg, control.rate)

    def on_velcmd(self, msg: VelCmd) -> None:
        try:
            self.host.command_velocity(rospy.get_time(), msg.Vx, msg.Vy, msg.w)
        except (NubotCommonError, HardwareError) as exc:
            rospy.logerr_throttle(2.0, f"nubot_hwcontrol: velocity command refused: {exc}")

    def on_shoot(self, req: Shoot._request_class) -> ShootResponse:
        try:
            return ShootResponse(ShootIsDone=int(self.host.shoot(rospy.get_time(), float(req.strength),
                                                                 int(req.ShootPos))))
        except (NubotCommonError, HardwareError) as exc:
            rospy.logerr(f"nubot_hwcontrol: Shoot refused: {exc}")
            return ShootResponse(ShootIsDone=0)

    def cycle(self, _event: object) -> None:
        now = rospy.get_time()  # the node's clock: the wall clock on a real robot, the simulator's under sim time
        try:
            done = self.host.cycle(now)
        except (NubotCommonError, HardwareError) as exc:
            rospy.logerr_throttle(2.0, f"nubot_hwcontrol: cycle failed: {exc}")
            return
        if done is None:
            return  # the timer woke again within one tick of the clock: this time's cycle ran already
        report, status = done
        odo = report.odometry
        msg = OdoInfo(Vx=odo.vx, Vy=odo.vy, w=odo.w, RobotStuck=odo.stuck, PowerState=report.state.power_on)
        msg.header.stamp = rospy.Time.from_sec(now)
        self.odo_pub.publish(msg)
        self.holding_pub.publish(Bool(report.holding))
        if status is not None:
            out = HardwareStatus(**vars(status))
            out.header.stamp = rospy.Time.now()
            self.status_pub.publish(out)
