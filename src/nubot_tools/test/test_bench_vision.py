"""The vision benchmark: its quick run writes vision.json with plausible figures and both plots; its paths, its
placement and its scenarios are deterministic for a seed. No ROS."""

import json
import math
import os

import cv2
import numpy as np
import pytest

from nubot_common.field import FieldGeometry
from nubot_common.params import load_yaml
from nubot_common.world_description import load_world
from nubot_tools.bench import vision as bv
from omni_vision.colors import ColorTable
from omni_vision.pipeline import OmniVisionParams


def test_quick_run_writes_plausible_figures(tmp_path):
    before, threads = os.sched_getaffinity(0), cv2.getNumThreads()
    assert bv.main(["--quick", "--out", str(tmp_path), "--seed", "3"]) == 0
    assert os.sched_getaffinity(0) == before and cv2.getNumThreads() == threads  # both restored
    data = json.loads((tmp_path / "vision.json").read_text())
    assert data["quick"] and data["seed"] == 3 and data["field"] == "18x12"
    assert data["targets"]["pipeline_total_median_ms"] == 5.0 and data["targets"]["global_frames"] == 30
    for part in ("pipeline_time", "standing", "figure_eight", "global_localization", "ball", "fig11"):
        assert isinstance(data[part]["met"], bool), part

    pipeline = data["pipeline_time"]
    assert pipeline["cv2_threads"] == 1 and pipeline["frames_tracking"] > 200  # 8 s at 30 Hz
    for stage in bv.STAGES:
        assert pipeline["stages_ms"][stage]["median"] > 0, stage
    assert pipeline["stages_ms"]["total"]["median"] >= pipeline["stages_ms"]["localization"]["median"]
    assert pipeline["render_ms"]["median"] > 0

    for part in ("standing", "figure_eight", "fig11"):
        figures = data[part]
        assert figures["localized_share"] > 0.9, part
        assert 0 < figures["position_error_m"]["mean"] < 0.1, part
        assert figures["heading_error_deg"]["mean"] < 3.0, part
    assert len(data["standing"]["poses"]) == 2

    glob = data["global_localization"]
    assert glob["poses"] == 8 and len(glob["cases"]) == 8
    assert glob["converged"] >= 6 and glob["frames_needed"]["median"] <= 30
    assert glob["frames_needed_cumulative"][f"<={glob['max_frames']}"] == glob["converged"]

    ball = data["ball"]
    assert list(ball["bins"]) == ["0-2m", "2-4m", "4-6m", "6-9m"]
    assert sum(b["placements"] for b in ball["bins"].values()) == 60 == len(ball["samples"])
    near = ball["up_to_6m"]
    assert near["detection_rate"] > 0.8 and near["error_percent"]["median"] < 5.0
    assert ball["false_detections"]["frames"] >= 115 and ball["false_detections"]["per_minute"] is not None
    for name in ("vision_localization.png", "vision_ball.png"):
        assert (tmp_path / name).stat().st_size > 10_000, name


@pytest.fixture(scope="module")
def parts():
    world = load_world("18x12")
    params = load_yaml(OmniVisionParams, bv.VISION_CONFIG / "omni_vision.yaml")
    return world, params, ColorTable.load(bv.VISION_CONFIG / "colors_sim.npz")


def test_scenarios_are_deterministic(parts):
    d = bv.Durations(1, 0.5, 1.0, 3, 30, 8, 1.0, (4.0, 2.0), 1)

    def once() -> tuple[dict, dict]:
        rig = bv.VisionRig(*parts, 3, seed=5)
        glob = bv.bench_global(rig, np.random.default_rng(1), d, lambda _line: None)
        ball = bv.bench_ball(rig, np.random.default_rng(2), d, lambda _line: None)
        return glob, ball

    first, second = once(), once()
    assert first == second
    assert len(first[1]["samples"]) == 8


def test_figure_eight_path_is_8_by_4_m_at_3_m_s():
    path = bv.FigureEight(bv.EIGHT_SIZE, bv.EIGHT_SPEED, bv.EIGHT_ACCELERATION)
    points = path.points()
    assert np.ptp(points[:, 0]) == pytest.approx(8.0, abs=1e-3) and np.ptp(points[:, 1]) == pytest.approx(4.0, abs=1e-2)
    start = path(0.0)
    assert (start.x, start.y, math.hypot(start.vx, start.vy)) == (0.0, 0.0, 0.0)
    for t in np.linspace(1.0, 20.0, 40):  # after the 1 s ramp: 3 m/s along the path, turning with it
        ref, later = path(t), path(t + 1e-4)
        assert math.hypot(ref.vx, ref.vy) == pytest.approx(3.0)
        assert math.hypot(later.x - ref.x, later.y - ref.y) / 1e-4 == pytest.approx(3.0, rel=1e-3)
        assert ref.theta == pytest.approx(math.atan2(ref.vy, ref.vx))
        assert (later.theta - ref.theta) / 1e-4 == pytest.approx(ref.w, abs=1e-2)


def test_polyline_stops_at_each_corner():
    path = bv.Polyline([(0.0, 0.0), (4.0, 0.0), (4.0, 1.0)], 1, speed=2.0, acceleration=2.0)
    # 4 m: 1 s up, 1 s at 2 m/s, 1 s down; 1 m (too short for 2 m/s): 2 sqrt(1/2) s; 4.12 m back
    assert path.times[:2] == pytest.approx([3.0, 2.0 * math.sqrt(0.5)])
    at = path(path.times[0])
    assert (at.x, at.y, at.vx, at.vy) == pytest.approx((4.0, 0.0, 0.0, 0.0))
    assert path(1.5).vx == pytest.approx(2.0)
    end = path(path.duration + 5.0)
    assert (end.x, end.y, end.vx, end.vy) == pytest.approx((0.0, 0.0, 0.0, 0.0))


def test_free_spots_keep_their_distance_and_refuse_an_impossible_request():
    field = FieldGeometry()
    spots = bv.free_spots(np.random.default_rng(0), 6, field, [(0.0, 0.0)], 1.5)
    everything = [(0.0, 0.0), *spots]
    assert all(math.dist(a, b) >= 1.5 for i, a in enumerate(everything) for b in everything[i + 1:])
    with pytest.raises(RuntimeError, match="found only .* of 200 free spots 3.0 m apart"):
        bv.free_spots(np.random.default_rng(0), 200, field, [], 3.0)


def test_negative_seed_is_refused(capsys, tmp_path):
    with pytest.raises(SystemExit):
        bv.main(["--seed", "-1", "--out", str(tmp_path)])
    assert "--seed must not be negative, got -1" in capsys.readouterr().err
