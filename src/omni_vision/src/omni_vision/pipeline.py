"""One robot's omni vision, frame by frame: camera image, odometry and inertial heading in; percepts out.

Requires: the match's ``WorldDescription`` (the field's lines, the ball's and the robots' radii), the
``OmniVisionParams`` (config/omni_vision.yaml), a calibrated ``ColorTable`` and the robot's AgentID; then,
as they arrive, wheel odometry (``odometry``: body-frame velocity, ~50 Hz), the inertial heading
(``inertial``: team frame, 0 facing the goal the team attacks) and camera frames (``process``: RGB).
Provides: ``OmniVision.process`` -> ``VisionFrame``: the ``RobotView`` world_model reads (the robot's
pose from self-localization, its velocity from odometry, the ball and the obstacles placed on the field, none
inside a goal: its dark ground is no robot; all in the team frame) plus what the debug image and the
benchmarks show (line points, detections, the localization estimate, each stage's time).

The stages, in order: read the frame along the radial scan lines (colour classes through the table);
white line points; the ball; the obstacles; self-localization (odometry prediction, line matching,
Kalman fusion, global search while not localized). Whether the robot holds the ball is what its ball
handler says (``ball_holding``: the base driver's signal); without a recent one, the vision's guess: the
ball in front within ``holding_distance`` and ``holding_angle`` (a free ball lying there reads as held).
The robot is ``valid`` while localized and on the field with its border.
"""

from __future__ import annotations

import math
import time
from dataclasses import dataclass, replace
from dataclasses import field as dc_field

import numpy as np

from nubot_common.geometry import Pose2D, rotate
from nubot_common.mirror import MirrorModel
from nubot_common.percepts import BallPercept, RobotReport, RobotView
from nubot_common.world_description import WorldDescription
from omni_vision import OmniVisionError
from omni_vision.colors import ColorTable
from omni_vision.lines import LineParams, LinePoints, LineScanner
from omni_vision.localization import LocalizationEstimate, LocalizationParams, SelfLocator
from omni_vision.objects import (
    BallDetection,
    BallDetector,
    BallParams,
    ObstacleDetection,
    ObstacleDetector,
    ObstacleParams,
)


@dataclass(frozen=True)
class OmniVisionParams:
    mirror: MirrorModel = dc_field(default_factory=MirrorModel)
    lines: LineParams = dc_field(default_factory=LineParams)
    ball: BallParams = dc_field(default_factory=BallParams)
    obstacles: ObstacleParams = dc_field(default_factory=ObstacleParams)
    localization: LocalizationParams = dc_field(default_factory=LocalizationParams)
    holding_distance: float = 0.6  # [m] a ball centre this close in front is in the grabber
    holding_angle_deg: float = 20.0  # [deg] either side of the front
    heading_timeout: float = 0.5  # [s] an older inertial heading is not used
    holding_timeout: float = 0.5  # [s] an older ball handler signal is not used

    def __post_init__(self) -> None:
        for name in ("holding_distance", "holding_angle_deg", "heading_timeout", "holding_timeout"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0.0):
                raise ValueError(f"{name} must be positive, got {value}")


@dataclass(frozen=True)
class VisionFrame:
    view: RobotView  # what world_model reads (team frame)
    estimate: LocalizationEstimate
    lines: LinePoints  # body frame, with their pixels
    ball: BallDetection | None  # body frame
    obstacles: tuple[ObstacleDetection, ...]  # body frame
    classes: np.ndarray  # ColorClass of each scan-ray sample (ray_count x samples), for the debug image
    timings: dict[str, float]  # [s] per stage: sample, lines, ball, obstacles, localization, total

    @property
    def localized(self) -> bool:
        return self.estimate.localized


