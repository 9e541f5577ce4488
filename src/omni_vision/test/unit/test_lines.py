"""White line points on the radial scan rays."""

import math

import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.mirror import MirrorModel
from omni_vision import OmniVisionError
from omni_vision.lines import LineParams, LineScanner, ScanRays, find_runs

from .scenes import ArcLine, Scene, _arc_distance, _segment_distance, calibrated_table, field_scene, render

MIRROR = MirrorModel()
LINE_AT_2_M = (((2.0, -8.0), (2.0, 8.0)),)


@pytest.fixture(scope="module")
def scanner():
    return LineScanner(MIRROR)


def _scan(scanner, scene):
    image, _ = render(MIRROR, scene)
    return scanner.scan_image(image, calibrated_table(MIRROR))


def _tolerance(distance):
    """3 cm near, 5 % of the distance far (beyond 0.6 m the second is larger)."""
    return np.maximum(0.03, 0.05 * distance)


@pytest.mark.parametrize("seed, brightness, blur", [(0, 1.0, 0.0), (1, 0.85, 0.0), (2, 1.15, 0.8)])
def test_points_of_a_straight_line_lie_on_it(scanner, seed, brightness, blur):
    """A line at x = 2 m (light varying +-25 % over the ground, noise, with and without blur) gives points within
    3 cm of it near (up to 3 m) and within 5 % of their distance farther, from bearings -60 to 60 deg and more."""
    found = _scan(scanner, Scene(segments=LINE_AT_2_M, seed=seed, brightness=brightness, blur_sigma=blur,
                                 light_phase=seed))
    x, y = found.points.T
    distance = np.hypot(x, y)
    error = np.abs(x - 2.0)
    near = distance <= 3.0
    assert near.sum() >= 50 and (~near).sum() >= 10
    assert error[near].max() <= 0.03, f"near: {error[near].max():.3f} m"
    assert np.all(error[~near] <= 0.05 * distance[~near]), f"far: {np.max(error[~near] / distance[~near]):.3f}"
    bearing = np.degrees(np.arctan2(y, x))
    assert bearing.min() <= -60.0 and bearing.max() >= 60.0


def test_points_are_ordered_by_bearing_and_their_pixels_show_them(scanner):
    """Points come ray by ray from bearing 0 counter-clockwise, and each one's pixel maps back to it through the
    mirror model."""
    found = _scan(scanner, Scene(segments=LINE_AT_2_M + (((-1.5, -8.0), (-1.5, 8.0)),), seed=3))
    bearing = np.arctan2(found.points[:, 1], found.points[:, 0]) % (2 * math.pi)
    assert np.all(np.diff(bearing) >= -math.radians(1.0))
    x, y = MIRROR.pixel_to_body(found.pixels[:, 0], found.pixels[:, 1])
    assert np.allclose(np.column_stack((x, y)), found.points, atol=1e-6)


def test_field_lines_seen_from_poses_give_points_on_the_field_lines(scanner):
    """From 3 poses on the field (with a ball and a robot in view), >= 97 % of the points lie within 3 cm (near) or
    5 % (far) of a field line's centre and all lie on the painted lines (within half a line width more)."""
    field = FieldGeometry()
    for n, pose in enumerate([(-2.0, 1.0, 0.3), (6.0, -3.0, 2.0), (-7.5, 4.5, 3.0)]):
        scene = field_scene(pose, field, balls=((pose[0] + 1.0, pose[1] + 0.5),),
                            robots=((pose[0] - 1.5, pose[1] + 1.0),), seed=n, blur_sigma=0.5 * n)
        found = _scan(scanner, scene)
        assert len(found) >= 150
        c, s = math.cos(pose[2]), math.sin(pose[2])
        wx = pose[0] + c * found.points[:, 0] - s * found.points[:, 1]
        wy = pose[1] + s * found.points[:, 0] + c * found.points[:, 1]
        off = np.min([_segment_distance(wx, wy, a, b) for a, b in field.line_segments()]
                     + [_arc_distance(wx, wy, ArcLine(a.x, a.y, a.radius, a.start, a.end)) for a in field.arcs()],
                     axis=0)
        tolerance = _tolerance(np.hypot(*found.points.T))
        assert np.mean(off <= tolerance) >= 0.97, f"pose {pose}: {np.mean(off <= tolerance):.3f}"
        assert np.all(off <= tolerance + field.line_width / 2), f"pose {pose}: {off.max():.3f} m"


