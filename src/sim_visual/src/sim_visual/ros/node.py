"""The simulator node's ROS side: ``SimHost`` (``sim_visual.host``) behind the robots' topics and services and the
simulator's own. It only adapts: parameters in, messages to and from the core's types, the loop that steps it."""

from __future__ import annotations

import time
from collections.abc import Callable
from typing import Any, cast

import rospy
from dynamic_reconfigure.server import Server as ReconfigureServer
from geometry_msgs.msg import Twist
from rosgraph_msgs.msg import Clock
from sensor_msgs.msg import CameraInfo, Image, Imu, PointCloud2, PointField
from std_msgs.msg import Bool
from std_srvs.srv import Empty, EmptyResponse, Trigger, TriggerResponse

from nubot_common import NubotCommonError
from nubot_common import conversions as shared
from nubot_common.camera_info import camera_info_msg
from nubot_common.clouds import cloud_msg
from nubot_common.images import array_to_image
from nubot_common.msg import (
    BallHolder,
    BallInfo3d,
    BallTouch,
    DriveFeedback,
    GoalEvent,
    KickEvent,
    ModelStates,
    OdoInfo,
    OmniVisionInfo,
    VelCmd,
    WheelSpeeds,
    WorldDescription,
)
from nubot_common.node_io import publisher
from nubot_common.params import from_mapping
from nubot_common.reconfigure import config_type
from nubot_common.srv import (
    BallHandle,
    BallHandleResponse,
    DeleteModel,
    DeleteModelResponse,
    SetModelState,
    SetModelStateResponse,
    Shoot,
    ShootResponse,
    SpawnModel,
    SpawnModelResponse,
)
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from sim_visual import SimVisualError
from sim_visual import conversions as conv
from sim_visual.host import RECONFIGURABLE, RobotOutputs, RobotSensors, SimHost, Tick, event_line, kick_line
from sim_visual.params import RobotSpawn, SimNodeParams
from sim_visual.simulator import BallTouched, GoalScored, HolderChanged
from sim_visual.world import RobotState


def node_params(private: dict) -> SimNodeParams:
    """The node's parameters from its private namespace, the world from /world. Raises ``NubotCommonError`` or
    ``ValueError``. The reconfigure server mirrors its values as flat ~parameters: ones left by an earlier run are
    deleted, so that they do not override the YAML configuration."""
    for name in RECONFIGURABLE & private.keys() - {"real_time_factor"}:
        rospy.delete_param("~" + name)
        private.pop(name)
    sim = private.get("sim", {})
    if isinstance(sim, dict):
        if "world" in sim:
            raise NubotCommonError(f"~sim/world: the world comes from {WORLD_NAMESPACE} only")
        private["sim"] = {**sim, "world": world_from_params(rospy.get_param(WORLD_NAMESPACE, None))}
    return from_mapping(SimNodeParams, private, "~")


