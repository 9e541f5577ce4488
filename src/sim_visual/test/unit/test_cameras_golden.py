"""The ray casting of the front and RGB-D cameras against the golden trace of the Python that made it.

``golden/cameras.npz`` holds what the Python made while every robot's cameras rendered two seeded lockstep matches
(seeds 0 and 1, 30 s each) every 0.3 s, then 600 seeded cylinders before the front camera and 100 seeded RGB-D views
from 0.3-2 m up (both cameras sit below the robots' and the posts' tops, which only these show)
(``python -m nubot_tools.golden cameras``): every upright cylinder a front camera painted (7082: robots, goal posts
and 492 of the seeded ones) and every RGB-D ray cast (900: the goalies' two cameras and the seeded views). The same
operations in the same order on the same libm give the same answers to the last bit (tolerance 0): the same pixels
painted in the same colours, the same surface met by every ray at the same range."""

from __future__ import annotations

import hashlib
from pathlib import Path

import numpy as np
import pytest

from nubot_common.world_description import WorldDescription
from sim_visual.front_camera import FrontCameraRenderer
from sim_visual.params import SensorParams
from sim_visual.rgbd_camera import BALL, GOAL, LINE, ROBOT, RgbdCameraRenderer

TRACE = Path(__file__).resolve().parents[1] / "golden" / "cameras.npz"


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
        shapes = [(int(s[0]), int(s[1]), *map(float, s[2:])) for s in
                  trace["shapes"][trace["shapes_offsets"][i]:trace["shapes_offsets"][i + 1]]]
        rng_t, kind = renderer.cast(o, renderer.rays @ rotation.T, shapes)
        assert np.array_equal(kind, _part(trace, "kind", i)), i
        assert np.array_equal(rng_t[kind == BALL], _part(trace, "ranges", i)), i
        assert hashlib.sha256(rng_t.tobytes()).digest() == trace["ranges_sha"][i].tobytes(), i
    assert {LINE, BALL, ROBOT, GOAL} <= set(np.unique(trace["kind"]))  # lines, ball, robots and goals all in it
    assert (casts[:, 2] > WorldDescription().field.goal_height).sum() > 20  # posts' and robots' tops seen from above
