"""The front vision node's ROS side: the front camera's images into FrontVision (front_vision.pipeline) and
the near ball out, in the robot's body frame. It only adapts."""

from __future__ import annotations

from dataclasses import dataclass, fields

import cv2
import rospy
from sensor_msgs.msg import Image

from front_vision import FrontVisionError
from front_vision.pipeline import FrontVision, FrontVisionParams
from nubot_common import NubotCommonError
from nubot_common import conversions as shared
from nubot_common import images as image_conv
from nubot_common.camera_model import load_camera
from nubot_common.msg import FrontBallInfo
from nubot_common.naming import RobotNodeParams
from nubot_common.node_io import publisher
from nubot_common.params import from_mapping
from nubot_common.rejections import RefusalLog
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params
from omni_vision import OmniVisionError
from omni_vision.colors import ColorTable

_IMAGE_BUFFER = 1 << 19  # [B]: a whole 320 x 240 RGB image (230 kB) in one read
_ERROR_LOG_PERIOD = 5.0  # [s, wall] between two log lines about bad images


@dataclass(frozen=True)
class FrontVisionNodeParams(RobotNodeParams):
    camera: str = ""  # path of the calibrated camera's YAML
    color_table: str = ""  # path of the colour lookup table file


class FrontVisionNode:
    def __init__(self) -> None:
        private = rospy.get_param("~", {})
        own = {f.name: private.pop(f.name) for f in fields(FrontVisionNodeParams) if f.name in private}
        try:
            node = from_mapping(FrontVisionNodeParams, own, "~")
            if not node.camera or not node.color_table:
                raise FrontVisionError("~camera and ~color_table: give the paths of the calibrated camera's YAML "
                                       "and of a colour lookup table file")
            camera = load_camera(node.camera)
            table = ColorTable.load(node.color_table)
            world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))  # the ball's size
            self.vision = FrontVision(camera, table, from_mapping(FrontVisionParams, private, "~"), world)
        except (NubotCommonError, FrontVisionError, OmniVisionError, ValueError, OSError) as exc:
            rospy.logfatal("front_vision: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.robot = node.robot
        self.frame_id = f"{self.robot}/base_link"
        self.refusals = RefusalLog(f"front_vision: {self.robot}", rospy.logerr, _ERROR_LOG_PERIOD)
        self.ball_pub = publisher(f"/{self.robot}/front_vision/FrontBallInfo", FrontBallInfo)
        rospy.Subscriber("image", Image, self.on_image, queue_size=1, buff_size=_IMAGE_BUFFER)
        rospy.loginfo("front_vision: %s on %s, camera %s (%d x %d), table %s", self.robot,
                      rospy.resolve_name("image"), node.camera, camera.width, camera.height, node.color_table)

    def _log_bad_input(self, text: str) -> None:
        kind, _, detail = text.partition(": ")
        self.refusals.refused(kind, detail)

    def on_image(self, msg: Image) -> None:
        t = shared.seconds(msg.header.stamp) or rospy.get_time()
        try:
            result = self.vision.process(t, image_conv.image_to_array(msg))
            percept = result.percept
        except (NubotCommonError, FrontVisionError, OmniVisionError, cv2.error) as exc:
            self._log_bad_input(f"image refused: {exc}")
            percept = None
        self.ball_pub.publish(shared.front_ball_info_msg(percept, t, self.frame_id))
