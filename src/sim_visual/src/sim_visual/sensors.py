"""The robots' own simulated sensors: the omni camera, wheel odometry, the inertial heading and the goalie's RGB-D
cameras.

Requires: the match's ``WorldDescription``, ``SensorParams`` (the mirror the camera looks through, the
camera's rendering, the odometry's and the inertial sensor's errors) and the simulator's seed; then, per
reading, the true states from the simulator. Provides: ``RobotSensors`` with ``camera`` (a
``RenderedFrame``), ``odometry`` (an ``OdometryReading``), ``inertial_heading`` (an ``ImuReading``) and ``rgbd``
(both RGB-D cameras' ``RgbdFrame``), ``front_camera`` (a regular robot's front camera image, RGB), keeping each
robot's odometry and inertial state. The robots that see through the camera get these instead of the
simulator's percepts (``Simulator.observe``); omni_vision turns them into percepts.

Randomness: one generator of its own, derived from the simulator's seed (``SeedSequence([seed, 1])``), so
switching one robot to the camera changes no other robot's percept noise; the RGB-D and the front cameras draw
from generators of their own (``SeedSequence([seed, 1, 2])``, ``[seed, 1, 3]``), so rendering them only while
someone listens (the simulator node) changes no other sensor's noise.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from dataclasses import field as dc_field
from typing import TYPE_CHECKING

import numpy as np

from nubot_common.mirror import MirrorModel
from nubot_common.world_description import WorldDescription
from sim_visual.camera_params import OmniCameraParams
from sim_visual.front_camera_params import FrontCameraParams
from sim_visual.odometry import (
    ImuParams,
    ImuReading,
    InertialHeading,
    OdometryParams,
    OdometryReading,
    WheelOdometry,
    body_velocity,
)
from sim_visual.rgbd_camera import RgbdCameraParams, RgbdCameraRenderer, RgbdFrame
from sim_visual.world import BallState, RobotState

if TYPE_CHECKING:  # the renderer (OpenCV) is imported on the first frame, not by every simulator
    from sim_visual.front_camera import FrontCameraRenderer
    from sim_visual.omni_camera import OmniCameraRenderer, RenderedFrame

SENSOR_STREAM = 1  # the sensors' generator: SeedSequence([seed, SENSOR_STREAM])
RGBD_STREAM = 2  # the RGB-D cameras' generator: SeedSequence([seed, SENSOR_STREAM, RGBD_STREAM])
FRONT_STREAM = 3  # the front cameras' generator: SeedSequence([seed, SENSOR_STREAM, FRONT_STREAM])


@dataclass(frozen=True)
class SensorParams:
    mirror: MirrorModel = dc_field(default_factory=MirrorModel)  # the camera's true mirror
    camera: OmniCameraParams = dc_field(default_factory=OmniCameraParams)
    odometry: OdometryParams = dc_field(default_factory=OdometryParams)
    imu: ImuParams = dc_field(default_factory=ImuParams)
    rgbd: RgbdCameraParams = dc_field(default_factory=RgbdCameraParams)  # the goalie's two RGB-D cameras
    front_camera: FrontCameraParams = dc_field(default_factory=FrontCameraParams)  # a regular robot's front camera


class RobotSensors:
    def __init__(self, world: WorldDescription, params: SensorParams, seed: int):
        self.world, self.params = world, params
        self.rng = np.random.default_rng(np.random.SeedSequence([seed, SENSOR_STREAM]))
        self.rgbd_rng = np.random.default_rng(np.random.SeedSequence([seed, SENSOR_STREAM, RGBD_STREAM]))
        self.front_rng = np.random.default_rng(np.random.SeedSequence([seed, SENSOR_STREAM, FRONT_STREAM]))
        self._renderer: OmniCameraRenderer | None = None  # built on the first frame (about 0.1 s)
        self._rgbd: RgbdCameraRenderer | None = None  # built on the first RGB-D frame
        self._front: FrontCameraRenderer | None = None  # built on the first front camera frame (about 0.7 s)
        self._odometry: dict[str, WheelOdometry] = {}
        self._imu: dict[str, InertialHeading] = {}

    @property
    def renderer(self) -> OmniCameraRenderer:
        if self._renderer is None:
            from sim_visual.omni_camera import OmniCameraRenderer

            self._renderer = OmniCameraRenderer(self.world, self.params.mirror, self.params.camera)
        return self._renderer

    def camera(self, t: float, me: RobotState, ball: BallState, others: Sequence[RobotState],
               labels: bool = False) -> RenderedFrame:
        """The image robot ``me`` sees at ``t`` [s] (and its per-pixel colour classes with ``labels``)."""
        return self.renderer.render(me, ball, others, t, self.rng, labels)

    def rgbd(self, t: float, me: RobotState, ball: BallState,
             others: Sequence[RobotState]) -> tuple[RgbdFrame, RgbdFrame]:
        """The point clouds robot ``me``'s left and right RGB-D cameras see at ``t`` [s]."""
        if self._rgbd is None:
            self._rgbd = RgbdCameraRenderer(self.world, self.params.rgbd)
        return self._rgbd.render(me, ball, others, t, self.rgbd_rng)

    def front_camera(self, t: float, me: RobotState, ball: BallState, others: Sequence[RobotState]) -> np.ndarray:
        """The RGB image robot ``me``'s front camera sees at ``t`` [s] (front_vision reads it)."""
        if self._front is None:
            from sim_visual.front_camera import FrontCameraRenderer

            self._front = FrontCameraRenderer(self.world, self.params.front_camera, self.params.camera)
        return self._front.render(me, ball, others, t, self.front_rng)

    def odometry(self, name: str, state: RobotState, dt: float, stuck: bool) -> OdometryReading:
        """Robot ``name``'s wheel odometry over the last ``dt`` [s]."""
        sensor = self._odometry.setdefault(name, WheelOdometry(self.params.odometry))
        vx, vy, w = body_velocity(state)
        return sensor.measure(vx, vy, w, dt, stuck, self.rng)

    def inertial_heading(self, name: str, team_heading: float, w: float, dt: float) -> ImuReading:
        """Robot ``name``'s inertial heading (true heading ``team_heading`` [rad] in its team frame)."""
        sensor = self._imu.setdefault(name, InertialHeading(self.params.imu))
        return sensor.measure(team_heading, w, dt, self.rng)

    def forget(self, name: str) -> None:
        """Drop robot ``name``'s sensor state (deleted, or reset)."""
        self._odometry.pop(name, None)
        self._imu.pop(name, None)

    def reset(self) -> None:
        self._odometry.clear()
        self._imu.clear()
