"""The LCM types kept in src/nubot_lcm are exactly what lcm-gen makes of lcm/*.lcm today (no drift either way)."""

import shutil
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2]
DEFINITIONS = sorted((PACKAGE / "lcm").glob("*.lcm"))
KEPT = PACKAGE / "src" / "nubot_lcm"


def lcm_gen() -> str | None:
    beside = Path(sys.executable).parent / "lcm-gen"
    return str(beside) if beside.exists() else shutil.which("lcm-gen")


def test_the_kept_python_types_are_what_lcm_gen_makes_of_the_definitions(tmp_path):
    tool = lcm_gen()
    if tool is None:
        pytest.skip("lcm-gen not found (pip install lcm, requirements.txt)")
    subprocess.run([tool, "-p", "--ppath", str(tmp_path), *map(str, DEFINITIONS)], check=True, timeout=60)
    made = {p.name: p.read_text() for p in (tmp_path / "nubot_lcm").glob("*.py")}
    kept = {p.name: p.read_text() for p in KEPT.glob("*.py")}
    assert sorted(made) == sorted(kept), "regenerate: lcm-gen -p --ppath src lcm/*.lcm (in src/nubot_comm)"
    changed = [name for name in made if made[name] != kept[name]]
    assert not changed, f"{changed} differ from lcm-gen's output: regenerate with lcm-gen -p --ppath src lcm/*.lcm"
