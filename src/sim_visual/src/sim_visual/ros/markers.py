"""The match_markers node's ROS side: the simulator's model states and the referee's ends into tf frames and RViz
markers (sim_visual.markers builds them), published only while someone watches. It only adapts."""

from __future__ import annotations

import threading

import rospy
from tf2_msgs.msg import TFMessage
from visualization_msgs.msg import MarkerArray

from nubot_common import NubotCommonError
from nubot_common import conversions as shared
from nubot_common.msg import GameState, PlannedPath, WorldDescription
from nubot_common.naming import is_robot_name
from nubot_common.node_io import publisher, timer
from nubot_common.params import from_mapping
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from sim_visual import marker_conversions as conv
from sim_visual.markers import (
    MatchMarkersParams,
    SimTimeThrottle,
    TeamSides,
    configured_attacks,
    field_markers,
    frame_transforms,
    scene_markers,
)


class MatchMarkers:
    def __init__(self) -> None:
        try:
            self.params = from_mapping(MatchMarkersParams, rospy.get_param("~", {}), "~")
            world_value = rospy.get_param(WORLD_NAMESPACE, None)
            self.world = world_from_params(world_value) if world_value is not None else None
            self.sides = TeamSides(configured_attacks(rospy.get_param("/sim_visual/sim/robots", [])))
        except (NubotCommonError, ValueError) as exc:
            rospy.logfatal("match_markers: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.lock = threading.Lock()
        self.throttle = SimTimeThrottle(1.0 / self.params.tf_rate)
        self.poses: list = []  # the latest ModelPose list decoded
        self.paths: dict[str, tuple[str, list[tuple[float, float]]]] = {}  # robot -> (frame, points)
        self.path_subs: dict[str, rospy.Subscriber] = {}
        self.tf_pub = publisher("/tf", TFMessage)
        self.field_pub = publisher("~field", MarkerArray, latch=True)
        self.scene_pub = publisher("~scene", MarkerArray)
        if self.world is not None:
            self.field_pub.publish(conv.marker_array(field_markers(self.world)))
        rospy.Subscriber("/sim_visual/world_description", WorldDescription, self.on_world, queue_size=1)
        rospy.Subscriber("/referee/state", GameState, self.on_referee, queue_size=1)
        rospy.Subscriber("/sim_visual/model_states", rospy.AnyMsg, self.on_states, queue_size=1)
        self.timer = timer(1.0 / self.params.scene_rate, self.on_scene_timer)
        rospy.loginfo("match_markers: frames at %.0f Hz, scene at %.0f Hz while watched", self.params.tf_rate,
                      self.params.scene_rate)

    def on_world(self, msg: WorldDescription) -> None:
        try:
            world = shared.world_description(msg)
        except (NubotCommonError, ValueError) as exc:
            rospy.logwarn("match_markers: world description ignored: %s", exc)
            return
        if world != self.world:
            self.world = world
            self.field_pub.publish(conv.marker_array(field_markers(world)))

    def on_referee(self, msg: GameState) -> None:
        with self.lock:
            self.sides.on_referee(list(msg.teams), list(msg.attack))

    def on_states(self, raw: rospy.AnyMsg) -> None:
        watched = self.tf_pub.get_num_connections() > 0 or self.scene_pub.get_num_connections() > 0
        if not watched or self.world is None:
            return
        stamp = conv.header_stamp(raw._buff)
        if not self.throttle.due(stamp.to_sec()):
            return
        poses = conv.model_poses(conv.model_states(raw._buff))
        with self.lock:
            self.poses = poses
            transforms = frame_transforms(poses, self.sides, self.world.ball_name)
        self.tf_pub.publish(conv.tf_message(transforms, stamp))

    def on_path(self, robot: str, msg: PlannedPath) -> None:
        with self.lock:
            self.paths[robot] = (msg.header.frame_id, shared.planned_path(msg))

    def on_scene_timer(self, _event: object) -> None:
        watched = self.scene_pub.get_num_connections() > 0
        with self.lock:
            robots = {p.name for p in self.poses if is_robot_name(p.name)}
            wanted = robots if watched else set()
            for robot in set(self.path_subs) - wanted:  # nobody watches, or the robot left
                self.path_subs.pop(robot).unregister()
                self.paths.pop(robot, None)
            for robot in wanted - set(self.path_subs):
                self.path_subs[robot] = rospy.Subscriber(f"/{robot}/nubotcontrol/path", PlannedPath,
                                                         lambda m, r=robot: self.on_path(r, m), queue_size=1)
            if not watched or self.world is None:
                return
            markers = scene_markers(self.poses, self.world, self.sides, self.paths)
        self.scene_pub.publish(conv.marker_array(markers))
