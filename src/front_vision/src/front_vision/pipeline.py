"""One front-camera frame: image in, the near ball relative to the robot out (chapter 4.2).

Requires: the calibrated ``PinholeCamera`` (``camera_model.load_camera``), omni_vision's ``ColorTable`` and
``FrontVisionParams`` (config/front_vision.yaml). Provides ``FrontVision.process(t, rgb) -> FrontBallResult``:
``percept`` is a ``nubot_common.percepts.BallPercept`` whose (x, y) [m] is the ball's centre in the robot's
body frame (x ahead, y left; no velocity: the world model fits one), or None when the ball is not known
(not seen, partly out of view, not on the ground); ``sighting`` says which. ``check_frame`` is the one entry
check of a frame: anything but a non-empty uint8 RGB array of the camera's size raises ``FrontVisionError``
saying why (so a NaN-filled float image, an empty one or one of another size is refused, never processed).
"""

from __future__ import annotations

from dataclasses import dataclass
from dataclasses import field as dc_field

import numpy as np

from front_vision import FrontVisionError
from front_vision.ball import BallLocator, BallParams, BallSighting, Sighting
from nubot_common.camera_model import PinholeCamera
from nubot_common.percepts import BallPercept
from nubot_common.world_description import WorldDescription
from omni_vision.colors import ColorTable


@dataclass(frozen=True)
class FrontVisionParams:
    ball: BallParams = dc_field(default_factory=BallParams)


@dataclass(frozen=True)
class FrontBallResult:
    stamp: float  # [s] the frame's time
    sighting: BallSighting
    percept: BallPercept | None  # body frame [m]; None: not known


def check_frame(image: object, camera: PinholeCamera) -> np.ndarray:
    """``image`` as a C-contiguous, writable uint8 RGB array if it is a usable frame of ``camera``; else raise
    ``FrontVisionError`` saying why."""
    if not isinstance(image, np.ndarray):
        raise FrontVisionError(f"the image must be a numpy array, got {type(image).__name__}")
    if image.size == 0:
        raise FrontVisionError(f"the image is empty (shape {image.shape})")
    if image.dtype != np.uint8:
        detail = " with NaN" if image.dtype.kind == "f" and bool(np.isnan(image).any()) else ""
        raise FrontVisionError(f"the image must be uint8 RGB, got {image.dtype}{detail}")
    expected = (camera.height, camera.width, 3)
    if image.shape != expected:
        raise FrontVisionError(f"the image must be RGB of {camera.width} x {camera.height} px (the calibrated "
                               f"camera's; shape {expected}), got shape {image.shape}")
    if image.flags.c_contiguous and image.flags.writeable:
        return image
    return np.array(image, order="C", copy=True)


class FrontVision:
    """The front camera's vision of one robot: stateless from frame to frame."""

    def __init__(self, camera: PinholeCamera, table: ColorTable, params: FrontVisionParams | None = None,
                 world: WorldDescription | None = None):
        self.camera = camera
        self.params = params if params is not None else FrontVisionParams()
        self.world = world if world is not None else WorldDescription()
        self.locator = BallLocator(camera, table, self.params.ball, self.world.ball.radius)

    def process(self, t: float, image: object) -> FrontBallResult:
        """The ball in the frame ``image`` taken at ``t`` [s]; raise ``FrontVisionError`` for a bad frame."""
        rgb = check_frame(image, self.camera)
        sighting = self.locator.locate(rgb)
        percept = BallPercept(t, sighting.x, sighting.y) if sighting.sighting is Sighting.SEEN else None
        return FrontBallResult(t, sighting, percept)
