"""kinect_ball's core: both RGB-D cameras' clouds and the robot's pose in, the ball in 3-D with its flight out.

Requires: the ball's radius [m] (the world's ball), ``KinectBallParams`` (detection, flight, the cameras' mounts
on the robot, the fusion distance, the RANSAC's seed) and, per frame, its stamp [s], the robot's pose in its team
frame (its own self-localization; None before it has one) and one ``Cloud`` per camera that has a frame at that
stamp. Provides ``KinectBall.process`` -> ``KinectResult``: the ``Ball3dPercept`` (team frame; velocity the
fitted parabola's slope at the stamp) or None with the reason, the predicted touchdown (``Landing``, team frame),
each camera's ``DetectionReport`` and the stage times [s].

Fusion: each camera's sphere centre goes into the robot's body frame through its mount, then into the team frame
through the robot's pose; two sightings closer than ``fusion_distance`` are one ball (weighted by their inverse
variances), farther apart the one with more inliers is kept.
"""

from __future__ import annotations

import math
import time
from collections.abc import Mapping
from dataclasses import dataclass
from dataclasses import field as dc_field

import numpy as np

from kinect_ball.detection import DetectionParams, DetectionReport, detect_ball
from kinect_ball.flight import FlightParams, FlightTracker, Sighting
from nubot_common.ball_flight import Landing
from nubot_common.clouds import Cloud
from nubot_common.geometry import Pose2D
from nubot_common.kinect_mount import CAMERAS, GOALIE_MOUNTS, RgbdMounts, body_to_team
from nubot_common.params import require_positive
from nubot_common.percepts import Ball3dPercept


@dataclass(frozen=True)
class KinectBallParams:
    detection: DetectionParams = dc_field(default_factory=DetectionParams)
    flight: FlightParams = dc_field(default_factory=FlightParams)
    mounts: RgbdMounts = dc_field(default_factory=lambda: GOALIE_MOUNTS)
    fusion_distance: float = 0.3  # [m] two cameras' sightings closer than this are one ball
    seed: int = 0  # the RANSAC's samples

    def __post_init__(self) -> None:
        require_positive(self, "fusion_distance")
        if self.seed < 0:
            raise ValueError(f"seed must not be negative, got {self.seed}")


@dataclass(frozen=True)
class KinectResult:
    stamp: float  # [s]
    percept: Ball3dPercept | None  # None: no ball this frame
    reason: str  # why there is no percept ("" with one)
    touchdown: Landing | None  # where and when the ball comes down (team frame), once its flight is fitted
    reports: dict[str, DetectionReport]  # per camera given
    times: dict[str, float]  # [s] per stage: detect, track


class KinectBall:
    def __init__(self, params: KinectBallParams, ball_radius: float):
        if not ball_radius > 0.0:
            raise ValueError(f"ball_radius must be positive, got {ball_radius}")
        self.params, self.radius = params, ball_radius
        self.rng = np.random.default_rng(params.seed)
        self.tracker = FlightTracker(params.flight, ball_radius)

    def reset(self) -> None:
        self.tracker.reset()

    def process(self, stamp: float, pose: Pose2D | None, clouds: Mapping[str, Cloud]) -> KinectResult:
        """One frame: each camera's cloud (camera name -> cloud) at ``stamp`` [s] seen from ``pose`` (team frame)."""
        start = time.perf_counter()
        reports: dict[str, DetectionReport] = {}
        sightings: list[tuple[np.ndarray, float, int]] = []  # team-frame centre, sigma, inliers
        for name, cloud in clouds.items():
            if name not in CAMERAS:
                raise ValueError(f"no camera named {name!r}; cameras: {', '.join(CAMERAS)}")
            report = detect_ball(cloud, self.radius, self.params.detection, self.rng)
            reports[name] = report
            if report.detection is not None and pose is not None:
                body = self.params.mounts.by_name(name).to_body(report.detection.centre[None, :])
                team = body_to_team(body, pose.x, pose.y, pose.theta)[0]
                sightings.append((team, report.detection.sigma, report.detection.inliers))
        detected = time.perf_counter()
        times = {"detect": detected - start}
        if not sightings:
            if pose is None and any(r.detection is not None for r in reports.values()):
                reason = "seen, but no self-localization yet"
            else:
                reason = "; ".join(f"{n}: {r.reason}" for n, r in reports.items()) or "no cloud"
            times["track"] = 0.0
            return KinectResult(stamp, None, reason, None, reports, times)
        centre, sigma = self._fuse(sightings)
        percept = self.tracker.add(Sighting(stamp, float(centre[0]), float(centre[1]), float(centre[2]), sigma))
        touchdown = self.tracker.touchdown(percept)
        times["track"] = time.perf_counter() - detected
        return KinectResult(stamp, percept, "", touchdown, reports, times)

    def _fuse(self, sightings: list[tuple[np.ndarray, float, int]]) -> tuple[np.ndarray, float]:
        if len(sightings) == 1:
            return sightings[0][0], sightings[0][1]
        (a, sa, na), (b, sb, nb) = sightings[:2]
        if float(np.linalg.norm(a - b)) > self.params.fusion_distance:
            return (a, sa) if na >= nb else (b, sb)
        wa, wb = 1.0 / (sa * sa), 1.0 / (sb * sb)
        return (wa * a + wb * b) / (wa + wb), 1.0 / math.sqrt(wa + wb)
