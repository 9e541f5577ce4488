"""PinholeCamera: pixel -> ray -> ground -> pixel round trips, the mount's rotation, YAML, refusals."""

from __future__ import annotations

import math
from dataclasses import replace

import numpy as np
import pytest

from nubot_common import NubotCommonError
from nubot_common.camera_model import PinholeCamera, camera_yaml, load_camera

from .scenes import CAMERA_FILE


def _grid(camera: PinholeCamera, step: int = 8) -> np.ndarray:
    v, u = np.mgrid[0:camera.height:step, 0:camera.width:step].astype(np.float64)
    return np.column_stack([u.ravel(), v.ravel()])


@pytest.mark.parametrize("camera", [PinholeCamera(), PinholeCamera(yaw_deg=10.0, roll_deg=-4.0, pitch_deg=25.0,
                                                                    distortion=(-0.2, 0.05, 0.001, -0.002, 0.0))])
@pytest.mark.parametrize("plane", [0.0, 0.11])
def test_pixel_to_ground_to_pixel_round_trip(camera: PinholeCamera, plane: float) -> None:
    uv = _grid(camera)
    ground = camera.plane_points(uv, plane)
    hits = np.all(np.isfinite(ground), axis=1)
    assert hits.mean() > 0.9, "a camera looking down sees the ground in nearly every pixel"
    back, ahead = camera.project(np.column_stack([ground[hits], np.full(hits.sum(), plane)]))
    assert ahead.all()
    np.testing.assert_allclose(back, uv[hits], atol=1e-3)  # [px]


def test_ground_to_pixel_to_ground_round_trip() -> None:
    camera = PinholeCamera()
    rng = np.random.default_rng(3)
    points = np.column_stack([rng.uniform(0.8, 2.5, 200), rng.uniform(-0.5, 0.5, 200), np.zeros(200)])
    uv, ahead = camera.project(points)
    inside = ahead & (uv[:, 0] >= 0) & (uv[:, 0] < camera.width) & (uv[:, 1] >= 0) & (uv[:, 1] < camera.height)
    assert inside.sum() > 100
    np.testing.assert_allclose(camera.plane_points(uv[inside], 0.0), points[inside, :2], atol=1e-6)  # [m]


def test_the_mount_points_the_optical_axis_down_ahead() -> None:
    camera = PinholeCamera(pitch_deg=30.0, yaw_deg=0.0)
    axis = camera.rotation[:, 2]
    np.testing.assert_allclose(axis, [math.cos(math.radians(30)), 0.0, -math.sin(math.radians(30))], atol=1e-12)
    np.testing.assert_allclose(camera.rotation[:, 0], [0.0, -1.0, 0.0], atol=1e-12)  # image right = robot's right
    centre = camera.plane_points(np.array([[camera.cx, camera.cy]]), 0.0)[0]
    expected = camera.position[0] + camera.position[2] / math.tan(math.radians(30.0))
    assert centre == pytest.approx((expected, 0.0), abs=1e-9)


def test_a_rotation_gives_back_its_mount() -> None:
    camera = PinholeCamera(yaw_deg=7.0, pitch_deg=28.0, roll_deg=-3.0)
    again = PinholeCamera.from_rotation(camera.rotation, camera.origin, **camera.intrinsics())
    assert (again.yaw_deg, again.pitch_deg, again.roll_deg) == pytest.approx((7.0, 28.0, -3.0), abs=1e-9)


def test_points_behind_the_lens_and_rays_above_the_horizon_are_flagged() -> None:
    camera = PinholeCamera()
    _, ahead = camera.project(np.array([[-1.0, 0.0, 0.3], [2.0, 0.0, 0.0]]))
    assert ahead.tolist() == [False, True]
    up = np.array([[1.0, 0.0, 0.1]]) / math.hypot(1.0, 0.1)
    assert np.isnan(camera.ray_plane_points(up, 0.0)).all()


def test_yaml_round_trip(tmp_path) -> None:
    camera = PinholeCamera(fx=231.5, distortion=(-0.05, 0.01, 0.0, 0.0, 0.0), pitch_deg=31.25)
    path = tmp_path / "camera.yaml"
    path.write_text(camera_yaml(camera, "made by a test\nsecond line"))
    assert path.read_text().startswith("# made by a test\n# second line\n")
    assert load_camera(path) == camera


def test_the_shipped_calibration_loads_and_is_near_the_simulated_camera() -> None:
    calibrated, truth = load_camera(CAMERA_FILE), PinholeCamera()
    assert calibrated.width == truth.width and calibrated.height == truth.height
    assert calibrated.fx == pytest.approx(truth.fx, rel=0.01)
    assert calibrated.pitch_deg == pytest.approx(truth.pitch_deg, abs=0.3)


@pytest.mark.parametrize(("change", "message"), [
    ({"fx": -1.0}, "fx must be a positive focal length"),
    ({"cx": 400.0}, "principal point"),
    ({"width": 8}, "width must be an integer"),
    ({"distortion": (0.0, 0.0, 0.0, 0.0)}, "five finite coefficients"),
    ({"distortion": (math.nan, 0.0, 0.0, 0.0, 0.0)}, "five finite coefficients"),
    ({"position": (0.2, 0.0, -0.1)}, "above the ground"),
    ({"pitch_deg": 95.0}, "pitch_deg must lie in"),
])
def test_a_bad_camera_is_refused_with_the_reason(change: dict, message: str) -> None:
    with pytest.raises(NubotCommonError, match=message):
        replace(PinholeCamera(), **change)


@pytest.mark.parametrize(("text", "message"), [
    ("camera: [1, 2", "not YAML"),
    ("- 1\n- 2\n", "expected a mapping"),
    ("camera:\n  fx: 200\n  focal: 3\n", "unknown parameter"),
    ("camera:\n  fx: .nan\n", "finite number"),
])
def test_a_bad_camera_file_is_refused_naming_it(tmp_path, text: str, message: str) -> None:
    path = tmp_path / "bad.yaml"
    path.write_text(text)
    with pytest.raises(NubotCommonError, match=message):
        load_camera(path)
    with pytest.raises(NubotCommonError, match="cannot read it"):
        load_camera(tmp_path / "missing.yaml")
