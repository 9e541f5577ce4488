"""Strategies of the user's own: a team names one, every robot of that team plays it (ROS nodes and lockstep).

Requires: a strategy spec, ``"package.module:ClassName"`` (importable from ``sys.path``) or
``"path/to/file.py:ClassName"`` (a relative path is taken from ``base``, e.g. the team YAML's folder).
Provides: ``strategy_class(spec, base)`` -> the class (a ``StrategyFactory``), ``resolve_spec`` (the spec with an
absolute file path, so a node started elsewhere finds the same file). The class is built like ``Strategy``:
``cls(params: ControlParams, world: WorldDescription, agent_id: int)``, and must offer ``step(TeamState)
-> ControlOutput`` and the attributes ``role`` and ``role_since`` [s]; subclassing ``Strategy`` and
overriding its methods gives all of that. ``StrategyPlugin`` and ``StrategyFactory`` say it as typing
``Protocol``s, so a checker holds a strategy of the user's own to them.
"""

from __future__ import annotations

import importlib
import importlib.util
import sys
from pathlib import Path
from typing import TYPE_CHECKING, Protocol, cast

from nubot_control import NubotControlError

if TYPE_CHECKING:
    from nubot_common.team_play import Role
    from nubot_common.world_description import WorldDescription
    from nubot_control.params import ControlParams
    from nubot_control.strategy import ControlOutput
    from nubot_control.team_state import TeamState

REQUIRED = ("step",)  # what a strategy class must define (role and role_since are set by its constructor)


class StrategyPlugin(Protocol):
    """What a robot's strategy offers the control stage: its role and since when [s], and a cycle's decision."""

    role: Role
    role_since: float

    def step(self, state: TeamState) -> ControlOutput:
        """One cycle: the team's state (the world model's decision, the robot's own view) in, its commands out."""
        ...


class StrategyFactory(Protocol):
    """A strategy class: built from the control parameters, the world description and the robot's AgentID."""

    def __call__(self, params: ControlParams, world: WorldDescription, agent_id: int) -> StrategyPlugin:
        ...


def _split(spec: str) -> tuple[str, str]:
    module, sep, name = spec.rpartition(":")
    if not sep or not module or not name.isidentifier():
        raise NubotControlError(f"strategy {spec!r}: write it as 'package.module:ClassName' or "
                                "'path/to/file.py:ClassName'")
    return module, name


def resolve_spec(spec: str, base: str | Path | None = None) -> str:
    """``spec`` with a file path made absolute against ``base`` (module paths are left as they are)."""
    if not spec:
        return spec
    module, name = _split(spec)
    if module.endswith(".py"):
        path = Path(module).expanduser()
        if not path.is_absolute() and base is not None:
            path = Path(base) / path
        return f"{path.resolve()}:{name}"
    return spec


def strategy_class(spec: str, base: str | Path | None = None) -> StrategyFactory:
    """Import the class ``spec`` names; raise ``NubotControlError`` saying what is missing."""
    module_name, name = _split(resolve_spec(spec, base))
    key = f"nubot_user_strategy_{abs(hash(module_name))}"
    try:
        if module_name.endswith(".py"):
            path = Path(module_name)
            if not path.is_file():
                raise NubotControlError(f"strategy {spec!r}: no file {path}")
            module = sys.modules.get(key)
            if module is None:
                loader_spec = importlib.util.spec_from_file_location(key, path)
                if loader_spec is None or loader_spec.loader is None:
                    raise NubotControlError(f"strategy {spec!r}: {path} is not a Python module")
                module = importlib.util.module_from_spec(loader_spec)
                sys.modules[key] = module
                loader_spec.loader.exec_module(module)
        else:
            module = importlib.import_module(module_name)
    except NubotControlError:
        raise
    except ImportError as exc:
        raise NubotControlError(f"strategy {spec!r}: cannot import module {module_name!r} ({exc}); is it on "
                                "PYTHONPATH, or give a file path") from None
    except Exception as exc:  # noqa: BLE001 - the user's module failed while loading: say so, no traceback
        sys.modules.pop(key, None)
        raise NubotControlError(f"strategy {spec!r}: loading {module_name} failed: "
                                f"{type(exc).__name__}: {exc}") from None
    cls = getattr(module, name, None)
    if not isinstance(cls, type):
        raise NubotControlError(f"strategy {spec!r}: module {module_name} has no class {name!r}")
    missing = [m for m in REQUIRED if not callable(getattr(cls, m, None))]
    if missing:
        raise NubotControlError(f"strategy {spec!r}: class {name} lacks {', '.join(missing)}")
    return cast("StrategyFactory", cls)
