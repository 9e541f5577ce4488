"""Pure cores: no module under src/<pkg>/src/ imports rospy (STYLE.md practice 1)."""

import ast
from pathlib import Path

WORKSPACE_SRC = Path(__file__).resolve().parents[2]


def test_core_modules_never_import_rospy():
    offenders = []
    cores = sorted(WORKSPACE_SRC.glob("*/src/*/**/*.py"))
    assert cores, "no core modules found"
    for path in cores:
        tree = ast.parse(path.read_text(), str(path))
        for node in ast.walk(tree):
            names = [a.name for a in node.names] if isinstance(node, ast.Import) else \
                [node.module or ""] if isinstance(node, ast.ImportFrom) else []
            if any(n == "rospy" or n.startswith("rospy.") for n in names):
                offenders.append(f"{path.relative_to(WORKSPACE_SRC)}:{node.lineno}")
    assert not offenders, f"core modules import rospy: {offenders}"
