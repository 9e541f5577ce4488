"""The omni vision node's ROS side: OmniVision (omni_vision.pipeline) between the robot's camera, odometry,
IMU and ball-holding signal and its OmniVisionInfo; with the simulator's truth, the localization error. It only
adapts."""

from __future__ import annotations

import threading
from dataclasses import dataclass, fields

import rospy
from sensor_msgs.msg import Image, Imu
from std_msgs.msg import Bool

from nubot_common import NubotCommonError, images
from nubot_common import conversions as shared
from nubot_common.msg import LocalizationError, OdoInfo, OmniVisionInfo
from nubot_common.naming import RobotNodeParams
from nubot_common.node_io import publisher
from nubot_common.params import from_mapping
from nubot_common.rejections import RefusalLog
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from omni_vision import OmniVisionError
from omni_vision import conversions as conv
from omni_vision.colors import ColorTable
from omni_vision.debug import draw_debug_image
from omni_vision.pipeline import OmniVision, OmniVisionParams
from omni_vision.stamp_pairs import StampPairs

_IMAGE_BUFFER = 1 << 20  # [B]: a whole 480 x 480 RGB image (691 kB) in one read
_ERROR_LOG_PERIOD = 5.0  # [s, wall] between two log lines about bad images
_TRUTH_KEPT = 30  # truth frames kept to match an image's stamp (one second at 30 Hz)


@dataclass(frozen=True)
class OmniVisionNodeParams(RobotNodeParams):
    color_table: str = ""  # path of the colour lookup table file (calibrate_colors writes one)


class OmniVisionNode:
    def __init__(self) -> None:
        private = rospy.get_param("~", {})
        own = {f.name: private.pop(f.name) for f in fields(OmniVisionNodeParams) if f.name in private}
        try:
            node = from_mapping(OmniVisionNodeParams, own, "~")
            if not node.color_table:
                raise OmniVisionError("~color_table: give the path of a colour lookup table file")
            table = ColorTable.load(node.color_table)
            world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))
            params = from_mapping(OmniVisionParams, private, "~")
            self.vision = OmniVision(world, params, table, node.agent)
        except (NubotCommonError, OmniVisionError, ValueError, OSError) as exc:
            rospy.logfatal("omni_vision: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.robot = node.robot
        self.lock = threading.Lock()
        self.pairs: StampPairs = StampPairs(_TRUTH_KEPT)  # each frame with the truth of its stamp, either first
        self.refusals = RefusalLog(f"omni_vision: {self.robot}", rospy.logerr, _ERROR_LOG_PERIOD)
        self.vision_pub = publisher(f"/{self.robot}/omnivision/OmniVisionInfo", OmniVisionInfo)
        self.debug_pub = publisher(f"/{self.robot}/omnivision/debug_image", Image)
        self.error_pub = publisher(f"/{self.robot}/omnivision/localization_error", LocalizationError)
        rospy.Subscriber(f"/{self.robot}/nubotdriver/odoinfo", OdoInfo, self.on_odometry, queue_size=10)
        rospy.Subscriber(f"/{self.robot}/nubotdriver/ballholding", Bool, self.on_holding, queue_size=10)
        rospy.Subscriber(f"/{self.robot}/imu/data", Imu, self.on_imu, queue_size=10)
        rospy.Subscriber(f"/{self.robot}/sim_visual/truth", OmniVisionInfo, self.on_truth, queue_size=10)
        rospy.Subscriber("image", Image, self.on_image, queue_size=1, buff_size=_IMAGE_BUFFER)
        rospy.loginfo("omni_vision: %s (agent %d) on %s, field %s, table %s", self.robot, node.agent,
                      rospy.resolve_name("image"), world.name, node.color_table)

    def _log_bad_input(self, text: str) -> None:
        kind, _, detail = text.partition(": ")
        self.refusals.refused(kind, detail)

    def on_odometry(self, msg: OdoInfo) -> None:
        try:
            with self.lock:
                self.vision.odometry(shared.seconds(msg.header.stamp), msg.Vx, msg.Vy, msg.w, msg.RobotStuck)
        except OmniVisionError as exc:
            self._log_bad_input(f"odometry refused: {exc}")

    def on_holding(self, msg: Bool) -> None:
        with self.lock:
            self.vision.ball_holding(rospy.get_time(), msg.data)

    def on_imu(self, msg: Imu) -> None:
        try:
            yaw = conv.imu_yaw(msg)
            with self.lock:
                self.vision.inertial(shared.seconds(msg.header.stamp), yaw)
        except OmniVisionError as exc:
            self._log_bad_input(f"inertial heading refused: {exc}")

    def on_truth(self, msg: OmniVisionInfo) -> None:
        with self.lock:
            frame = self.pairs.second(shared.seconds(msg.header.stamp), msg)
        if frame is not None:  # its image came first: the error now
            self._publish_error(frame, msg)

    def on_image(self, msg: Image) -> None:
        t = shared.seconds(msg.header.stamp) or rospy.get_time()
        try:
            rgb = images.image_to_array(msg)
            with self.lock:
                frame = self.vision.process(t, rgb)
                truth = self.pairs.first(t, frame)  # on a busy machine the truth may come after it
        except (NubotCommonError, OmniVisionError) as exc:
            self._log_bad_input(f"image refused: {exc}")
            return
        self.vision_pub.publish(shared.omni_vision_msg(frame.view))
        if truth is not None:
            self._publish_error(frame, truth)
        if self.debug_pub.get_num_connections() > 0:
            self.debug_pub.publish(images.array_to_image(draw_debug_image(rgb, frame, self.vision), Image,
                                                       msg.header.stamp, msg.header.frame_id))

    def _publish_error(self, frame, truth: OmniVisionInfo) -> None:
        true_pose = shared.robot_report(truth.robotinfo[0]).pose
        self.error_pub.publish(conv.localization_error_msg(frame.view, frame.localized, true_pose, LocalizationError))
