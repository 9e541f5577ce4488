"""The ball and the obstacles, and the whole frame's chain on frames the vision must refuse or find empty."""

import math

import cv2
import numpy as np
import pytest

from nubot_common.color_class import ColorClass
from nubot_common.mirror import MirrorModel
from omni_vision import OmniVisionError
from omni_vision.lines import LineScanner, ScanRays
from omni_vision.objects import (
    BallDetector,
    BallParams,
    ObstacleDetector,
    ObstacleParams,
    ball_centre_distance,
    ball_far_distance,
)

from .scenes import BALL_RADIUS, BALL_RGB, Scene, calibrated_table, field_scene, render

MIRROR = MirrorModel()
RAYS = ScanRays(MIRROR)


def _detect(scene, paint=None, obstacles=None, labels=None):
    """Ball and obstacles of the rendered ``scene`` (``paint`` may draw on the image first; ``labels``, a list,
    receives the label image)."""
    image, truth = render(MIRROR, scene)
    if paint is not None:
        paint(image)
    if labels is not None:
        labels.append(truth)
    table = calibrated_table(MIRROR)
    samples = RAYS.sample(image, table)
    return BallDetector(RAYS).detect(samples, table), (obstacles or ObstacleDetector(RAYS)).detect(samples)


@pytest.mark.parametrize("ball", [(2.0, 0.0), (0.0, -3.0), (4.0, 4.0), (0.7, 0.3), (-6.0, 2.0)])
@pytest.mark.parametrize("seed", [0, 1])
def test_a_ball_on_the_ground_is_found_within_5_percent_of_its_distance(ball, seed):
    """A ball lying at (2, 0), (0, -3), (4, 4), (0.7, 0.3) or (-6, 2) m among field lines, under varying light, is
    reported within 5 % of its distance, its pixel (the blob's centroid) on the ball's image."""
    pose = (-1.0 + seed, 0.5, 0.4 * seed)
    c, s = math.cos(pose[2]), math.sin(pose[2])
    world = (pose[0] + c * ball[0] - s * ball[1], pose[1] + s * ball[0] + c * ball[1])
    labels: list[np.ndarray] = []
    found, _ = _detect(field_scene(pose, balls=(world,), seed=seed, light_phase=2.0 * seed), labels=labels)
    distance = math.hypot(*ball)
    assert found is not None
    assert math.hypot(found.x - ball[0], found.y - ball[1]) <= 0.05 * distance, (found.x, found.y)
    assert labels[0][round(found.pixel[1]), round(found.pixel[0])] == ColorClass.BALL
    assert found.confidence >= 0.6


def test_the_ball_radius_correction_inverts_the_tangent_geometry():
    """A sphere of radius R on the ground at D: its near tangent ray from the viewpoint meets the ground where
    ball_centre_distance gives D back; its far tangent ray where ball_far_distance says (traced numerically)."""
    h = MIRROR.viewpoint_height
    for big_d in (0.5, 1.0, 2.0, 5.0, 9.0):
        grounds = np.linspace(0.0, 40.0, 400001)
        # a ray from (0, h) to (g, 0) misses the ball when the ball centre (D, R) is farther than R from it
        miss = np.abs(h * big_d + grounds * BALL_RADIUS - h * grounds) / np.hypot(h, grounds) > BALL_RADIUS
        hits = grounds[~miss]
        assert ball_centre_distance(hits.min(), BALL_RADIUS, h) == pytest.approx(big_d, abs=2e-4)
        assert ball_far_distance(big_d, BALL_RADIUS, h) == pytest.approx(hits.max(), abs=2e-4)


def test_no_ball_gives_none():
    """Lines and robots but no ball: no ball."""
    found, _ = _detect(field_scene((2.0, -1.0, 1.0), robots=((3.0, -1.5), (1.0, 0.5)), seed=3))
    assert found is None


@pytest.mark.parametrize("paint", [
    lambda image: cv2.rectangle(image, (300, 100), (301, 101), BALL_RGB, -1),  # a speck: too small
    lambda image: cv2.line(image, (330, 200), (400, 130), BALL_RGB, 3),  # a stripe: far too long for its width
    lambda image: cv2.circle(image, (350, 300), 40, BALL_RGB, -1),  # a disc: far too big at its distance
])
def test_ball_coloured_shapes_of_the_wrong_size_are_no_ball(paint):
    """A 2 x 2 px speck, a 3 px wide stripe and a 80 px disc in the ball's colour are refused: no ball."""
    found, _ = _detect(Scene(seed=4), paint)
    assert found is None


def test_the_ball_is_chosen_over_a_wrong_sized_blob():
    """A ball at (2, 0) m and a ball-coloured disc far too big: the ball is reported."""
    found, _ = _detect(Scene(balls=((2.0, 0.0),), seed=5),
                       lambda image: cv2.circle(image, (350, 300), 40, BALL_RGB, -1))
    assert found is not None and math.hypot(found.x - 2.0, found.y) <= 0.1


@pytest.mark.parametrize("ball", [(3.0, 0.02), (-3.0, 0.02), (-3.0, -0.02)])
def test_a_ball_across_a_seam_of_the_bearings_is_one_ball_at_its_bearing(ball):
    """A ball straddling bearing 0 (rays 359 and 0 both see it) or 180 deg (where atan2 jumps from pi to -pi) is one
    blob at its true bearing."""
    found, _ = _detect(Scene(balls=(ball,), seed=6))
    assert found is not None and math.hypot(found.x - ball[0], found.y - ball[1]) <= 0.15


def _matched(obstacles, robots):
    """The obstacle nearest each robot and its error [m]."""
    return [min((math.hypot(o.x - x, o.y - y), o) for o in obstacles) for x, y in robots]


