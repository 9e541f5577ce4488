"""The ball in front-camera images: segmentation, region growing, the tangent cone, the ground point, and every
way of not knowing (nothing seen, partly out of view, in the air, not a ball)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from front_vision.ball import BallLocator, BallParams, Sighting, fit_tangent_cone
from front_vision.pipeline import FrontVision
from nubot_common.camera_model import load_camera
from nubot_common.color_class import ColorClass

from .scenes import CAMERA, CAMERA_FILE, render_ball, render_empty, table


@pytest.fixture(scope="module")
def locator() -> BallLocator:
    return BallLocator(CAMERA, table())


@pytest.mark.parametrize(("bx", "by", "tolerance"), [(0.75, 0.0, 0.01), (1.0, 0.3, 0.01), (1.2, -0.4, 0.01),
                                                     (1.5, 0.0, 0.01), (1.4, 0.5, 0.01), (2.5, 0.4, 0.03)])
def test_a_ball_on_the_ground_is_found_within_a_centimetre_up_to_1_5_m(locator: BallLocator, bx: float, by: float,
                                                                      tolerance: float) -> None:
    sighting = locator.locate(render_ball(bx, by))
    assert sighting.sighting is Sighting.SEEN
    assert math.hypot(sighting.x - bx, sighting.y - by) < tolerance  # [m], through the true camera


def test_the_calibrated_camera_finds_it_within_two_centimetres() -> None:
    vision = FrontVision(load_camera(CAMERA_FILE), table())
    for bx, by in [(0.8, 0.2), (1.1, -0.3), (1.5, 0.1)]:
        result = vision.process(3.0, render_ball(bx, by, seed=7))
        assert result.percept is not None and result.percept.stamp == 3.0
        assert math.hypot(result.percept.x - bx, result.percept.y - by) < 0.02


def test_region_growing_takes_the_whole_shaded_ball_and_nothing_else(locator: BallLocator) -> None:
    image = render_ball(1.0, 0.0, noise_std=0.0)
    sighting = locator.locate(image)
    ball = table().classify_rgb(image) == ColorClass.BALL
    assert sighting.pixels == pytest.approx(int(ball.sum()), rel=0.02)
    u, v = sighting.pixel
    assert ball[int(round(v)), int(round(u))], "the centre's ray lies inside the region"


def test_the_centre_ray_is_the_cone_axis_not_the_blob_centroid(locator: BallLocator) -> None:
    """Off the optical axis a sphere's image is an ellipse whose centroid lies outwards of its centre's image."""
    bx, by = 1.0, 0.5
    image = render_ball(bx, by, noise_std=0.0)
    sighting = locator.locate(image)
    truth, _ = CAMERA.project(np.array([[bx, by, 0.11]]))
    rows, cols = np.nonzero(table().classify_rgb(image) == ColorClass.BALL)
    centroid = np.array([cols.mean(), rows.mean()])
    assert np.hypot(*(np.array(sighting.pixel) - truth[0])) < 0.3  # [px]
    assert np.hypot(*(centroid - truth[0])) > 1.0  # the centroid would be wrong by more than a pixel


def test_the_tangent_cone_fit_recovers_axis_and_angle() -> None:
    axis = np.array([0.2, -0.1, 1.0]) / np.linalg.norm([0.2, -0.1, 1.0])
    side = np.cross(axis, [0.0, 1.0, 0.0])
    side /= np.linalg.norm(side)
    up = np.cross(axis, side)
    psi = np.linspace(0.0, 2.0 * math.pi, 50, endpoint=False)
    alpha = 0.1
    rays = math.cos(alpha) * axis + math.sin(alpha) * (np.outer(np.cos(psi), side) + np.outer(np.sin(psi), up))
    cone = fit_tangent_cone(rays)
    assert cone is not None
    np.testing.assert_allclose(cone.axis, axis, atol=1e-9)
    assert cone.half_angle == pytest.approx(alpha, abs=1e-9)
    assert fit_tangent_cone(rays[:2]) is None


def test_nothing_seen(locator: BallLocator) -> None:
    sighting = locator.locate(render_empty())
    assert sighting.sighting is Sighting.NOT_SEEN and not sighting.known and math.isnan(sighting.x)


@pytest.mark.parametrize(("bx", "by"), [(0.5, 0.0), (1.0, 0.6), (1.0, -0.6)])
def test_a_ball_partly_out_of_view_is_not_known(locator: BallLocator, bx: float, by: float) -> None:
    sighting = locator.locate(render_ball(bx, by))
    assert sighting.sighting is Sighting.OUT_OF_VIEW and not sighting.known


def test_a_ball_in_the_air_is_not_taken_for_one_on_the_ground(locator: BallLocator) -> None:
    sighting = locator.locate(render_ball(1.4, 0.0, z=0.3))
    assert sighting.sighting is Sighting.IMPLAUSIBLE and not sighting.known
    on_ground = locator.locate(render_ball(1.4, 0.0))
    assert on_ground.known


def test_a_ball_behind_a_robot_edge_and_a_robot_nearby(locator: BallLocator) -> None:
    sighting = locator.locate(render_ball(1.0, -0.1, others=((1.6, 0.4),)))
    assert sighting.known and math.hypot(sighting.x - 1.0, sighting.y + 0.1) < 0.01


def test_small_orange_specks_are_noise() -> None:
    image = render_empty()
    image[100:103, 100:103] = (245, 110, 20)
    assert BallLocator(CAMERA, table(), BallParams(min_pixels=20)).locate(image).sighting is Sighting.NOT_SEEN


def test_an_orange_square_is_no_ball(locator: BallLocator) -> None:
    image = render_empty()
    image[80:130, 100:200] = (245, 110, 20)
    assert locator.locate(image).sighting is Sighting.IMPLAUSIBLE


def test_in_darker_light_the_shaded_underside_the_table_does_not_know_joins_the_region(locator: BallLocator) -> None:
    """Where the field's light is dim, the table knows only the ball's lit top; region growing takes the rest."""
    from sim_visual.world import BallState, RobotState

    from .scenes import renderer

    me = RobotState(4.0713, -0.7362, 1.7623, 0.0, 0.0, 0.0)
    ball = BallState(3.8823, 0.0651, 0.11, 0.0, 0.0, 0.0)
    image = renderer().render(me, ball, [], 45.0, np.random.default_rng(3))  # the dimmest time of the light
    known = int((table().classify_rgb(image) == ColorClass.BALL).sum())
    sighting = locator.locate(image)
    c, s = math.cos(me.theta), math.sin(me.theta)
    bx, by = c * (ball.x - me.x) + s * (ball.y - me.y), -s * (ball.x - me.x) + c * (ball.y - me.y)
    assert sighting.known and sighting.pixels > 1.5 * known
    assert math.hypot(sighting.x - bx, sighting.y - by) < 0.01
