"""The simulated front camera calibrated from the views it renders (nubot_tools.front_calibration)."""

from __future__ import annotations

import pytest

from nubot_common.camera_model import load_camera
from nubot_tools.front_calibration import main as calibrate_main
from sim_visual.front_camera_params import FrontCameraParams

CAMERA = FrontCameraParams().camera


def test_the_tool_writes_a_camera_file_front_vision_loads(tmp_path, capsys) -> None:
    out = tmp_path / "camera.yaml"
    assert calibrate_main(["--views", "16", "--seed", "2", "--out", str(out)]) == 0
    camera = load_camera(out)
    assert camera.fx == pytest.approx(CAMERA.fx, rel=0.02)
    assert out.read_text().startswith("# Front camera calibration")
    assert "RMS reprojection" in capsys.readouterr().out


def test_bad_arguments_and_a_failed_calibration_are_refused(tmp_path, capsys) -> None:
    config = tmp_path / "sim.yaml"
    config.write_text("sim: {sensors: {front_camera: {no_such_key: 1}}}\n")
    assert calibrate_main(["--sim-config", str(config), "--out", str(tmp_path / "c.yaml")]) == 2
    assert "no_such_key" in capsys.readouterr().err
    assert calibrate_main(["--views", "2", "--out", str(tmp_path / "c.yaml")]) == 2, "too few views"
    assert "calibrate_front_camera:" in capsys.readouterr().err
    assert not (tmp_path / "c.yaml").exists()
    with pytest.raises(SystemExit):
        calibrate_main(["--board", "nine", "--out", str(tmp_path / "c.yaml")])
