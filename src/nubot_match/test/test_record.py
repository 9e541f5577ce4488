"""MatchLogRecorder keeps every model's track exactly, however long the match, and whatever the disk does."""

from __future__ import annotations

import subprocess
import sys
import tempfile
import textwrap

import numpy as np

from nubot_match import match_analysis as ma
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


def _resident_track_bytes() -> int:
    """The bytes of the recorder's track files (unnamed temporary files) that this process holds in memory."""
    unnamed = f"{tempfile.gettempdir()}/#"  # how a mapped file made without a name shows
    total, in_track = 0, False
    with open("/proc/self/smaps") as smaps:
        for line in smaps:
            first = line.split(maxsplit=1)[0]
            if "-" in first and not first.endswith(":"):  # a mapping's header line
                fields = line.split(maxsplit=5)
                in_track = len(fields) == 6 and fields[5].startswith(unnamed) and fields[5].rstrip().endswith(
                    "(deleted)")
            elif in_track and first == "Rss:":
                total += int(line.split()[1]) * 1024
    return total


def test_a_report_reads_a_long_match_s_tracks_a_piece_at_a_time():
    # 20 min of 100 Hz samples: the report's passes over them must not hold every track in memory at once.
    samples = 120_000
    recorder = MatchLogRecorder()
    i = np.arange(samples)
    one, two, ball = np.sin(i / 500.0).tolist(), (np.sin(i / 700.0) + 0.5).tolist(), np.cos(i / 300.0).tolist()
    for k in range(samples):
        recorder.model_states(k / 100.0, [("nubot1", RobotState(one[k], 0.0, 0, 0, 0, 0)),
                                          ("nubot2", RobotState(two[k], 0.1, 0, 0, 0, 0)),
                                          ("ball", BallState(0.2, ball[k], 0.11, 0, 0, 0))])
    log = recorder.finish()
    in_memory = {n: ma.Track(n, t.t.copy(), np.array(t.xy)) for n, t in log.tracks.items()}
    assert _resident_track_bytes() > 5 * 2**20  # the copies read them all; now let go
    for track in log.tracks.values():
        track.let_go()
    assert _resident_track_bytes() == 0
    intervals = [(0.0, samples / 100.0)]
    contacts = ma.collisions(log.tracks, intervals, hull_radius=0.2)
    reaches = ma.ball_reaches(log.tracks, intervals, ball_name="ball")
    runs = [ma.distance_run(log.tracks[n]) for n in ("nubot1", "nubot2")]
    ball = ma.ball_time_in_play(log.tracks["ball"], intervals)
    assert _resident_track_bytes() < 2**20  # of 5.5 MiB of tracks
    # ... and gets what it gets from tracks held in memory, to the last bit
    assert contacts == ma.collisions(in_memory, intervals, hull_radius=0.2) and len(contacts) > 10
    assert reaches == ma.ball_reaches(in_memory, intervals, ball_name="ball") and len(reaches[0]) > 10
    assert runs == [ma.distance_run(in_memory[n]) for n in ("nubot1", "nubot2")]
    np.testing.assert_array_equal(ball.xy, ma.ball_time_in_play(in_memory["ball"], intervals).xy)
