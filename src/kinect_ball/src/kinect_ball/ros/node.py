"""The kinect_ball node's ROS side: the goalie's two RGB-D clouds into KinectBall (kinect_ball.pipeline) and
its 3-D ball out. It only adapts."""

from __future__ import annotations

import threading
from dataclasses import fields

import rospy
from sensor_msgs.msg import PointCloud2

from kinect_ball import KinectBallError
from kinect_ball.pipeline import KinectBall, KinectBallParams
from nubot_common import NubotCommonError
from nubot_common import conversions as shared
from nubot_common.clouds import Cloud, cloud_from_msg
from nubot_common.geometry import Pose2D
from nubot_common.kinect_mount import CAMERAS
from nubot_common.msg import BallInfo3d, OmniVisionInfo
from nubot_common.naming import RobotNodeParams
from nubot_common.node_io import publisher
from nubot_common.params import from_mapping
from nubot_common.rejections import RefusalLog
from nubot_common.world_description import WORLD_NAMESPACE, world_from_params

_LOG_PERIOD = 5.0  # [s, wall] between two log lines about bad clouds or a missing pose
_PAIR_TOLERANCE = 0.005  # [s] two cameras' frames this close in time are one pair
_CLOUD_BUFFER = 1 << 20  # [B] a 128 x 106 cloud (217 kB) in one read


class KinectBallNode:
    def __init__(self) -> None:
        private = rospy.get_param("~", {})
        own = {f.name: private.pop(f.name) for f in fields(RobotNodeParams) if f.name in private}
        try:
            node = from_mapping(RobotNodeParams, own, "~")
            world = world_from_params(rospy.get_param(WORLD_NAMESPACE, None))
            params = from_mapping(KinectBallParams, private, "~")
            self.core = KinectBall(params, world.ball.radius)
        except (NubotCommonError, KinectBallError, ValueError) as exc:
            rospy.logfatal("kinect_ball: bad parameters: %s", exc)
            raise SystemExit(2) from exc
        self.robot = node.robot
        self.lock = threading.Lock()
        self.pose: Pose2D | None = None  # the robot's own pose from its omni vision
        self.pending: dict[str, tuple[float, PointCloud2]] = {}
        self.refusals = RefusalLog(f"kinect_ball: {self.robot}", rospy.logwarn, _LOG_PERIOD)
        self.ball_pub = publisher(f"/{self.robot}/kinect/ballinfo", BallInfo3d)
        rospy.Subscriber("pose", OmniVisionInfo, self.on_pose, queue_size=1)
        for camera in CAMERAS:
            rospy.Subscriber(f"/{self.robot}/kinect/{camera}/points", PointCloud2, self.on_cloud, camera,
                             queue_size=1, buff_size=_CLOUD_BUFFER)
        rospy.loginfo("kinect_ball: %s, ball radius %.3f m, pose from %s", self.robot, world.ball.radius,
                      rospy.resolve_name("pose"))

    def _log(self, kind: str, text: str) -> None:
        self.refusals.refused(kind, text)

    def on_pose(self, msg: OmniVisionInfo) -> None:
        if not msg.robotinfo:
            return
        report = shared.robot_report(msg.robotinfo[0])
        with self.lock:
            self.pose = report.pose if report.valid else None

    def on_cloud(self, msg: PointCloud2, camera: str) -> None:
        t = shared.seconds(msg.header.stamp) or rospy.get_time()
        other = CAMERAS[1] if camera == CAMERAS[0] else CAMERAS[0]
        with self.lock:
            groups = []
            stale = self.pending.pop(camera, None)
            if stale is not None:  # its partner never came
                groups.append({camera: stale})
            partner = self.pending.get(other)
            if partner is not None and abs(partner[0] - t) <= _PAIR_TOLERANCE:
                del self.pending[other]
                groups.append({other: partner, camera: (t, msg)})
            else:
                if partner is not None and partner[0] < t:
                    del self.pending[other]
                    groups.insert(0, {other: partner})
                self.pending[camera] = (t, msg)
            for group in groups:
                self._process(group)

    def _process(self, group: dict[str, tuple[float, PointCloud2]]) -> None:
        stamp = max(t for t, _ in group.values())
        clouds: dict[str, Cloud] = {}
        for camera, (_, msg) in group.items():
            try:
                clouds[camera] = cloud_from_msg(msg)
            except (NubotCommonError, KinectBallError) as exc:
                self._log(f"cloud_{camera}", f"{camera} cloud refused: {exc}")
        result = self.core.process(stamp, self.pose, clouds)
        if result.percept is None and result.reason.startswith("seen"):
            self._log("pose", f"{result.reason} (from {rospy.resolve_name('pose')})")
        self.ball_pub.publish(shared.ball_info3d_msg(result.percept, stamp))
