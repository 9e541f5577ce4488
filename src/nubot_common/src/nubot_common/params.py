"""Typed parameter loading: a nested mapping (YAML, the ROS parameter server) into frozen dataclasses.

Provides: ``from_mapping(cls, data)`` which builds ``cls`` from ``data``,
converting numbers and recursing into nested dataclass fields, and
``load_yaml(cls, path)``. Unknown keys and values of the wrong type raise
``NubotCommonError`` naming the offending key, so a typo in a config file is
reported instead of silently ignored. Range checks belong in each dataclass's
``__post_init__``.
"""

from __future__ import annotations

import dataclasses
import math
import typing
from collections.abc import Mapping
from pathlib import Path
from typing import Any, TypeVar

import yaml

from nubot_common import NubotCommonError

T = TypeVar("T")


def _convert(value: Any, annotation: Any, where: str) -> Any:
    origin = typing.get_origin(annotation)
    if dataclasses.is_dataclass(annotation):
        if isinstance(value, annotation):
            return value
        if not isinstance(value, Mapping):
            raise NubotCommonError(f"{where}: expected a mapping, got {value!r}")
        return from_mapping(annotation, value, where)
    if origin is tuple:
        args = typing.get_args(annotation)
        if not isinstance(value, (list, tuple)):
            raise NubotCommonError(f"{where}: expected a list, got {value!r}")
        if len(args) == 2 and args[1] is Ellipsis:
            return tuple(_convert(v, args[0], f"{where}[{i}]") for i, v in enumerate(value))
        if len(args) != len(value):
            raise NubotCommonError(f"{where}: expected {len(args)} values, got {len(value)}")
        return tuple(_convert(v, a, f"{where}[{i}]") for i, (v, a) in enumerate(zip(value, args)))
    if annotation is float:
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise NubotCommonError(f"{where}: expected a number, got {value!r}")
        try:
            number = float(value)
        except OverflowError:
            number = math.inf
        if not math.isfinite(number):
            raise NubotCommonError(f"{where}: expected a finite number, got {value!r}")
        return number
    if annotation is int:
        if isinstance(value, bool) or not isinstance(value, int):
            raise NubotCommonError(f"{where}: expected an integer, got {value!r}")
        return value
    if annotation is bool:
        if not isinstance(value, bool):
            raise NubotCommonError(f"{where}: expected true or false, got {value!r}")
        return value
    if annotation is str:
        if not isinstance(value, str):
            raise NubotCommonError(f"{where}: expected a string, got {value!r}")
        return value
    return value


def from_mapping(cls: type[T], data: Mapping[str, Any] | None, where: str = "") -> T:
    """Build the dataclass ``cls`` from ``data``; missing keys keep their defaults."""
    if data is None:
        data = {}
    if not isinstance(data, Mapping):
        raise NubotCommonError(f"{where or cls.__name__}: expected a mapping of parameters, got {data!r}")
    data = dict(data)
    hints = typing.get_type_hints(cls)
    fields = {f.name: f for f in dataclasses.fields(cls) if f.init}
    unknown = sorted(str(key) for key in set(data) - set(fields))
    if unknown:
        raise NubotCommonError(
            f"{where or cls.__name__}: unknown parameter(s) {', '.join(unknown)}; "
            f"known: {', '.join(sorted(fields))}"
        )
    kwargs = {
        name: _convert(value, hints[name], f"{where}.{name}" if where else name)
        for name, value in data.items()
    }
    try:
        return cls(**kwargs)
    except (TypeError, ValueError) as exc:
        raise NubotCommonError(f"{where or cls.__name__}: {exc}") from exc


def require_positive(obj: object, *names: str) -> None:
    """Raise ValueError naming the first of ``names`` whose value on ``obj`` is not > 0 (for __post_init__)."""
    for name in names:
        if not getattr(obj, name) > 0.0:
            raise ValueError(f"{name} must be positive, got {getattr(obj, name)}")


def require_non_negative(obj: object, *names: str) -> None:
    """Raise ValueError naming the first of ``names`` whose value on ``obj`` is < 0 (for __post_init__)."""
    for name in names:
        if not getattr(obj, name) >= 0.0:
            raise ValueError(f"{name} must not be negative, got {getattr(obj, name)}")


def load_yaml(cls: type[T], path: str | Path) -> T:
    """Read a YAML file into the dataclass ``cls``."""
    with open(path, encoding="utf-8") as handle:
        data = yaml.safe_load(handle)
    return from_mapping(cls, data, Path(path).name)


def to_mapping(obj: Any) -> dict[str, Any]:
    """Turn a (nested) dataclass back into plain dicts and lists."""
    def plain(value: Any) -> Any:
        if dataclasses.is_dataclass(value):
            return {f.name: plain(getattr(value, f.name)) for f in dataclasses.fields(value)}
        if isinstance(value, tuple):
            return [plain(v) for v in value]
        return value
    result: dict[str, Any] = plain(obj)
    return result
