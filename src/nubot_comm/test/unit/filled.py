"""Messages and packets with every field set to a value of its own, and a field-by-field comparison of two of them.

``fill`` walks a genpy message (or an LCM struct) and gives each number a distinct value (exact in float32),
each list three items and each header a stamp; ``differences`` lists the paths where two of them differ. A field
a conversion forgets keeps its default and shows up as a difference.
"""

from __future__ import annotations

import importlib
import itertools
from typing import Any

import genpy

NOT_CARRIED = {"seq", "frame_id"}  # of a header: rospy numbers messages itself; the team frame is implied
LIST_LENGTH = 3


def fill(obj: Any, counter: itertools.count | None = None) -> Any:
    """``obj`` (a genpy message or an LCM struct) with every field set, in place; returns it."""
    counter = counter if counter is not None else itertools.count(1)
    if isinstance(obj, genpy.Message):
        for name, kind in zip(obj.__slots__, obj._slot_types):
            setattr(obj, name, _ros_value(getattr(obj, name), kind, counter))
        return obj
    for name, kind, dims in zip(obj.__slots__, obj.__typenames__, obj.__dimensions__):
        if dims:  # an array of structs, sized by a count field set below
            cls = getattr(importlib.import_module("nubot_lcm"), kind.split(".")[1])
            setattr(obj, name, [fill(cls(), counter) for _ in range(LIST_LENGTH)])
        elif kind.startswith("nubot_lcm."):
            fill(getattr(obj, name), counter)
        else:
            setattr(obj, name, _number(kind, next(counter)))
    for name, dims in zip(obj.__slots__, obj.__dimensions__):
        if dims:
            setattr(obj, dims[0], len(getattr(obj, name)))
    return obj


def _ros_value(current: Any, kind: str, counter: itertools.count) -> Any:
    if kind == "std_msgs/Header":
        n = next(counter)
        current.stamp = genpy.Time(1_700_000_000 + n, 1000 * n + 7)
        return current
    if kind.endswith("[]"):
        package, name = kind[:-2].split("/")
        cls = getattr(importlib.import_module(f"{package}.msg"), name)
        return [fill(cls(), counter) for _ in range(LIST_LENGTH)]
    if isinstance(current, genpy.Message):
        return fill(current, counter)
    return _number(kind, next(counter))


def _number(kind: str, n: int) -> Any:
    if kind in ("bool", "boolean"):
        return n % 2 == 1
    if kind in ("float32", "float64", "float", "double"):
        return n + 0.25 if n % 2 else -(n + 0.5)  # exact in float32
    if kind in ("char", "uint8", "byte"):
        return n % 256
    if kind == "string":
        return "nubot"
    return n  # integers of every size: small and positive, valid everywhere


def differences(a: Any, b: Any, path: str = "") -> list[str]:
    """Paths of every field where ``a`` and ``b`` differ (headers' seq and frame_id left out)."""
    if isinstance(a, genpy.Message):
        if type(a) is not type(b):
            return [f"{path}: {type(a).__name__} against {type(b).__name__}"]
        found = []
        for name in a.__slots__:
            if a._type == "std_msgs/Header" and name in NOT_CARRIED:
                continue
            found += differences(getattr(a, name), getattr(b, name), f"{path}.{name}")
        return found
    if isinstance(a, list):
        if len(a) != len(b):
            return [f"{path}: {len(a)} items against {len(b)}"]
        return [d for i, (x, y) in enumerate(zip(a, b)) for d in differences(x, y, f"{path}[{i}]")]
    if isinstance(a, genpy.Time):
        return [] if (a.secs, a.nsecs) == (b.secs, b.nsecs) else [f"{path}: {a} against {b}"]
    if hasattr(a, "__slots__") and hasattr(a, "__typenames__"):
        return [d for name in a.__slots__ for d in differences(getattr(a, name), getattr(b, name), f"{path}.{name}")]
    return [] if a == b else [f"{path}: {a!r} against {b!r}"]
