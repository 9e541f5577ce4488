"""MatchLogRecorder keeps every model's track exactly, however long the match, and whatever the disk does."""

from __future__ import annotations

import subprocess
import sys
import textwrap

import numpy as np

from nubot_match import record
from nubot_match.record import MatchLogRecorder
from sim_visual.world import BallState, RobotState


def _states(i: int, names: list[str]) -> list:
    """Sample ``i``: distinct, exactly representable positions, a ball among the robots."""
    out = []
    for k, name in enumerate(names):
        x, y = i * 0.001 + k, -i * 0.002 - k / 3.0
        out.append((name, BallState(x, y, 0.11, 0, 0, 0) if name == "ball" else RobotState(x, y, 0, 0, 0, 0)))
    return out


def _record(samples: int, leave: range = range(0)) -> tuple[MatchLogRecorder, dict[str, list]]:
    """Feed ``samples`` model states (robot ``b`` absent in the samples of ``leave``); also return the truth."""
    recorder, truth = MatchLogRecorder(), {"a": [], "b": [], "ball": []}
    for i in range(samples):
        names = [n for n in truth if not (n == "b" and i in leave)]
        states = _states(i, names)
        recorder.model_states(i / 100.0, states)
        for name, s in states:
            truth[name].append((i / 100.0, s.x, s.y))
    return recorder, truth


def _assert_tracks(recorder: MatchLogRecorder, truth: dict[str, list]) -> None:
    log = recorder.finish()
    assert set(log.tracks) == set(truth)
    for name, rows in truth.items():
        expected = np.array(rows)
        track = log.tracks[name]
        np.testing.assert_array_equal(track.t, expected[:, 0])
        np.testing.assert_array_equal(track.xy, expected[:, 1:])  # the very numbers, not close ones


def test_tracks_longer_than_what_memory_holds_come_back_exactly():
    # Several blocks written out plus a part block in memory.
    recorder, truth = _record(3 * record._BLOCK + 17)
    _assert_tracks(recorder, truth)


def test_a_model_that_leaves_and_comes_back_keeps_its_own_times():
    recorder, truth = _record(2 * record._BLOCK + 5, leave=range(100, record._BLOCK + 300))
    log_truth_b = len(truth["b"])
    assert log_truth_b == 2 * record._BLOCK + 5 - (record._BLOCK + 200)
    _assert_tracks(recorder, truth)


def test_a_match_without_model_states_has_no_tracks():
    assert MatchLogRecorder().finish().tracks == {}


def test_a_disk_that_refuses_the_tracks_loses_no_sample():
    # A file size limit below one model's track: the spill files stop growing part way (EFBIG, as a full disk
    # answers with ENOSPC) and the rest of each track stays in memory.
    code = textwrap.dedent(f"""
        import resource, signal, sys
        sys.path[:0] = {sys.path!r}
        signal.signal(signal.SIGXFSZ, signal.SIG_IGN)
        limit = 2 * {record._BLOCK} * 16 + 100  # two blocks and part of a sample
        resource.setrlimit(resource.RLIMIT_FSIZE, (limit, limit))
        from test_record import _record, _assert_tracks
        recorder, truth = _record(5 * {record._BLOCK} + 3, leave=range(10, 20))
        sizes = {{name: spill.size for name, spill in recorder._positions.items()}}
        assert all(size == limit - limit % 16 for size in sizes.values()), sizes  # whole samples only
        _assert_tracks(recorder, truth)
        print("ok")
    """)
    done = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=120,
                          cwd=str(__import__("pathlib").Path(__file__).parent))
    assert done.returncode == 0 and done.stdout.strip() == "ok", done.stderr[-2000:]
