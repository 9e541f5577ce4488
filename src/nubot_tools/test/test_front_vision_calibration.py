"""Calibration on pattern images rendered by the simulated camera recovers its true intrinsics and mount."""

from __future__ import annotations

import numpy as np
import pytest

from front_vision import FrontVisionError
from front_vision.calibrate_tool import main as calibrate_main
from front_vision.calibration import Chessboard, GroundPlacement, calibrate, find_corners
from nubot_common.camera_model import load_camera
from nubot_tools.front_calibration import board_views, ground_views
from sim_visual.front_camera_params import FrontCameraParams

PARAMS = FrontCameraParams()
CAMERA = PARAMS.camera  # the simulated camera's truth
BOARD = Chessboard()
GROUND_BOARD = Chessboard(7, 4, 0.10)
PLACEMENTS = [GroundPlacement(0.95, 0.0, -90.0), GroundPlacement(1.25, 0.0, -90.0)]


@pytest.fixture(scope="module")
def calibrated():
    views = board_views(PARAMS, BOARD, 24, seed=5)
    ground = ground_views(PARAMS, GROUND_BOARD, PLACEMENTS, seed=6)
    return calibrate(views, BOARD, ground, PLACEMENTS, GROUND_BOARD)


def test_the_intrinsics_are_recovered(calibrated) -> None:
    camera, report = calibrated
    assert report.views >= 12 and report.intrinsics_rms < 0.3  # [px]
    assert (camera.fx, camera.fy) == pytest.approx((CAMERA.fx, CAMERA.fy), rel=0.01)
    assert (camera.cx, camera.cy) == pytest.approx((CAMERA.cx, CAMERA.cy), abs=1.5)  # [px]
    assert camera.distortion[0] == pytest.approx(CAMERA.distortion[0], abs=0.01)
    assert camera.distortion[1] == pytest.approx(CAMERA.distortion[1], abs=0.02)


def test_the_mount_is_recovered(calibrated) -> None:
    camera, report = calibrated
    assert report.ground_views == 2 and report.mount_rms < 0.3  # [px]
    np.testing.assert_allclose(camera.position, CAMERA.position, atol=0.005)  # [m]
    assert camera.pitch_deg == pytest.approx(CAMERA.pitch_deg, abs=0.3)
    assert camera.yaw_deg == pytest.approx(CAMERA.yaw_deg, abs=0.3)
    assert camera.roll_deg == pytest.approx(CAMERA.roll_deg, abs=0.3)


def test_the_calibrated_camera_maps_ground_pixels_within_a_centimetre(calibrated) -> None:
    camera, _ = calibrated
    rng = np.random.default_rng(1)
    points = np.column_stack([rng.uniform(0.7, 1.5, 100), rng.uniform(-0.4, 0.4, 100), np.full(100, 0.11)])
    uv, _ = CAMERA.project(points)
    error = np.hypot(*(camera.plane_points(uv, 0.11) - points[:, :2]).T)
    assert error.max() < 0.01  # [m]


def test_corners_come_in_the_boards_order_whatever_its_turn() -> None:
    image = ground_views(PARAMS, GROUND_BOARD, [GroundPlacement(1.0, 0.0, -90.0)], seed=0)[0]
    turned = ground_views(PARAMS, GROUND_BOARD, [GroundPlacement(1.0, 0.0, 90.0)], seed=0)[0]
    a, b = find_corners(image, GROUND_BOARD), find_corners(turned, GROUND_BOARD)
    assert a is not None and b is not None
    np.testing.assert_allclose(a, b[::-1], atol=0.5)  # the same corners, numbered from the other end


def test_no_board_no_corners() -> None:
    assert find_corners(np.full((240, 320, 3), 90, np.uint8), BOARD) is None


def test_too_few_views_and_bad_boards_are_refused() -> None:
    with pytest.raises(FrontVisionError, match="at least 3 views"):
        calibrate([np.full((240, 320, 3), 90, np.uint8)] * 2, BOARD, [], [], GROUND_BOARD)
    with pytest.raises(FrontVisionError, match="must be odd"):
        Chessboard(8, 6, 0.03)
    with pytest.raises(FrontVisionError, match="one camera, one size"):
        calibrate([np.zeros((240, 320, 3), np.uint8), np.zeros((100, 100, 3), np.uint8)], BOARD, [], [],
                  GROUND_BOARD)


def test_the_tool_refuses_a_folder_without_images(tmp_path, capsys) -> None:
    assert calibrate_main(["--images", str(tmp_path), "--out", str(tmp_path / "c.yaml")]) == 2
    assert "no images" in capsys.readouterr().err


def test_the_tool_calibrates_from_image_files_as_a_real_camera_gives_them(tmp_path) -> None:
    import cv2

    pictures = tmp_path / "pictures"
    pictures.mkdir()
    for n, image in enumerate(board_views(PARAMS, BOARD, 16, seed=8)):
        cv2.imwrite(str(pictures / f"view{n:02d}.png"), cv2.cvtColor(image, cv2.COLOR_RGB2BGR))
    ground = ground_views(PARAMS, GROUND_BOARD, PLACEMENTS[:1], seed=9)[0]
    cv2.imwrite(str(tmp_path / "ground.png"), cv2.cvtColor(ground, cv2.COLOR_RGB2BGR))
    out = tmp_path / "camera.yaml"
    assert calibrate_main(["--images", str(pictures), "--ground", "0.95,0,-90", "--ground-image",
                           str(tmp_path / "ground.png"), "--out", str(out)]) == 0
    camera = load_camera(out)
    np.testing.assert_allclose(camera.position, CAMERA.position, atol=0.01)
    assert camera.pitch_deg == pytest.approx(CAMERA.pitch_deg, abs=0.5)
    assert calibrate_main(["--images", str(pictures), "--out", str(out)]) == 2, "no ground view: refused"