@pytest.mark.parametrize("robots", [
    ((2.0, 1.5), (-1.0, -3.0)),
    ((5.0, 0.0), (-6.0, 2.0)),
    ((0.9, 0.5), (-1.5, -0.2)),
])
def test_two_robots_give_two_obstacles_at_their_positions(robots):
    """Two robots among field lines (and a ball) give two obstacles, each within 10 cm + 3 % of its distance, its
    angular width about the robot's."""
    pose = (1.0, -2.0, 0.0)
    scene = field_scene(pose, robots=tuple((pose[0] + x, pose[1] + y) for x, y in robots),
                        balls=((pose[0] - 2.0, pose[1] + 2.5),), seed=7)
    _, obstacles = _detect(scene)
    assert len(obstacles) == 2
    for (error, obstacle), robot in zip(_matched(obstacles, robots), robots):
        distance = math.hypot(*robot)
        assert error <= 0.10 + 0.03 * distance, (robot, obstacle)
        assert obstacle.angular_width == pytest.approx(2 * math.asin(0.26 / distance), abs=math.radians(2.5))
        assert obstacle.near_distance == pytest.approx(distance - 0.26, abs=0.10 + 0.03 * distance)


@pytest.mark.parametrize("x", [1.0, 2.0, 4.0])
def test_two_robots_side_by_side_are_split_into_two(x):
    """Two robots touching side by side (no ray sees between them) form one black wedge twice a robot wide: it is
    split into two obstacles at the robots' positions; without splitting it would be one."""
    robots = ((x, 0.255), (x, -0.255))
    _, obstacles = _detect(Scene(robots=robots, seed=8))
    assert len(obstacles) == 2
    assert all(error <= 0.10 + 0.03 * x for error, _ in _matched(obstacles, robots))
    _, unsplit = _detect(Scene(robots=robots, seed=8), obstacles=ObstacleDetector(RAYS, ObstacleParams(
        split_factor=100.0)))
    assert len(unsplit) == 1


def test_the_own_bodys_struts_are_ignored_at_the_excluded_bearings():
    """The mirror holder's struts (thin black wedges reaching 25 px out of the body at 45, 135, 225 and 315 deg) are
    obstacles unless their bearings are excluded; a robot elsewhere is still found, and a robot right behind a
    strut (seen on both sides of the excluded bearings) is one obstacle at its position."""
    struts = (45.0, 135.0, 225.0, 315.0)
    scene = Scene(struts=struts, strut_width_deg=3.0, robots=((2.0, -1.0),), seed=9)
    _, seen = _detect(scene)
    assert len(seen) == 5
    excluded = ObstacleDetector(RAYS, ObstacleParams(excluded_bearings=tuple((b - 5.0, b + 5.0) for b in struts)))
    _, obstacles = _detect(scene, obstacles=excluded)
    assert len(obstacles) == 1 and math.hypot(obstacles[0].x - 2.0, obstacles[0].y + 1.0) <= 0.2
    robots = ((2.0, -1.0), (1.2, 1.2))
    _, obstacles = _detect(Scene(struts=struts, strut_width_deg=3.0, robots=robots, seed=9), obstacles=excluded)
    assert len(obstacles) == 2
    assert all(error <= 0.10 + 0.03 * math.hypot(*robot) for (error, _), robot in zip(_matched(obstacles, robots),
                                                                                           robots))


def test_a_frame_without_lines_ball_or_robots_gives_empty_results():
    """Carpet only: no line points, no ball, no obstacles, and no error."""
    image, _ = render(MIRROR, Scene(seed=10))
    table = calibrated_table(MIRROR)
    samples = RAYS.sample(image, table)
    assert len(LineScanner(MIRROR).scan_image(image, table)) == 0
    assert BallDetector(RAYS).detect(samples, table) is None
    assert ObstacleDetector(RAYS).detect(samples) == []


@pytest.mark.parametrize("image, message", [
    (np.zeros((480, 480, 3), np.uint8), "black"),
    (np.full((480, 640, 3), 90, np.uint8), r"got shape \(480, 640, 3\)"),
    (np.full((480, 480), 90, np.uint8), r"got shape \(480, 480\)"),
])
def test_unusable_frames_are_refused_at_the_entry_with_the_reason(image, message):
    """An all-black frame, a 640 x 480 frame and a grey frame are refused by the one entry check (reading the frame
    along the rays), with an OmniVisionError saying why."""
    with pytest.raises(OmniVisionError, match=message):
        RAYS.sample(image, calibrated_table(MIRROR))


@pytest.mark.parametrize("params, kwargs, message", [
    (BallParams, {"ball_radius": 0.0}, "ball_radius"),
    (BallParams, {"min_pixels": 0}, "min_pixels"),
    (BallParams, {"width_ratio_range": (2.0, 1.0)}, "width_ratio_range"),
    (ObstacleParams, {"min_run": 0}, "min_run"),
    (ObstacleParams, {"excluded_bearings": ((10.0, float("nan")),)}, "excluded_bearings"),
    (ObstacleParams, {"split_factor": 0.5}, "split_factor"),
])
def test_bad_object_parameters_are_refused(params, kwargs, message):
    """Parameters out of range are refused naming the parameter."""
    with pytest.raises(OmniVisionError, match=message):
        params(**kwargs)


def test_detections_of_the_same_frame_are_the_same():
    """Two detector sets on the same frame give identical results (no hidden state)."""
    scene = field_scene((0.0, 0.0, 0.5), balls=((1.5, 1.0),), robots=((-2.0, 1.0), (3.0, -2.0)), seed=11)
    assert _detect(scene) == _detect(scene)
