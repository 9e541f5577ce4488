"""JSON the project writes (results, reports, benchmarks): strict JSON (RFC 8259) that any reader takes.

Provides: ``strict_json(data, indent)``: the text of ``data`` with every non-finite float (an unknown interval's NaN,
an infinite rate) written as ``null``, never as the bare ``NaN`` or ``Infinity`` Python's ``json`` writes by default
and other readers refuse.
"""

from __future__ import annotations

import json
import math
from typing import Any


def finite_or_none(data: Any) -> Any:
    """``data`` with every non-finite float replaced by None, through dicts, lists and tuples."""
    if isinstance(data, float):
        return data if math.isfinite(data) else None
    if isinstance(data, dict):
        return {key: finite_or_none(value) for key, value in data.items()}
    if isinstance(data, (list, tuple)):
        return [finite_or_none(value) for value in data]
    return data


def strict_json(data: Any, indent: int | None = 2) -> str:
    """The strict JSON text of ``data`` (non-finite floats as null), with a final newline."""
    return json.dumps(finite_or_none(data), indent=indent, allow_nan=False) + "\n"
