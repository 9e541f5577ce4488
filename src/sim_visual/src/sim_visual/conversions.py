"""Conversions between ROS messages and the simulator's core types (the only place that knows both).

Requires: generated ``nubot_common`` messages, ``geometry_msgs``, ``genpy`` (no rospy).
"""

from __future__ import annotations

import math

import genpy
from geometry_msgs.msg import Pose, Twist

from nubot_common.geometry import quaternion_to_yaw, yaw_to_quaternion
from nubot_common.msg import (
    BallInfo,
    BallTouch,
    GoalEvent,
    KickEvent,
    ModelStates,
    ObstaclesInfo,
    OmniVisionInfo,
    Point2d,
    Point3d,
    PPoint,
    RobotInfo,
)
from sim_visual import SimVisualError
from sim_visual.sensing import OmniVisionFrame
from sim_visual.simulator import BallKicked, BallTouched, GoalScored
from sim_visual.world import BallState, RobotState

BALL_SEEN = 1


def stamp(t: float) -> genpy.Time:
    return genpy.Time.from_sec(t)


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


def model_states_msg(states: list[tuple[str, RobotState | BallState]]) -> ModelStates:
    msg = ModelStates()
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


def omni_vision_msg(frame: OmniVisionFrame) -> OmniVisionInfo:
    t = stamp(frame.stamp)
    msg = OmniVisionInfo()
    msg.header.stamp = t
    ball = BallInfo()
    ball.header.stamp = t
    if frame.ball is not None:
        b = frame.ball
        ball.ballinfostate = BALL_SEEN
        ball.pos, ball.velocity = Point2d(b.x, b.y), Point2d(b.vx, b.vy)
        ball.real_pos = PPoint(b.angle, b.radius)
        ball.pos_known = ball.velocity_known = True
    msg.ballinfo = ball
    obstacles = ObstaclesInfo()
    obstacles.header.stamp = t
    obstacles.pos = [Point2d(o.x, o.y) for o in frame.obstacles]
    obstacles.polar_pos = [PPoint(o.angle, o.radius) for o in frame.obstacles]
    msg.obstacleinfo = obstacles
    r = frame.robot
    info = RobotInfo()
    info.header.stamp = t
    info.AgentID = r.agent_id
    info.pos = Point2d(r.x, r.y)
    info.heading.theta = r.theta
    info.vrot = r.w
    info.vtrans = Point2d(r.vx, r.vy)
    info.iskick, info.isvalid, info.isstuck, info.isdribble = r.is_kick, r.is_valid, r.is_stuck, r.is_dribble
    msg.robotinfo = [info]
    return msg


def goal_event_msg(goal: GoalScored) -> GoalEvent:
    msg = GoalEvent()
    msg.header.stamp = stamp(goal.time)
    msg.side = goal.side
    msg.ball_pos = Point3d(goal.ball.x, goal.ball.y, goal.ball.z)
    msg.last_touch = goal.last_touch
    return msg


def ball_touch_msg(touch: BallTouched) -> BallTouch:
    msg = BallTouch()
    msg.header.stamp = stamp(touch.time)
    msg.robot = touch.robot
    msg.ball_pos = Point3d(touch.ball.x, touch.ball.y, touch.ball.z)
    return msg


def kick_event_msg(kick: BallKicked) -> KickEvent:
    msg = KickEvent()
    msg.header.stamp = stamp(kick.time)
    msg.robot = kick.robot
    msg.kind = kick.kind
    msg.velocity = Point3d(*kick.velocity)
    msg.ball_pos = Point3d(*kick.position)
    return msg
