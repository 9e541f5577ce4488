"""A strategy of the user's own (nubot_control.plugins): loaded from a file or a module, refused with the reason,
and held by a type checker to the ``StrategyPlugin`` / ``StrategyFactory`` protocols the control stage uses."""

import subprocess
import sys
import textwrap
from pathlib import Path

import pytest

from nubot_common.world_description import WorldDescription
from nubot_control import NubotControlError
from nubot_control.agent import Controller
from nubot_control.params import ControlParams
from nubot_control.plugins import resolve_spec, strategy_class

WORKSPACE_SRC = Path(__file__).resolve().parents[3]
CLEVER = '''
from nubot_control.plugins import StrategyFactory, StrategyPlugin
from nubot_control.strategy import ControlOutput, Strategy
from nubot_control.team_state import TeamState


class Clever(Strategy):
    """Plays the shipped strategy and counts its cycles."""

    cycles = 0

    def step(self, state: TeamState) -> ControlOutput:
        Clever.cycles += 1
        return super().step(state)


FACTORY: StrategyFactory = Clever
'''
WRONG = '''
from nubot_control.plugins import StrategyFactory
from nubot_control.strategy import Strategy


class Wrong(Strategy):
    def step(self, state: int) -> str:  # type: ignore[override]
        return "no"


FACTORY: StrategyFactory = Wrong
'''


def test_a_strategy_file_is_loaded_and_played_by_the_control_stage(tmp_path):
    (tmp_path / "clever.py").write_text(CLEVER)
    spec = resolve_spec("clever.py:Clever", tmp_path)
    assert spec == f"{tmp_path / 'clever.py'}:Clever"
    controller = Controller(ControlParams(strategy=spec), WorldDescription(), 2)
    assert type(controller.strategy).__name__ == "Clever"
    assert strategy_class(spec) is type(controller.strategy)


@pytest.mark.parametrize(("spec", "reason"), [
    ("no_colon", "write it as"), ("missing.py:Clever", "no file"), ("no_such_module_xyz:Clever", "cannot import"),
    ("clever.py:Absent", "has no class 'Absent'"), ("clever.py:NOT_A_CLASS", "has no class"),
    ("stepless.py:Stepless", "lacks step"), ("broken.py:Broken", "loading .* failed: ZeroDivisionError")])
def test_a_strategy_that_cannot_play_is_refused_with_the_reason(tmp_path, spec, reason):
    (tmp_path / "clever.py").write_text(CLEVER + "\nNOT_A_CLASS = 3\n")
    (tmp_path / "stepless.py").write_text("class Stepless:\n    pass\n")
    (tmp_path / "broken.py").write_text("1 / 0\n")
    with pytest.raises(NubotControlError, match=reason):
        strategy_class(spec, tmp_path)


def test_a_type_checker_holds_a_strategy_to_the_protocols(tmp_path):
    """mypy accepts the subclass that keeps ``step``'s types and refuses one whose ``step`` takes and returns
    something else, by the ``StrategyFactory`` protocol alone (the override itself is silenced)."""
    (tmp_path / "clever.py").write_text(textwrap.dedent(CLEVER))
    (tmp_path / "wrong.py").write_text(textwrap.dedent(WRONG))
    paths = ":".join(str(p) for p in sorted(WORKSPACE_SRC.glob("*/src")))

    def check(name: str) -> subprocess.CompletedProcess[str]:
        return subprocess.run([sys.executable, "-m", "mypy", "--strict", "--follow-imports=silent",
                               "--ignore-missing-imports", "--no-incremental", "--cache-dir", "/dev/null",
                               str(tmp_path / name)], capture_output=True, text=True, env={"MYPYPATH": paths},
                              check=False)

    good, bad = check("clever.py"), check("wrong.py")
    assert good.returncode == 0, good.stdout
    assert bad.returncode == 1 and "StrategyFactory" in bad.stdout, bad.stdout
