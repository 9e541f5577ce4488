"""Pair the items of two streams that carry the same stamp, in whichever order they come (no ROS).

Provides: ``StampPairs`` (``first(stamp, a)`` and ``second(stamp, b)`` each return the other stream's item of that
stamp once both have come, else keep theirs; the ``kept`` newest of each side are kept). The vision node pairs each
processed camera frame with the simulator's truth of its stamp this way: on a busy machine either may come first.
"""

from __future__ import annotations

from typing import Generic, TypeVar

A = TypeVar("A")
B = TypeVar("B")


class StampPairs(Generic[A, B]):
    def __init__(self, kept: int, digits: int = 4) -> None:
        self.kept, self.digits = kept, digits
        self._first: dict[float, A] = {}
        self._second: dict[float, B] = {}

    def first(self, stamp: float, item: A) -> B | None:
        """``item`` of the first stream at ``stamp`` [s]: the second stream's item of that stamp, or None (``item``
        is then kept for it)."""
        return self._arrive(round(stamp, self.digits), item, self._first, self._second)

    def second(self, stamp: float, item: B) -> A | None:
        """The same for an item of the second stream."""
        return self._arrive(round(stamp, self.digits), item, self._second, self._first)

    def _arrive(self, key: float, item, mine: dict, theirs: dict):
        match = theirs.pop(key, None)
        if match is None:
            mine[key] = item
            while len(mine) > self.kept:
                mine.pop(next(iter(mine)))
        return match


__all__ = ["StampPairs"]
