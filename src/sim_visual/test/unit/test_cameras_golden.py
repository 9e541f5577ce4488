"""The compiled ray casting of the front and RGB-D cameras against the golden trace of the Python it replaced.

``golden/cameras.npz`` holds what the Python made while every robot's cameras rendered two seeded lockstep matches
(seeds 0 and 1, 30 s each) every 0.3 s, then 600 seeded cylinders before the front camera and 100 seeded RGB-D views
from 0.3-2 m up (both cameras sit below the robots' and the posts' tops, which only these show)
(``python -m nubot_tools.golden cameras``): every upright cylinder a front camera painted (7082: robots, goal posts
and 451 of the seeded ones) and every RGB-D ray cast (900: the goalies' two cameras and the seeded views). The same
operations in the same order on the same libm give the same answers to the last bit (tolerance 0): the same pixels
painted in the same colours, the same surface met by every ray at the same range. The rays' rotation and the ball's
dot products were numpy matrix products, which OpenBLAS summed with fused multiply-adds: the compiled cast repeats
them with std::fma in that order. One step is not the same function: whether a ground point lies on an arc takes
the angle from libm's atan2, where numpy used its own vectorised one (a last-bit difference in a quarter of the
angles); a pixel's class could only change at an arc's very end (within 1e-9 rad and that last bit), which no
recorded pixel is."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from nubot_common.kernels import load_kernels
from nubot_common.world_description import WorldDescription
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.params import SensorParams
from sim_visual.rgbd_camera import BALL, GOAL, LINE, ROBOT, RgbdCameraRenderer
from sim_visual.world import BallState, RobotState

TRACE = Path(__file__).resolve().parents[1] / "golden" / "cameras.npz"
_kernels = load_kernels("sim_visual")


@pytest.fixture(scope="module")
def trace():
    with np.load(TRACE) as data:
        return {k: data[k] for k in data.files}


def _part(trace, name, i):
    offsets = trace[f"{name}_offsets"]
    return trace[name][offsets[i]:offsets[i + 1], 0]


def _bits(trace, name, i, shape):
    offsets = trace["bits_offsets"]
    return np.unpackbits(trace[name][offsets[i]:offsets[i + 1]], count=shape[0] * shape[1]).reshape(shape) == 1


def test_every_recorded_cylinder_paints_the_same_pixels_in_the_same_colours(trace):
    params = SensorParams()
    renderer = FrontCameraRenderer(WorldDescription(), params.front_camera, params.camera)
    rows = trace["paint"]
    assert len(rows) == 7082
    sides = tops = 0
    for i, row in enumerate(rows):
        u0, v0, u1, v1 = (int(v) for v in row[:4])
        geometry = tuple(float(v) for v in row[4:8])
        side, top = row[8:11].astype(np.uint8), row[11:14].astype(np.uint8)
        fill = next(v for v in range(3) if v not in (side[0], top[0]))  # a colour neither face has
        image = np.full((renderer.camera.height, renderer.camera.width, 3), fill, np.uint8)
        expected = image.copy()
        renderer._paint_cylinder(image, (u0, v0, u1, v1), geometry, side, top)
        expected_side = _bits(trace, "side_bits", i, (v1 - v0, u1 - u0))
        expected_top = _bits(trace, "top_bits", i, (v1 - v0, u1 - u0))
        assert not (expected_side & expected_top).any(), i
        crop = expected[v0:v1, u0:u1]
        crop[expected_side] = side
        crop[expected_top] = top
        assert np.array_equal(image, expected), i  # nothing else painted, nothing outside the box
        sides += int(expected_side.sum())
        tops += int(expected_top.sum())
    assert sides > 1_000_000 and tops > 100_000  # the trace shows both faces, often


def test_every_recorded_rgbd_cast_meets_the_same_surfaces_at_the_same_ranges(trace):
    renderer = RgbdCameraRenderer(WorldDescription(), SensorParams().rgbd)
    casts = trace["cast"]
    assert len(casts) == 900
    for i, row in enumerate(casts):
        o, rotation = row[:3].copy(), row[3:].reshape(3, 3)
        shapes = trace["shapes"][trace["shapes_offsets"][i]:trace["shapes_offsets"][i + 1]]
        rng_t, kind = renderer.cast(o, rotation, shapes)
        assert np.array_equal(kind, _part(trace, "kind", i)), i
        assert np.array_equal(rng_t[kind == BALL], _part(trace, "ranges", i)), i
        assert hashlib.sha256(rng_t.tobytes()).digest() == trace["ranges_sha"][i].tobytes(), i
    assert {LINE, BALL, ROBOT, GOAL} <= set(np.unique(trace["kind"]))  # lines, ball, robots and goals all in it
    assert (casts[:, 2] > WorldDescription().field.goal_height).sum() > 20  # posts' and robots' tops seen from above


@pytest.fixture(scope="module")
def front():
    params = SensorParams()
    return FrontCameraRenderer(WorldDescription(), params.front_camera, params.camera)


@pytest.fixture(scope="module")
def rgbd():
    return RgbdCameraRenderer(WorldDescription(), SensorParams().rgbd)


def _image(front):
    return np.zeros((front.camera.height, front.camera.width, 3), np.uint8)


SIDE, TOP = np.array([10, 20, 30], np.uint8), np.array([40, 50, 60], np.uint8)


@pytest.mark.parametrize("bad", [float("nan"), float("inf"), -float("inf")])
def test_a_cylinder_or_viewpoint_that_is_not_a_number_is_refused_by_name(front, rgbd, bad):
    with pytest.raises(ValueError, match="geometry must be finite numbers"):
        front._paint_cylinder(_image(front), (0, 0, 10, 10), (2.0, bad, 0.75, 0.26), SIDE, TOP)
    o, rotation = np.array([1.0, 2.0, 0.6]), np.eye(3)
    cylinder = np.array([[0, ROBOT, 3.0, 2.0, 0.26, 0.75]], float)
    with pytest.raises(ValueError, match="origin must be finite numbers"):
        rgbd.cast(np.array([1.0, bad, 0.6]), rotation, cylinder)
    with pytest.raises(ValueError, match="rotation must be finite numbers"):
        rgbd.cast(o, np.where(np.eye(3) > 0, bad, 0.0), cylinder)
    with pytest.raises(ValueError, match="shapes must be finite numbers"):
        rgbd.cast(o, rotation, np.array([[0, ROBOT, 3.0, 2.0, bad, 0.75]]))


def test_a_robot_whose_pose_is_not_a_number_is_not_cast(rgbd):
    me = RobotState(float("nan"), 0.0, 0.0, 0.0, 0.0, 0.0)
    with pytest.raises(ValueError, match="origin must be finite numbers"):
        rgbd.render(me, BallState(1.0, 0.0, 0.11, 0.0, 0.0, 0.0), [], 0.0, np.random.default_rng(0))


def test_images_and_rays_of_another_kind_shape_or_layout_are_refused(front):
    image, rays, box, geometry = _image(front), front._rays, (0, 0, 10, 10), (2.0, 0.0, 0.75, 0.26)
    paint = _kernels.paint_cylinder
    with pytest.raises(ValueError, match="image must be of dtype uint8, got float64"):
        paint(image.astype(float), rays, box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match=r"image must have shape \(n, n, 3\), got \(240, 320, 4\)"):
        paint(np.zeros((240, 320, 4), np.uint8), rays, box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match="image must be C-contiguous"):
        paint(np.zeros((240, 640, 3), np.uint8)[:, ::2], rays, box, front._origin, geometry, SIDE, TOP)
    read_only = image.copy()
    read_only.flags.writeable = False
    with pytest.raises(ValueError, match="image must be writeable"):
        paint(read_only, rays, box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match="image must be a numpy array of uint8"):
        paint(image.tolist(), rays, box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match="rays must be of dtype float32, got float64"):
        paint(image, rays.astype(float), box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match=r"rays must have shape \(240, 320, 3\), got \(120, 320, 3\)"):
        paint(image, rays[:120].copy(), box, front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match=r"box \(u0, v0, u1, v1\) must lie within the 320 x 240 image, got "
                                         r"\(300, 0, 321, 10\)"):
        paint(image, rays, (300, 0, 321, 10), front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match=r"box .* got \(5, 0, 4, 10\)"):
        paint(image, rays, (5, 0, 4, 10), front._origin, geometry, SIDE, TOP)
    with pytest.raises(ValueError, match=r"geometry must have shape \(4,\), got \(3,\)"):
        paint(image, rays, box, front._origin, geometry[:3], SIDE, TOP)
    with pytest.raises(ValueError, match=r"side_rgb must be three integers in \[0, 255\]"):
        paint(image, rays, box, front._origin, geometry, (10, 20, 256), TOP)
    paint(image, rays, (0, 0, 0, 0), front._origin, geometry, SIDE, TOP)  # an empty box paints nothing
    assert not image.any()


def test_casts_and_casters_of_another_shape_are_refused(rgbd):
    o, rotation = np.array([1.0, 2.0, 0.6]), np.eye(3)
    with pytest.raises(ValueError, match=r"rotation must have shape \(3, 3\), got \(2, 3\)"):
        rgbd.cast(o, rotation[:2], np.zeros((0, 6)))
    with pytest.raises(ValueError, match=r"origin must have shape \(3,\), got \(2,\)"):
        rgbd.cast(o[:2], rotation, np.zeros((0, 6)))
    with pytest.raises(ValueError, match=r"shapes must have shape \(n, 6\), got \(1, 5\)"):
        rgbd.cast(o, rotation, np.zeros((1, 5)))
    with pytest.raises(ValueError, match="a shape must be CYLINDER, BAR or SPHERE"):
        rgbd.cast(o, rotation, np.array([[3, ROBOT, 3.0, 2.0, 0.26, 0.75]], float))
    with pytest.raises(ValueError, match=r"a shape's label must be an integer in \[0, 255\]"):
        rgbd.cast(o, rotation, np.array([[0, 2.5, 3.0, 2.0, 0.26, 0.75]]))
    with pytest.raises(ValueError, match=r"rays must have shape \(n, 3\), got \(4, 2\)"):
        _kernels.RgbdRayCaster(np.ones((4, 2)), np.zeros((0, 2, 2)), np.zeros((0, 5)), 0.0625, 8.0)
    with pytest.raises(ValueError, match="rays must be finite numbers"):
        _kernels.RgbdRayCaster(np.full((4, 3), np.nan), np.zeros((0, 2, 2)), np.zeros((0, 5)), 0.0625, 8.0)
    with pytest.raises(ValueError, match="max_range must be a finite number above 0"):
        _kernels.RgbdRayCaster(np.ones((4, 3)), np.zeros((0, 2, 2)), np.zeros((0, 5)), 0.0625, float("inf"))
    rng_t, kind = rgbd.cast(o, rotation, np.zeros((0, 6)))  # nothing but the ground
    assert len(rng_t) == len(kind) == len(rgbd.rays) and set(np.unique(kind)) <= {0, 1, 2}
