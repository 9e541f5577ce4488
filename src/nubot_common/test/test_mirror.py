"""The mirror model: image radius <-> ground distance, pixels <-> body frame, points above the ground."""

import math

import numpy as np
import pytest

from nubot_common.mirror import MirrorModel

MIRROR = MirrorModel()


def test_distance_follows_a_tan_b_r_and_radius_inverts_it():
    """d(r) = a tan(b r), and radius(d(r)) gives r back across the usable ring."""
    r = np.linspace(MIRROR.r_min, MIRROR.r_max, 50)
    assert MIRROR.distance(r) == pytest.approx(MIRROR.a * np.tan(MIRROR.b * r))
    assert MIRROR.radius(MIRROR.distance(r)) == pytest.approx(r, abs=1e-6)
    assert np.all(np.diff(MIRROR.distance(r)) > 0), "farther out in the image is farther away on the ground"


def test_the_default_mirror_sees_from_a_held_ball_to_nine_metres():
    """The usable ring shows the ground from 0.28 m (a ball in the grabber) to 9 m."""
    assert MIRROR.min_distance == pytest.approx(0.28, abs=0.01)
    assert MIRROR.max_distance == pytest.approx(9.0, abs=0.05)


@pytest.mark.parametrize("x, y", [(2.0, 0.0), (0.0, 3.0), (-1.5, -1.0), (0.4, -0.2), (5.0, 4.0)])
def test_body_points_round_trip_through_pixels(x, y):
    """A ground point goes to its pixel and back; the front is up in the image and the left is left."""
    u, v = MIRROR.body_to_pixel(x, y)
    bx, by = MIRROR.pixel_to_body(u, v)
    assert (float(bx), float(by)) == pytest.approx((x, y), abs=1e-6)


def test_image_orientation_front_up_left_left():
    """Body +x (ahead) is above the image centre, body +y (left) left of it."""
    u, v = MIRROR.body_to_pixel(2.0, 0.0)
    assert float(u) == pytest.approx(MIRROR.centre_u) and float(v) < MIRROR.centre_v
    u, v = MIRROR.body_to_pixel(0.0, 2.0)
    assert float(u) < MIRROR.centre_u and float(v) == pytest.approx(MIRROR.centre_v)


def test_a_point_above_the_ground_appears_farther_out_and_above_the_viewpoint_not_at_all():
    """A lofted ball's centre shows where its ray meets the ground; at or above the viewpoint it is not seen."""
    h = MIRROR.viewpoint_height
    assert float(MIRROR.ground_distance(2.0, 0.0)) == pytest.approx(2.0)
    assert float(MIRROR.ground_distance(2.0, h / 2)) == pytest.approx(4.0)
    assert math.isinf(float(MIRROR.ground_distance(2.0, h)))


def test_a_calibrated_table_replaces_the_formula():
    """A measured (radius, distance) table is interpolated, both ways."""
    table = ((0.0, 0.0), (100.0, 1.0), (230.0, 9.0))
    mirror = MirrorModel(table=table)
    assert float(mirror.distance(50.0)) == pytest.approx(0.5)
    assert float(mirror.radius(5.0)) == pytest.approx(165.0)


def test_pixel_grid_marks_the_usable_ring():
    """Every pixel's ground point, and the ring between r_min and r_max as usable."""
    x, y, usable = MIRROR.pixel_grid()
    assert x.shape == y.shape == usable.shape == (MIRROR.height, MIRROR.width)
    assert not usable[int(MIRROR.centre_v), int(MIRROR.centre_u)] and not usable[0, 0]
    assert usable[int(MIRROR.centre_v) - 100, int(MIRROR.centre_u)]
    assert float(x[int(MIRROR.centre_v) - 100, int(MIRROR.centre_u)]) == pytest.approx(float(MIRROR.distance(100)))


@pytest.mark.parametrize("change, message", [
    ({"r_min": 240.0}, "r_min < r_max"),
    ({"b": 0.01}, "horizon"),
    ({"centre_u": 100.0}, "inside the 480 x 480 image"),
    ({"width": 8}, "width"),
    ({"viewpoint_height": 0.0}, "viewpoint_height"),
    ({"a": float("nan")}, "finite"),
    ({"table": ((0.0, 0.0), (100.0, 2.0), (90.0, 3.0), (230.0, 9.0))}, "increase"),
    ({"table": ((100.0, 1.0), (230.0, 9.0))}, "cover"),
])
def test_bad_mirrors_are_refused_with_the_reason(change, message):
    with pytest.raises(ValueError, match=message):
        MirrorModel(**change)
