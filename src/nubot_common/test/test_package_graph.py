"""The packages' dependencies, derived from the code: every package a module imports is declared in the importer's
package.xml (``exec_depend``/``depend`` for a package's modules and nodes, also ``test_depend`` for its tests), and
the declared graph has no loop (catkin orders the build by it and refuses a loop).

Every import is declared. An import that closed a loop and could not be declared yet would go into ``UNDECLARED``
with what is to break it; a test fails once one of them is no longer needed, so that the list only shrinks.
"""

import ast
import re
import xml.etree.ElementTree as ElementTree
from collections.abc import Iterator
from pathlib import Path

WORKSPACE_SRC = Path(__file__).resolve().parents[2]
PACKAGES = sorted(p.parent.name for p in WORKSPACE_SRC.glob("*/package.xml"))
RUN_TAGS = ("depend", "exec_depend", "build_depend", "build_export_depend")

# (importer, imported, where: "code" or "tests"): why the import is not declared yet.
UNDECLARED: dict[tuple[str, str, str], str] = {}


def _sources(package: str) -> Iterator[tuple[Path, str]]:
    """The package's Python files (modules, nodes and scripts without a suffix) and whether each is code or tests."""
    root = WORKSPACE_SRC / package
    for path in sorted(root.rglob("*")):
        if not path.is_file() or "__pycache__" in path.parts:
            continue
        script = path.suffix == "" and path.parent.name in ("nodes", "scripts") and path.read_bytes()[:2] == b"#!"
        if path.suffix == ".py" or script:
            yield path, "tests" if "test" in path.relative_to(root).parts[:1] else "code"


def imports() -> dict[tuple[str, str, str], list[str]]:
    """(importer, imported, "code" or "tests") -> where, for every import of another workspace package."""
    found: dict[tuple[str, str, str], list[str]] = {}
    for package in PACKAGES:
        for path, where in _sources(package):
            tree = ast.parse(path.read_text(), str(path))
            for node in ast.walk(tree):
                if isinstance(node, ast.Import):
                    modules = [alias.name for alias in node.names]
                elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
                    modules = [node.module]
                else:
                    continue
                for module in modules:
                    top = module.split(".")[0]
                    if top in PACKAGES and top != package:
                        found.setdefault((package, top, where), []).append(
                            f"{path.relative_to(WORKSPACE_SRC)}:{node.lineno}")
    return found


def declared() -> dict[str, dict[str, set[str]]]:
    """package -> {"code": what its modules may import, "tests": what its tests may import}."""
    out = {}
    for package in PACKAGES:
        root = ElementTree.parse(WORKSPACE_SRC / package / "package.xml").getroot()
        run = {e.text.strip() for tag in RUN_TAGS for e in root.iter(tag) if e.text}
        test = {e.text.strip() for e in root.iter("test_depend") if e.text}
        out[package] = {"code": run, "tests": run | test}
    return out


def loop_through(graph: dict[str, set[str]], start: str) -> list[str] | None:
    """A path of packages from ``start`` back to itself in ``graph``, or None."""
    stack, seen = [(start, [start])], set()
    while stack:
        package, path = stack.pop()
        for dep in sorted(graph.get(package, ())):
            if dep == start:
                return [*path, start]
            if dep not in seen and dep in PACKAGES:
                seen.add(dep)
                stack.append((dep, [*path, dep]))
    return None


def test_the_workspace_has_packages_and_imports():
    assert len(PACKAGES) >= 10 and len(imports()) >= 20, (PACKAGES, len(imports()))


def test_every_imported_package_is_declared():
    have = declared()
    missing = [f"{importer} ({where}) imports {imported} undeclared, e.g. {places[0]}"
               for (importer, imported, where), places in sorted(imports().items())
               if imported not in have[importer][where] and (importer, imported, where) not in UNDECLARED]
    assert not missing, "\n".join(missing)


def test_the_declared_packages_have_no_loop():
    have = declared()
    graph = {p: {d for d in have[p]["tests"] if d in PACKAGES} for p in PACKAGES}
    loops = [" -> ".join(path) for p in PACKAGES if (path := loop_through(graph, p))]
    assert not loops, "\n".join(loops)


def test_each_undeclared_import_is_still_there_and_closes_a_loop():
    """An entry of ``UNDECLARED`` whose import went away, or that no longer closes a loop (it could be declared),
    is to be removed from the list."""
    found, have = imports(), declared()
    graph = {p: {d for d in have[p]["tests"] if d in PACKAGES} for p in PACKAGES}
    stale = [key for key in UNDECLARED if key not in found or key[1] in have[key[0]][key[2]]]
    declarable = [key for key in UNDECLARED if key in found
                  and loop_through({**graph, key[0]: graph[key[0]] | {key[1]}}, key[0]) is None]
    assert not stale and not declarable, f"no longer imported or already declared: {stale}; " \
                                         f"closes no loop, declare it instead: {declarable}"


def test_the_package_names_in_the_manifests_are_their_folders():
    wrong = [p for p in PACKAGES
             if re.sub(r"\s", "", ElementTree.parse(WORKSPACE_SRC / p / "package.xml").getroot().findtext("name", ""))
             != p]
    assert not wrong, wrong
