"""FrontVision: one frame in, a BallPercept in the body frame or a clear 'not known' out; bad frames refused."""

from __future__ import annotations

import numpy as np
import pytest

from front_vision import FrontVisionError
from front_vision.ball import BallParams, Sighting
from front_vision.pipeline import FrontVision, FrontVisionParams, check_frame

from .scenes import CAMERA, render_ball, render_empty, table


@pytest.fixture(scope="module")
def vision() -> FrontVision:
    return FrontVision(CAMERA, table())


def test_a_seen_ball_is_a_body_frame_percept(vision: FrontVision) -> None:
    result = vision.process(12.5, render_ball(1.2, 0.2))
    assert result.sighting.sighting is Sighting.SEEN
    assert result.percept is not None
    assert (result.percept.x, result.percept.y) == pytest.approx((1.2, 0.2), abs=0.01)
    assert not result.percept.velocity_known and result.stamp == 12.5


@pytest.mark.parametrize(("image", "sighting"), [(render_empty(), Sighting.NOT_SEEN),
                                                 (render_ball(0.5, 0.0), Sighting.OUT_OF_VIEW)])
def test_not_known_has_no_percept(vision: FrontVision, image: np.ndarray, sighting: Sighting) -> None:
    result = vision.process(1.0, image)
    assert result.percept is None and result.sighting.sighting is sighting


@pytest.mark.parametrize(("image", "message"), [
    (np.zeros((0, 0, 3), np.uint8), "empty"),
    (np.full((240, 320, 3), np.nan, np.float32), "uint8 RGB, got float32 with NaN"),
    (np.zeros((240, 320, 3), np.float64), "uint8 RGB, got float64"),
    (np.zeros((480, 640, 3), np.uint8), "320 x 240 px"),
    (np.zeros((240, 320), np.uint8), "shape"),
    ([[0, 0, 0]], "numpy array"),
])
def test_a_bad_frame_is_refused_saying_why(vision: FrontVision, image: object, message: str) -> None:
    with pytest.raises(FrontVisionError, match=message):
        vision.process(1.0, image)


def test_a_read_only_frame_is_copied_not_refused() -> None:
    image = render_ball(1.0, 0.0)
    image.flags.writeable = False
    frame = check_frame(image, CAMERA)
    assert frame.flags.writeable and np.array_equal(frame, image)


def test_black_and_saturated_frames_see_nothing(vision: FrontVision) -> None:
    for level in (0, 255):
        result = vision.process(1.0, np.full((240, 320, 3), level, np.uint8))
        assert result.percept is None


@pytest.mark.parametrize(("change", "message"), [({"seed_step": 0}, "seed_step"),
                                                 ({"area_ratio_range": (1.2, 2.0)}, "area_ratio_range")])
def test_bad_parameters_are_refused(change: dict, message: str) -> None:
    with pytest.raises(FrontVisionError, match=message):
        FrontVisionParams(BallParams(**change))
