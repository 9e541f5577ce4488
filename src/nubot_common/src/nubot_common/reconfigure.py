"""dynamic_reconfigure descriptions built at run time from a list of parameters.

Debian's dynamic_reconfigure ships the Python server but not the CMake code
generator, so a node describes its reconfigurable parameters as ``ReconfigureParam``
and ``config_type`` returns the object the server expects as its ``type``
(the same attributes a generated ``<Name>Config`` module has). No rospy here.
"""

from __future__ import annotations

from dataclasses import dataclass
from types import SimpleNamespace

_CTYPES = {"double": "double", "int": "int", "bool": "bool", "str": "std::string"}


@dataclass(frozen=True)
class ReconfigureParam:
    name: str
    kind: str  # "double", "int", "bool" or "str"
    default: float | int | bool | str
    minimum: float | int | bool | str
    maximum: float | int | bool | str
    description: str

    def __post_init__(self) -> None:
        if self.kind not in _CTYPES:
            raise ValueError(f"unknown parameter kind {self.kind!r} for {self.name}")
        if self.kind == "double":  # an int here would be encoded among the ints
            for attr in ("default", "minimum", "maximum"):
                object.__setattr__(self, attr, float(getattr(self, attr)))
        if self.kind in ("double", "int") and not float(self.minimum) <= float(self.default) <= float(self.maximum):
            raise ValueError(f"{self.name}: default {self.default} outside [{self.minimum}, {self.maximum}]")


def config_type(params: list[ReconfigureParam]) -> SimpleNamespace:
    """Return a dynamic_reconfigure config type describing ``params`` (one group, level 0)."""
    entries = [
        {
            "name": p.name, "type": p.kind, "default": p.default, "level": 0,
            "description": p.description, "min": p.minimum, "max": p.maximum,
            "srcline": 0, "srcfile": __file__, "edit_method": "",
            "ctype": _CTYPES[p.kind], "cconsttype": "const " + _CTYPES[p.kind],
        }
        for p in params
    ]
    description = {
        "name": "Default", "type": "", "state": True, "cstate": "true", "id": 0, "parent": 0,
        "parameters": entries, "groups": [], "srcline": 0, "srcfile": __file__,
        "class": "DEFAULT", "parentclass": "", "parentname": "Default", "field": "default",
        "upper": "DEFAULT", "lower": "groups",
    }
    return SimpleNamespace(
        config_description=description,
        defaults={p.name: p.default for p in params},
        min={p.name: p.minimum for p in params},
        max={p.name: p.maximum for p in params},
        level={p.name: 0 for p in params},
        type={p.name: p.kind for p in params},
        all_level=0,
    )
