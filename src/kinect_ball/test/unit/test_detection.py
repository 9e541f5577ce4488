"""Unit tests of kinect_ball.detection: the RANSAC sphere fit of the known radius (with outliers, few points),
candidate clusters, bad clouds and a ball partly out of view."""

import numpy as np
import pytest

from kinect_ball.detection import DetectionParams, detect_ball, fit_sphere, sphere_hypotheses
from nubot_common.clouds import Cloud

from .scenes import RADIUS, cap_points, render

P = DetectionParams()


@pytest.mark.parametrize("seed", range(5))
def test_three_exact_points_give_the_true_sphere_among_at_most_two(seed):
    """Two spheres of the radius pass through three points; the one the camera could not see them on is dropped
    where it is clearly hidden, and the scoring over all points picks between the rest."""
    rng = np.random.default_rng(seed)
    centre = np.array([3.0, 0.4, 0.2])
    hyp = sphere_hypotheses(cap_points(centre, 3, 0.0, rng), RADIUS, np.array([[0, 1, 2]]))
    assert hyp.shape == (2, 3)
    assert np.nanmin(np.linalg.norm(hyp - centre, axis=1)) < 1e-9


def test_a_triple_wider_than_the_ball_gives_no_hypothesis():
    points = np.array([[3.0, 0.0, 0.0], [3.0, 0.5, 0.0], [3.0, 0.0, 0.5]])
    assert np.isnan(sphere_hypotheses(points, RADIUS, np.array([[0, 1, 2]]))).all()


@pytest.mark.parametrize("seed", range(5))
def test_the_fit_holds_with_a_third_of_outliers(seed):
    rng = np.random.default_rng(seed)
    centre = np.array([3.0, -0.5, 0.4])
    ball = cap_points(centre, 40, 0.004, rng)
    outliers = centre + rng.uniform(-0.3, 0.3, (20, 3))
    fit = fit_sphere(np.vstack([ball, outliers]), RADIUS, P.inlier_band(3.0), P.iterations, P.refine_steps, rng)
    assert fit is not None
    assert np.linalg.norm(fit.centre - centre) < 0.01
    assert 38 <= fit.inliers <= 50, "the ball's points in, most outliers out"


def test_a_far_ball_with_a_handful_of_points_is_found_within_a_few_centimetres():
    rng = np.random.default_rng(3)
    centre = np.array([7.5, 1.0, 0.8])
    fit = fit_sphere(cap_points(centre, 5, 0.015, rng, 40.0), RADIUS, P.inlier_band(7.5), P.iterations,
                     P.refine_steps, rng)
    assert fit is not None and np.linalg.norm(fit.centre - centre) < 0.05


def test_fewer_than_three_points_give_no_fit():
    assert fit_sphere(np.zeros((2, 3)), RADIUS, 0.01, 10, 2, np.random.default_rng(0)) is None


def test_the_ball_in_a_rendered_frame():
    centre = (3.0, 0.3, 0.2)
    report = detect_ball(render([centre]), RADIUS, P, np.random.default_rng(0))
    assert report.detection is not None and report.reason == ""
    assert np.linalg.norm(report.detection.centre - centre) < 0.01
    assert not report.detection.touches_border


def test_two_balls_give_the_one_with_more_support():
    report = detect_ball(render([(2.0, 0.5, 0.0), (6.0, -1.0, 0.3)]), RADIUS, P, np.random.default_rng(0))
    assert report.clusters == 2
    assert np.linalg.norm(report.detection.centre - (2.0, 0.5, 0.0)) < 0.01


def test_an_orange_blob_wider_than_a_ball_is_refused_with_its_reason():
    rng = np.random.default_rng(0)
    yy, zz = np.meshgrid(np.arange(-0.5, 0.5, 0.03), np.arange(-0.5, 0.5, 0.03))
    wall = np.column_stack([np.full(yy.size, 3.0), yy.ravel(), zz.ravel()])
    cloud = Cloud(wall, np.tile(np.array([245, 110, 20], np.uint8), (len(wall), 1)), (1, len(wall)))
    report = detect_ball(cloud, RADIUS, P, rng)
    assert report.detection is None and "wide" in report.reason


@pytest.mark.parametrize("cloud, reason", [
    (Cloud(np.zeros((0, 3)), np.zeros((0, 3), np.uint8), (0, 0)), "empty cloud"),
    (Cloud(np.full((50, 3), np.nan), np.full((50, 3), 200, np.uint8), (5, 10)), "no finite points"),
    (render([]), "0 orange points in range"),
])
def test_a_cloud_without_a_ball_says_why(cloud, reason):
    report = detect_ball(cloud, RADIUS, P, np.random.default_rng(0))
    assert report.detection is None and report.reason == reason


def test_orange_points_with_nan_coordinates_are_ignored():
    cloud = render([(3.0, 0.0, 0.0)])
    points = cloud.points.copy()
    orange = cloud.rgb[:, 0] > 200
    points[orange] = np.nan
    report = detect_ball(Cloud(points, cloud.rgb, cloud.shape), RADIUS, P, np.random.default_rng(0))
    assert report.detection is None


@pytest.mark.parametrize("y", [0.71, 0.76, 0.80])
def test_a_ball_partly_out_of_view_is_found_or_refused_never_wrong(y):
    """At 1 m the image's left edge is 0.71 m to the side: the ball half out of view, then mostly out."""
    centre = np.array([1.0, y, 0.0])
    report = detect_ball(render([centre], dropout=0.05, seed=2), RADIUS, P, np.random.default_rng(0))
    if report.detection is None:
        assert report.reason
    else:
        assert report.detection.touches_border
        assert np.linalg.norm(report.detection.centre - centre) < 0.02


def test_parameters_are_checked():
    with pytest.raises(ValueError, match="min_points must be at least 3"):
        DetectionParams(min_points=2)
    with pytest.raises(ValueError, match="min_red must lie in"):
        DetectionParams(min_red=300)