class RobotTopics:
    """One robot's topics and services (its sensors decide which)."""

    def __init__(self, node: SimVisualNode, name: str, has: RobotSensors):
        self.node, self.name, self.has = node, name, has
        pub = self._advertise
        one = 1  # images and clouds go through a queue of one: a lagging reader loses frames, as behind a camera
        self.percepts = pub("omnivision/OmniVisionInfo", OmniVisionInfo) if not has.camera else None
        self.ball3d = pub("kinect/ballinfo", BallInfo3d) if has.ball3d else None
        self.image = pub("camera/image_raw", Image, queue_size=one) if has.camera else None
        self.labels = pub("camera/labels", Image, queue_size=one) if has.labels else None
        self.odometry = pub("nubotdriver/odoinfo", OdoInfo) if has.camera else None
        self.holding = pub("nubotdriver/ballholding", Bool) if has.camera else None
        self.imu = pub("imu/data", Imu) if has.camera else None
        self.truth = pub("sim_visual/truth", OmniVisionInfo) if has.camera else None
        self.rgbd = [pub(f"kinect/{side}/points", PointCloud2, queue_size=one) for side in ("left", "right")] \
            if has.rgbd else []
        self.front = (pub("front_camera/image_raw", Image, queue_size=one),
                      pub("front_camera/camera_info", CameraInfo, queue_size=one)) if has.front else None
        self.drive: rospy.Publisher | None = None  # advertised once wheel speeds arrive
        self.inputs = [rospy.Subscriber(f"/{name}/nubotcontrol/velcmd", VelCmd, self.on_velcmd, queue_size=1),
                       rospy.Subscriber(f"/{name}/nubotdriver/wheel_speeds", WheelSpeeds, self.on_wheels,
                                        queue_size=1),
                       rospy.Service(f"/{name}/BallHandle", BallHandle, self.on_ball_handle),
                       rospy.Service(f"/{name}/Shoot", Shoot, self.on_shoot)]

    def _advertise(self, topic: str, kind: type, queue_size: int | None = None) -> rospy.Publisher:
        return publisher(f"/{self.name}/{topic}", kind, queue_size=queue_size)

    def listening(self, sensor: str) -> bool:
        if sensor == "front":
            return self.front is not None and self.front[0].get_num_connections() > 0
        return any(p.get_num_connections() > 0 for p in self.rgbd)

    def close(self) -> None:
        for item in self.inputs:
            item.unregister() if isinstance(item, rospy.Subscriber) else item.shutdown()
        for pub in (self.percepts, self.ball3d, self.image, self.labels, self.odometry, self.holding, self.imu,
                    self.truth, self.drive, *self.rgbd, *(self.front or ())):
            if pub is not None:
                pub.unregister()

    def publish(self, out: RobotOutputs, now: float) -> None:
        t, frame_id = conv.stamp(now), f"{self.name}/omni_camera"
        if out.percepts is not None and self.percepts is not None:
            self.percepts.publish(shared.omni_vision_msg(out.percepts))
        if out.has_ball3d and self.ball3d is not None:
            self.ball3d.publish(shared.ball_info3d_msg(out.ball3d, now))
        if out.camera is not None and out.truth is not None and self.image is not None and self.truth is not None:
            self.image.publish(array_to_image(out.camera.image, Image, t, frame_id))
            self.truth.publish(shared.omni_vision_msg(out.truth))
            if self.labels is not None and out.camera.labels is not None:
                self.labels.publish(array_to_image(out.camera.labels, Image, t, frame_id))
        if out.front is not None and self.front is not None:
            front_id = f"{self.name}/front_camera"
            self.front[0].publish(array_to_image(out.front, Image, t, front_id))
            camera = self.node.host.sim.config.sensors.front_camera.camera
            self.front[1].publish(camera_info_msg(camera, CameraInfo, t, front_id))
        for pub, cloud in zip(self.rgbd, out.rgbd):
            pub.publish(cloud_msg(cloud.points, cloud.rgb, PointCloud2, PointField, t,
                                  f"{self.name}/kinect_{cloud.camera}"))
        if out.odometry is not None and self.odometry is not None and self.holding is not None:
            self.odometry.publish(conv.odo_info_msg(out.odometry, now))
            self.holding.publish(Bool(bool(out.holding)))
        if out.drive is not None and self.drive is not None:
            msg = DriveFeedback(ground_speeds=out.drive[0].tolist(), ball_in_handler=out.drive[1])
            msg.header.stamp = t
            self.drive.publish(msg)
        if out.inertial is not None and self.imu is not None:
            self.imu.publish(conv.imu_msg(out.inertial, now, f"{self.name}/imu"))

    def on_velcmd(self, msg: VelCmd) -> None:
        self.node.warn(self.node.host.command_velocity(self.name, msg.Vx, msg.Vy, msg.w))

    def on_wheels(self, msg: WheelSpeeds) -> None:
        if self.drive is None:
            self.drive = self._advertise("sim_visual/drive_feedback", DriveFeedback)
        self.node.warn(self.node.host.command_wheels(self.name, tuple(msg.wheel_angles), msg.wheel_distance,
                                                     tuple(msg.speeds)))

    def on_ball_handle(self, req: BallHandle._request_class) -> BallHandleResponse:
        try:
            return BallHandleResponse(BallIsHolding=int(self.node.host.ball_handle(self.name, int(req.enable))))
        except SimVisualError as exc:
            self.node.warn(self.node.host.refused(self.name, "BallHandle refused", str(exc)))
            return BallHandleResponse(BallIsHolding=0)

    def on_shoot(self, req: Shoot._request_class) -> ShootResponse:
        try:
            done, event = self.node.host.shoot(self.name, float(req.strength), int(req.ShootPos))
        except SimVisualError as exc:
            self.node.warn(self.node.host.refused(self.name, "Shoot refused", str(exc)))
            return ShootResponse(ShootIsDone=0)
        if event is not None:
            self.node.kick_pub.publish(conv.kick_event_msg(event))
            rospy.loginfo(kick_line(event))
        return ShootResponse(ShootIsDone=int(done))