class OmniVision:
    def __init__(self, world: WorldDescription, params: OmniVisionParams, table: ColorTable, agent_id: int):
        if agent_id < 1:
            raise OmniVisionError(f"agent_id must be an AgentID from 1, got {agent_id}")
        # The field, the ball and the robots have one home, the world description: it overrides the config.
        self.params = params
        self.world = world
        self.table = table
        self.agent_id = agent_id
        self.mirror = params.mirror
        self.scanner = LineScanner(self.mirror, replace(params.lines, line_width=world.field.line_width))
        self.ball_detector = BallDetector(self.scanner.rays, replace(params.ball, ball_radius=world.ball.radius))
        self.obstacle_detector = ObstacleDetector(self.scanner.rays,
                                                  replace(params.obstacles, robot_radius=world.robot.radius))
        self.locator = SelfLocator(world.field, params.localization)
        self._velocity = (0.0, 0.0, 0.0)  # latest odometry, body frame [m/s, m/s, rad/s]
        self._stuck = False
        self._heading: tuple[float, float] | None = None  # (t [s], team-frame heading [rad])
        self._holding: tuple[float, bool] | None = None  # (t [s], the ball handler holds the ball)

    def reset(self, pose: Pose2D | None = None) -> None:
        """Forget the pose (or start tracking at ``pose``): the next frames localize globally."""
        self.locator.reset(pose)

    def odometry(self, t: float, vx: float, vy: float, w: float, stuck: bool = False) -> None:
        """Wheel odometry at ``t`` [s]: body-frame velocity [m/s], [rad/s]; the pose is predicted with it."""
        if not all(math.isfinite(v) for v in (t, vx, vy, w)):
            raise OmniVisionError(f"odometry must be finite, got t {t}, ({vx}, {vy}, {w})")
        self._velocity = (vx, vy, w)
        self._stuck = bool(stuck)
        self.locator.predict(t, vx, vy, w)

    def inertial(self, t: float, heading: float) -> None:
        """The inertial sensor's heading [rad] at ``t`` [s], in the team frame."""
        if not (math.isfinite(t) and math.isfinite(heading)):
            raise OmniVisionError(f"the inertial heading must be finite, got {heading} at {t}")
        self._heading = (t, heading)

    def ball_holding(self, t: float, holding: bool) -> None:
        """The ball handler's signal at ``t`` [s]: it holds the ball (the base driver's report)."""
        if not math.isfinite(t):
            raise OmniVisionError(f"the ball handler's time must be finite, got {t}")
        self._holding = (t, bool(holding))

    def process(self, t: float, image: np.ndarray) -> VisionFrame:
        """One camera frame taken at ``t`` [s] (RGB, the mirror model's size; OmniVisionError if unusable)."""
        clock = time.perf_counter
        start = clock()
        samples = self.scanner.rays.sample(image, self.table)
        t_sample = clock()
        lines = self.scanner.scan(samples)
        t_lines = clock()
        ball = self.ball_detector.detect(samples, self.table)
        t_ball = clock()
        obstacles = tuple(self.obstacle_detector.detect(samples))
        t_obstacles = clock()
        heading = None
        if self._heading is not None and abs(t - self._heading[0]) <= self.params.heading_timeout:
            heading = self._heading[1]
        estimate = self.locator.correct(t, lines.points, heading)
        end = clock()
        timings = {"sample": t_sample - start, "lines": t_lines - t_sample, "ball": t_ball - t_lines,
                   "obstacles": t_obstacles - t_ball, "localization": end - t_obstacles, "total": end - start}
        return VisionFrame(self._view(t, estimate, ball, obstacles), estimate, lines, ball, obstacles,
                           samples.classes, timings)

    def _view(self, t: float, estimate: LocalizationEstimate, ball: BallDetection | None,
              obstacles: tuple[ObstacleDetection, ...]) -> RobotView:
        pose = estimate.pose
        vx, vy, w = self._velocity
        tvx, tvy = rotate(vx, vy, pose.theta)
        field = self.world.field
        if self._holding is not None and abs(t - self._holding[0]) <= self.params.holding_timeout:
            holding = self._holding[1]
        else:
            holding = ball is not None and math.hypot(ball.x, ball.y) <= self.params.holding_distance and \
                abs(math.atan2(ball.y, ball.x)) <= math.radians(self.params.holding_angle_deg)
        valid = estimate.localized and field.is_inside(pose.x, pose.y, field.border)
        robot = RobotReport(self.agent_id, pose, tvx, tvy, w, valid=valid, stuck=self._stuck, holding=holding)
        percept = None
        if ball is not None and estimate.localized:
            percept = BallPercept(t, *pose.to_world(ball.x, ball.y))
        seen: tuple[tuple[float, float], ...] = ()
        if estimate.localized:  # the dark ground inside a goal is black too, but no robot
            seen = tuple(p for p in (pose.to_world(o.x, o.y) for o in obstacles)
                         if not field.in_goal(p[0], p[1], self.world.robot.radius))
        return RobotView(t, robot, percept, seen)
