"""Property-based: a file from elsewhere is read whole or refused with its reader's own error, never another
exception: a match bag, for the report (nubot_match.bag_reader) and for replay, cut short or with bytes changed; a
colour table file likewise."""

import functools
import os
import tempfile
from pathlib import Path

from hypothesis import given, settings
from hypothesis import strategies as st

from nubot_match.bag import BagRecorder
from nubot_match.bag_reader import MatchBagError, read_match
from nubot_match.config import match_config
from nubot_match.engine import LockstepMatch
from nubot_tools.replay import load_timeline
from omni_vision import OmniVisionError
from omni_vision.colors import ColorTable


@functools.cache
def _bag() -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "match.bag"
        match = LockstepMatch(match_config(half_seconds=1.0, halves=1), [BagRecorder(path, robots=False)])
        match.reset(0)
        match.run()
        match.close()
        return path.read_bytes()


@functools.cache
def _table() -> bytes:
    with tempfile.TemporaryDirectory() as folder:
        path = Path(folder) / "table.colors"
        ColorTable.empty().save(path)
        return path.read_bytes()


def _damaged(valid: bytes) -> st.SearchStrategy[bytes]:
    """``valid`` cut short, or with up to 16 bytes changed anywhere."""
    edits = st.lists(st.tuples(st.integers(0, len(valid) - 1), st.integers(0, 255)), min_size=1, max_size=16)
    return st.integers(0, len(valid) - 1).map(lambda n: valid[:n]) | edits.map(lambda e: _edit(valid, e))


def _edit(valid: bytes, edits: list[tuple[int, int]]) -> bytes:
    data = bytearray(valid)
    for at, value in edits:
        data[at] = value
    return bytes(data)


def _written(data: bytes) -> Path:
    handle, name = tempfile.mkstemp(suffix=".bag")
    os.write(handle, data)
    os.close(handle)
    return Path(name)


@settings(max_examples=12)  # each example reads a bag twice; make bench's probe is the long run
@given(st.data())
def test_a_damaged_match_bag_is_read_or_refused_for_the_report_and_for_replay(data):
    path = _written(data.draw(_damaged(_bag())))
    try:
        for read in (lambda p: read_match(p, warn=lambda _line: None), load_timeline):
            try:
                read(path)
            except MatchBagError:
                pass
    finally:
        path.unlink()


@settings(max_examples=40)
@given(st.data())
def test_a_damaged_colour_table_is_loaded_or_refused_with_the_reason(data):
    path = _written(data.draw(_damaged(_table())))
    try:
        ColorTable.load(path)
    except OmniVisionError:
        pass
    finally:
        path.unlink()