class SimVisualNode:
    def __init__(self, params: SimNodeParams):
        self.host = host = SimHost(params)
        self.clock_pub = publisher("/clock", Clock)
        self.states_pub = publisher("~model_states", ModelStates)
        self.world_pub = publisher("~world_description", WorldDescription, latch=True)
        self.world_pub.publish(shared.world_description_msg(params.sim.world, 0.0))
        self.event_pubs: dict[type, tuple[rospy.Publisher, Callable[[Any], Any]]] = {
            GoalScored: (publisher("~goal", GoalEvent), conv.goal_event_msg),
            BallTouched: (publisher("~ball_touch", BallTouch), conv.ball_touch_msg),
            HolderChanged: (publisher("~ball_holder", BallHolder, latch=True), conv.ball_holder_msg)}
        self.kick_pub = publisher("~kick", KickEvent)
        self.robots = {name: RobotTopics(self, name, has) for name, has in host.sensors.items()}
        rospy.Service("~set_model_state", SetModelState, self.on_set_model_state)
        rospy.Service("~spawn_model", SpawnModel, self.on_spawn)
        rospy.Service("~delete_model", DeleteModel, self.on_delete)
        rospy.Service("~reset_world", Empty, self.on_reset)
        rospy.Service("~switch_ends", Trigger, self.on_switch_ends)
        rospy.Service("~pause", Empty, lambda _req: self.on_pause(True))
        rospy.Service("~unpause", Empty, lambda _req: self.on_pause(False))
        self.reconfigure = ReconfigureServer(config_type(host.reconfigure_params()), self.on_reconfigure)
        rospy.loginfo("sim_visual: %d robot(s) %s, field %s, step %.3f s, real_time_factor %.2f", len(self.robots),
                      ", ".join(self.robots), params.sim.world.name, params.sim.physics.step_size,
                      host.pacer.factor)

    @staticmethod
    def warn(line: str | None) -> None:
        if line is not None:
            rospy.logwarn(line)

    def on_set_model_state(self, req: SetModelState._request_class) -> SetModelStateResponse:
        ms = req.model_state
        if ms.reference_frame not in ("", "world"):
            return SetModelStateResponse(False, f"reference_frame {ms.reference_frame!r} unsupported; use 'world'")
        try:
            state = conv.model_state_from_msg(ms.pose, ms.twist, ms.model_name == self.host.sim.config.ball_name)
            self.host.set_model_state(ms.model_name, state)
        except SimVisualError as exc:
            self.warn(self.host.refused("sim_visual", "set_model_state refused", str(exc)))
            return SetModelStateResponse(False, str(exc))
        return SetModelStateResponse(True, f"set {ms.model_name}")

    def on_spawn(self, req: SpawnModel._request_class) -> SpawnModelResponse:
        try:
            state = cast(RobotState, conv.model_state_from_msg(req.initial_pose, Twist(), is_ball=False))
            spawn = RobotSpawn(req.model_name, state.x, state.y, state.theta, int(req.attack))
            self.robots[spawn.name] = RobotTopics(self, spawn.name, self.host.spawn(spawn))
        except (SimVisualError, ValueError) as exc:
            self.warn(self.host.refused("sim_visual", "spawn_model refused", str(exc)))
            return SpawnModelResponse(False, str(exc))
        rospy.loginfo("sim_visual: spawned %s at (%.2f, %.2f), attacking %s", spawn.name, spawn.x, spawn.y,
                      "+x" if spawn.attack > 0 else "-x")
        return SpawnModelResponse(True, f"spawned {spawn.name}")

    def on_delete(self, req: DeleteModel._request_class) -> DeleteModelResponse:
        try:
            self.host.delete(req.model_name)
        except SimVisualError as exc:
            self.warn(self.host.refused("sim_visual", "delete_model refused", str(exc)))
            return DeleteModelResponse(False, str(exc))
        self.robots.pop(req.model_name).close()
        rospy.loginfo("sim_visual: deleted %s", req.model_name)
        return DeleteModelResponse(True, f"deleted {req.model_name}")

    def on_reset(self, _req: object) -> EmptyResponse:
        self.host.reset()
        rospy.loginfo("sim_visual: world reset")
        return EmptyResponse()

    def on_pause(self, paused: bool) -> EmptyResponse:
        self.host.pause(paused)
        return EmptyResponse()

    def on_switch_ends(self, _req: object) -> TriggerResponse:
        sides = self.host.switch_ends()
        rospy.loginfo("sim_visual: ends switched; robots now attack: %s", sides)
        return TriggerResponse(True, f"ends switched: {sides}")

    def on_reconfigure(self, config: dict, _level: int) -> dict:
        try:
            return {**config, **self.host.reconfigure(config)}
        except ValueError as exc:
            self.warn(self.host.refused("sim_visual", "reconfiguration refused", str(exc)))
            return {**config, **self.host.configuration()}

    def run(self) -> None:
        host = self.host
        while not rospy.is_shutdown():
            if host.paused:
                time.sleep(0.01)
                for line in host.idle():
                    rospy.logwarn(line)
                continue
            self.publish(host.step(self.listening))
            host.pacer.wait(host.sim.time, rospy.is_shutdown)

    def listening(self, robot: str, sensor: str) -> bool:
        topics = self.robots.get(robot)  # a robot just spawned may have no topics yet
        return topics is not None and topics.listening(sensor)

    def publish(self, tick: Tick) -> None:
        for line in tick.refusals:
            rospy.logwarn(line)
        if tick.clock:
            self.clock_pub.publish(Clock(clock=conv.stamp(tick.time)))
        if tick.states is not None:
            self.states_pub.publish(conv.model_states_msg(tick.states, tick.time))
        for name, out in tick.robots.items():
            robot = self.robots.get(name)
            if robot is not None:
                robot.publish(out, tick.time)
        for event in tick.events:
            said = event_line(event)
            if said is not None:
                rospy.loginfo(said)
            if type(event) in self.event_pubs:
                pub, to_msg = self.event_pubs[type(event)]
                pub.publish(to_msg(event))
