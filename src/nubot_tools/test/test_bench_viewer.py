"""The viewer benchmark's summaries (no ROS, no browser): CPU from resource samples, rates, frames, the PNGs."""

import numpy as np
import pytest
from PIL import Image

from nubot_tools.ros.bench_viewer import (
    counter_rates,
    frame_budget,
    match_figures,
    node_cpu,
    page_cost,
    plot,
    rate_summary,
    shrink_png,
    spread,
)


def sample(wall: float, process: str, pid: int, cpu: float) -> dict:
    return {"wall": wall, "sim": wall, "process": process, "pid": pid, "rss_mib": 50.0, "cpu_cores": cpu}


def test_node_cpu_drops_each_process_first_sample_and_sums_its_processes_per_instant():
    rows = [sample(0.0, "/viewer", 10, 0.0), sample(0.0, "/viewer", 11, 0.0), sample(0.0, "/referee", 12, 0.0),
            sample(5.0, "/viewer", 10, 0.10), sample(5.0, "/viewer", 11, 0.02), sample(5.0, "/referee", 12, 0.5),
            sample(10.0, "/viewer", 10, 0.20), sample(10.0, "/viewer", 11, 0.01),
            sample(10.0, "/viewer", 13, 0.0)]  # a process that came later: its first sample says nothing
    assert node_cpu(rows, "/viewer") == pytest.approx([0.12, 0.21])
    assert node_cpu(rows, "/nobody") == []


def test_spread_and_rate_summary_and_their_empty_cases():
    assert spread([0.1, 0.3, 0.2]) == {"mean": pytest.approx(0.2), "max": 0.3, "samples": 3}
    assert spread([]) == {"mean": None, "max": None, "samples": 0}
    assert rate_summary([25, 24, 25, 12, 25]) == {"median": 25, "min": 12, "samples": 5}
    assert rate_summary([]) == {"median": None, "min": None, "samples": 0}


def test_counter_rates_are_per_sample_period_and_skip_a_period_without_time():
    points = [(0.0, 100), (5.0, 225), (10.0, 250), (10.0, 260), (15.0, 385)]
    assert counter_rates(points) == pytest.approx([25.0, 5.0, 25.0])
    assert counter_rates(points[:1]) == []


def test_frame_budget_counts_the_frames_missing_against_the_server_rate():
    frames = frame_budget(100, 1100, 50.0, 25.0)
    assert frames == {"received": 1000, "at_server_rate": 1250, "missing": 250, "missing_share": 0.2,
                      "wall_seconds": 50.0}
    assert frame_budget(0, 1260, 50.0, 25.0)["missing"] == 0  # a tick's jitter gives a page a frame more
    with pytest.raises(ValueError, match="positive span and growing counters"):
        frame_budget(10, 5, 1.0, 25.0)
    with pytest.raises(ValueError, match="positive span"):
        frame_budget(0, 5, 0.0, 25.0)


def figures(rtf: float, viewer: list[float]) -> dict:
    perf = {"achieved_real_time_factor": rtf, "cpu_cores_total": 1.9, "cpu_cores_by_kind": {"viewer": 0.1}}
    resources = [sample(5.0 * k, "/viewer", 7, c) for k, c in enumerate([0.0, *viewer])]
    return match_figures(perf, resources)


def test_page_cost_is_the_change_the_page_made_and_is_plotted(tmp_path):
    without, page = figures(0.98, [0.05, 0.07]), figures(0.95, [0.15, 0.25])
    assert page["viewer_cpu_cores"] == {"mean": 0.2, "max": 0.25, "samples": 2}
    page |= {"chromium_cpu_cores": spread([0.3, 0.5]), "page_fps": rate_summary([25, 24])}
    cost = page_cost(without, page)
    assert cost == {"real_time_factor_change": pytest.approx(-0.03), "viewer_cpu_cores_change": pytest.approx(0.14),
                    "viewer_and_chromium_cpu_cores": pytest.approx(0.54)}
    plot({"machine": {"cpus": 2}, "matches": {"no_page": without, "page": page}}, tmp_path / "viewer.png")
    with Image.open(tmp_path / "viewer.png") as image:
        assert image.size[0] > 400


def test_page_cost_without_figures_is_none():
    without, page = figures(0.98, []), figures(0.95, [0.2])
    assert page_cost(without, page) == {"real_time_factor_change": pytest.approx(-0.03),
                                        "viewer_cpu_cores_change": None, "viewer_and_chromium_cpu_cores": None}


def test_shrink_png_quantises_a_large_screenshot_under_the_limit_and_keeps_a_small_one(tmp_path):
    rng = np.random.default_rng(0)
    shot = tmp_path / "shot.png"
    pixels = np.repeat(rng.integers(0, 256, (360, 640, 3), dtype=np.uint8), 2, axis=0)  # noise: big as a PNG
    Image.fromarray(pixels).save(shot)
    assert shot.stat().st_size > 500_000
    size = shrink_png(shot, 400_000)
    assert size == shot.stat().st_size <= 400_000
    with Image.open(shot) as image:
        assert image.size == (640, 720) and image.mode == "P"
    small = tmp_path / "small.png"
    Image.new("RGB", (64, 64), "green").save(small)
    before = small.read_bytes()
    assert shrink_png(small, 400_000) == len(before) and small.read_bytes() == before