def test_a_line_outside_the_usable_ring_gives_no_points(scanner):
    """A line beyond the mirror's rim (9.5 m) and a line inside r_min (under the robot, its body not painted, so the
    carpet and the line are visible there) give no points."""
    assert MIRROR.max_distance < 9.5 and MIRROR.min_distance > 0.25
    beyond = _scan(scanner, Scene(segments=(((9.5, -3.0), (9.5, 3.0)),), seed=4))
    under = _scan(scanner, Scene(segments=(((0.15, -0.1), (0.15, 0.1)), ((-0.12, -0.15), (-0.12, 0.15))),
                                 own_body=False, seed=5))
    assert len(beyond) == 0 and len(under) == 0


@pytest.mark.parametrize("seed, brightness", [(6, 1.0), (7, 0.8), (8, 1.2)])
def test_green_carpet_with_noise_only_gives_no_points(scanner, seed, brightness):
    """Carpet alone (noise, light varying +-25 % across it, dim or bright) gives no line points."""
    assert len(_scan(scanner, Scene(seed=seed, brightness=brightness, light_phase=seed))) == 0


def test_balls_and_robots_give_no_line_points(scanner):
    """The ball's lit top and the robots' ragged edges are not lines."""
    scene = Scene(balls=((2.0, 0.0), (0.0, -3.0), (0.7, 0.3), (1.2, -0.8)), robots=((2.0, 1.5), (-1.0, -3.0)),
                  seed=9)
    assert len(_scan(scanner, scene)) == 0


def test_at_most_five_points_per_ray_the_nearest(scanner):
    """Seven parallel lines 0.5 m apart across bearing 0: the ray at 0 deg reports the nearest five."""
    lines = tuple(((x, -8.0), (x, 8.0)) for x in (1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0))
    found = _scan(scanner, Scene(segments=lines, seed=10))
    on_ray = found.points[np.abs(found.points[:, 1]) < 0.005]
    assert np.allclose(np.sort(on_ray[:, 0]), [1.0, 1.5, 2.0, 2.5, 3.0], atol=0.03)


def test_a_band_too_wide_for_a_line_gives_no_points(scanner):
    """A white band 4 line widths wide (0.5 m) is no line: its runs are too wide at every bearing; a band of
    2.4 widths crossed head-on still is one."""
    assert len(_scan(scanner, Scene(segments=LINE_AT_2_M, line_width=0.5, seed=11))) == 0
    assert len(_scan(scanner, Scene(segments=LINE_AT_2_M, line_width=0.3, seed=11))) > 0


def test_find_runs_gives_each_rows_runs_in_order():
    """Runs of nonzero values per row, end exclusive, including runs touching either end of a row."""
    mask = np.array([[1, 1, 0, 1, 0, 0], [0, 0, 0, 0, 0, 0], [0, 1, 1, 1, 1, 1]], np.uint8)
    row, start, end = find_runs(mask)
    assert list(zip(row.tolist(), start.tolist(), end.tolist())) == [(0, 0, 2), (0, 3, 4), (2, 1, 6)]


def test_the_rays_sample_pixels_along_their_bearings():
    """Ray i points at bearing i deg (0 = body +x = image up, 90 = body +y = image left), sampling from r_min to
    r_max every pixel."""
    rays = ScanRays(MIRROR)
    assert rays.count == 360 and rays.radii[0] == MIRROR.r_min and rays.radii[-1] == MIRROR.r_max
    assert (rays.u[0, -1], rays.v[0, -1]) == (240, 240 - 230)
    assert (rays.u[90, -1], rays.v[90, -1]) == (240 - 230, 240)
    assert np.all(np.abs(rays.pixel_radius - rays.radii) <= math.sqrt(0.5))


def test_samples_of_other_rays_are_refused(scanner):
    """Samples read along another ScanRays cannot be scanned (their layout differs)."""
    image, _ = render(MIRROR, Scene(seed=12))
    samples = ScanRays(MIRROR, ray_count=180).sample(image, calibrated_table(MIRROR))
    with pytest.raises(OmniVisionError, match="other rays"):
        scanner.scan(samples)


@pytest.mark.parametrize("kwargs, message", [
    ({"ray_count": 4}, "ray_count"),
    ({"flank": 0}, "flank"),
    ({"min_contrast": 0.0}, "min_contrast"),
    ({"width_tolerance": float("inf")}, "width_tolerance"),
    ({"min_width_fraction": 2.0}, "min_width_fraction"),
])
def test_bad_line_parameters_are_refused(kwargs, message):
    """Parameters out of range are refused naming the parameter."""
    with pytest.raises(OmniVisionError, match=message):
        LineParams(**kwargs)
