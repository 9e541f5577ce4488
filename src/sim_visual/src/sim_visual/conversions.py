"""Conversions between ROS messages and the simulator's own core types (the only place that knows both).

Requires: generated ``nubot_common`` messages, ``geometry_msgs``, ``sensor_msgs``, ``genpy`` (no rospy). The shared
messages (OmniVisionInfo, VelCmd, the world description) are converted by ``nubot_common.conversions``.
"""

from __future__ import annotations

import math

from geometry_msgs.msg import Pose, Twist
from sensor_msgs.msg import Imu

from nubot_common.conversions import stamp
from nubot_common.geometry import quaternion_to_yaw, yaw_to_quaternion
from nubot_common.msg import BallHolder, BallTouch, GoalEvent, KickEvent, ModelStates, OdoInfo, Point3d
from sim_visual import SimVisualError
from sim_visual.odometry import ImuReading, OdometryReading
from sim_visual.simulator import BallKicked, BallTouched, GoalScored, HolderChanged
from sim_visual.world import BallState, RobotState


def _pose(x: float, y: float, z: float, yaw: float) -> Pose:
    pose = Pose()
    pose.position.x, pose.position.y, pose.position.z = x, y, z
    q = yaw_to_quaternion(yaw)
    pose.orientation.x, pose.orientation.y, pose.orientation.z, pose.orientation.w = q
    return pose


def _twist(vx: float, vy: float, vz: float, wx: float, wy: float, wz: float) -> Twist:
    twist = Twist()
    twist.linear.x, twist.linear.y, twist.linear.z = vx, vy, vz
    twist.angular.x, twist.angular.y, twist.angular.z = wx, wy, wz
    return twist


def model_states_msg(states: list[tuple[str, RobotState | BallState]], t: float) -> ModelStates:
    """Every model's state at sim time ``t`` [s], world frame."""
    msg = ModelStates()
    msg.header.stamp = stamp(t)
    for name, s in states:
        msg.name.append(name)
        if isinstance(s, RobotState):
            msg.pose.append(_pose(s.x, s.y, 0.0, s.theta))
            msg.twist.append(_twist(s.vx, s.vy, 0.0, 0.0, 0.0, s.w))
        else:
            msg.pose.append(_pose(s.x, s.y, s.z, 0.0))
            msg.twist.append(_twist(s.vx, s.vy, s.vz, s.wx, s.wy, s.wz))
    return msg


def model_state_from_msg(pose: Pose, twist: Twist, is_ball: bool) -> RobotState | BallState:
    """Core state from a SetModelState request; raises ``SimVisualError`` on a bad quaternion."""
    o = pose.orientation
    norm = math.sqrt(o.x * o.x + o.y * o.y + o.z * o.z + o.w * o.w)
    if not math.isfinite(norm):
        raise SimVisualError("orientation must be finite")
    yaw = quaternion_to_yaw(o.x, o.y, o.z, o.w) if norm > 1e-9 else 0.0
    p, v, w = pose.position, twist.linear, twist.angular
    if is_ball:
        return BallState(p.x, p.y, p.z, v.x, v.y, v.z, w.x, w.y, w.z)
    return RobotState(p.x, p.y, yaw, v.x, v.y, w.z)


def goal_event_msg(goal: GoalScored) -> GoalEvent:
    msg = GoalEvent()
    msg.header.stamp = stamp(goal.time)
    msg.side = goal.side
    msg.ball_pos = Point3d(goal.ball.x, goal.ball.y, goal.ball.z)
    msg.last_touch = goal.last_touch
    return msg


def _robot_and_ball(msg: BallTouch | BallHolder, event: BallTouched | HolderChanged) -> BallTouch | BallHolder:
    msg.header.stamp = stamp(event.time)
    msg.robot = event.robot
    msg.ball_pos = Point3d(event.ball.x, event.ball.y, event.ball.z)
    return msg


def ball_touch_msg(touch: BallTouched) -> BallTouch:
    return _robot_and_ball(BallTouch(), touch)


def ball_holder_msg(change: HolderChanged) -> BallHolder:
    return _robot_and_ball(BallHolder(), change)


def kick_event_msg(kick: BallKicked) -> KickEvent:
    msg = KickEvent()
    msg.header.stamp = stamp(kick.time)
    msg.robot = kick.robot
    msg.kind = int(kick.kind)
    msg.velocity = Point3d(*kick.velocity)
    msg.ball_pos = Point3d(*kick.position)
    return msg


def odo_info_msg(reading: OdometryReading, t: float) -> OdoInfo:
    """nubot_common/OdoInfo of a wheel odometry reading at sim time ``t`` [s] (body frame, SI)."""
    msg = OdoInfo(Vx=reading.vx, Vy=reading.vy, w=reading.w, RobotStuck=reading.robot_stuck,
                  PowerState=reading.power_state)
    msg.header.stamp = stamp(t)
    msg.header.frame_id = "base_link"
    return msg


def imu_msg(reading: ImuReading, t: float, frame_id: str) -> Imu:
    """sensor_msgs/Imu of an inertial heading at sim time ``t``: orientation (yaw only, team frame) and yaw
    rate; the covariances' first element -1 says a field is not given (REP 145), here the acceleration."""
    msg = Imu()
    msg.header.stamp = stamp(t)
    msg.header.frame_id = frame_id
    q = yaw_to_quaternion(reading.yaw)
    msg.orientation.x, msg.orientation.y, msg.orientation.z, msg.orientation.w = q
    msg.angular_velocity.z = reading.yaw_rate
    msg.linear_acceleration_covariance[0] = -1.0
    return msg
