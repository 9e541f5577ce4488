"""Conversions of the match_markers node: model states in, tf2 and RViz messages out (no rospy).

Requires: ``nubot_common/ModelStates``, ``tf2_msgs``, ``visualization_msgs``, ``geometry_msgs``. Provides:
``header_stamp`` (the stamp of a serialised message that begins with a Header, read without decoding the rest),
``model_states`` (a serialised ModelStates decoded), ``model_poses`` (ModelStates -> ``sim_visual.markers.ModelPose``
list), ``tf_message`` (``FrameTransform`` list
-> ``tf2_msgs/TFMessage``) and ``marker_array`` (``Marker`` list -> ``visualization_msgs/MarkerArray``).
Markers carry a zero stamp: RViz draws them with the latest transform of their frame.
"""

from __future__ import annotations

import struct
from collections.abc import Sequence

import genpy
from geometry_msgs.msg import Point, TransformStamped
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import Marker as MarkerMsg
from visualization_msgs.msg import MarkerArray

from nubot_common.geometry import yaw_to_quaternion
from nubot_common.msg import ModelStates
from sim_visual.markers import FrameTransform, Marker, MarkerKind, ModelPose

_STAMP = struct.Struct("<II")  # a Header's stamp: secs, nsecs, after its uint32 seq


def header_stamp(raw: bytes) -> genpy.Time:
    """The header stamp of a serialised message whose first field is a std_msgs/Header."""
    secs, nsecs = _STAMP.unpack_from(raw, 4)
    return genpy.Time(secs, nsecs)


def model_states(raw: bytes) -> ModelStates:
    return ModelStates().deserialize(raw)


def model_poses(msg: ModelStates) -> list[ModelPose]:
    out = []
    for name, pose in zip(msg.name, msg.pose):
        p, q = pose.position, pose.orientation
        out.append(ModelPose(name, (p.x, p.y, p.z), (q.x, q.y, q.z, q.w)))
    return out


def tf_message(transforms: Sequence[FrameTransform], stamp: genpy.Time) -> TFMessage:
    """The transforms at one instant (``stamp``: the model states' sim time)."""
    out = TFMessage()
    for tf in transforms:
        msg = TransformStamped()
        msg.header.stamp, msg.header.frame_id, msg.child_frame_id = stamp, tf.parent, tf.child
        t, r = msg.transform.translation, msg.transform.rotation
        t.x, t.y, t.z = tf.translation
        r.x, r.y, r.z, r.w = tf.rotation
        out.transforms.append(msg)
    return out


def marker_msg(marker: Marker) -> MarkerMsg:
    msg = MarkerMsg()
    msg.header.frame_id, msg.ns, msg.id = marker.frame, marker.ns, marker.id
    if marker.kind is MarkerKind.DELETEALL:
        msg.action = MarkerMsg.DELETEALL
        return msg
    msg.type, msg.action, msg.frame_locked, msg.text = int(marker.kind), MarkerMsg.ADD, marker.frame_locked, marker.text
    p, o = msg.pose.position, msg.pose.orientation
    p.x, p.y, p.z = marker.position
    o.x, o.y, o.z, o.w = yaw_to_quaternion(marker.yaw)
    msg.scale.x, msg.scale.y, msg.scale.z = marker.scale
    msg.color.r, msg.color.g, msg.color.b, msg.color.a = marker.colour
    msg.points = [Point(*point) for point in marker.points]
    return msg


def marker_array(markers: Sequence[Marker]) -> MarkerArray:
    return MarkerArray(markers=[marker_msg(m) for m in markers])
