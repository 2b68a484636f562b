"""The package is built in floors, and imports only go down.

Every module of ``clap_unified`` is parsed (not imported) and each of its
imports of ``clap_unified.*`` is resolved, relative or absolute, at module
level or inside a function, to the top-level unit it reaches (a subpackage
such as ``spaces`` or a module such as ``refine``). A module may import from
its own unit, from another unit on its own floor, or from a lower floor; an
import from a higher floor is reported with its file, line and target.
"""

from __future__ import annotations

import ast
import os
import subprocess
import sys
from pathlib import Path

import clap_unified

PACKAGE = "clap_unified"
ROOT = Path(clap_unified.__file__).resolve().parent

#: The package facade ``clap_unified/__init__.py``: ``from clap_unified import
#: fit`` (or ``from .. import fit``) reaches it, and it imports the strategies.
FACADE = "__init__"

#: Floors, bottom to top. Units on one floor may import each other; a unit
#: listed here that does not exist (yet, or any more) is ignored.
FLOORS = [
    # Foundations: argument checks, frozen data containers, user-file readers.
    ["_validation", "_compiled", "datatypes", "io"],
    # Manifolds of models (SE(2), SE(3), homographies, lines).
    ["geometry"],
    # Maps the spaces localize against (the RoboCup field).
    ["maps"],
    # Inliers and refitting on a space's protocol (one model, several models, spatial
    # coherence); spaces.base builds on it.
    ["refine", "partition", "coherence"],
    # Hypothesis spaces: model families, minimal solvers, residuals.
    ["spaces"],
    # The result types every strategy returns.
    ["result"],
    # The strategy registry, the presets and ``fit``, below the strategies that register.
    ["registry", "presets", "fitting", "segmenting"],
    # Strategies (``external``: other libraries' estimators as strategies; the
    # side-by-side ``compare`` while it exists).
    ["hough", "ransac", "clap", "preference", "external", "compare"],
    # The package facade re-exports strategies, spaces and ``fit``.
    [FACADE],
    # Applications.
    ["localization", "imaging"],
    # Drawing.
    ["viz"],
    # Experiments of the book and their claims.
    ["reproduce"],
    # The command line (``python -m clap_unified`` runs it).
    ["cli", "segment_cli", "__main__"],
]

FLOOR_OF = {unit: level for level, units in enumerate(FLOORS) for unit in units}

#: Known upward imports, ``(file, target module)``, each to be removed by moving
#: code down a floor (then delete the entry: a stale entry fails the test).
KNOWN_UPWARD: set = set()


def _module_name(path: Path) -> tuple[str, bool]:
    parts = list(path.relative_to(ROOT.parent).with_suffix("").parts)
    is_package = parts[-1] == "__init__"
    if is_package:
        parts = parts[:-1]
    return ".".join(parts), is_package


def _unit(module: str) -> str:
    """Top-level unit of a dotted ``clap_unified`` module name."""
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else FACADE


def _is_submodule(dotted: str) -> bool:
    path = ROOT.parent.joinpath(*dotted.split("."))
    return path.is_dir() or path.with_suffix(".py").is_file()


def _targets(node, module: str, is_package: bool):
    """Dotted ``clap_unified`` names an import statement reaches."""
    if isinstance(node, ast.Import):
        return [alias.name for alias in node.names]
    if node.level:
        package = module.split(".") if is_package else module.split(".")[:-1]
        base = package[: len(package) - node.level + 1]
        source = ".".join(base + ([node.module] if node.module else []))
    else:
        source = node.module
    if not source.startswith(PACKAGE):
        return []
    # ``from pkg import name``: name may be a submodule (``from .. import clap``)
    # or an attribute of pkg's __init__.
    return list(dict.fromkeys(
        f"{source}.{alias.name}" if _is_submodule(f"{source}.{alias.name}") else source
        for alias in node.names))


def _imports():
    """``(file, line, importing unit, target module)`` for every package import."""
    for path in sorted(ROOT.rglob("*.py")):
        module, is_package = _module_name(path)
        tree = ast.parse(path.read_text(encoding="utf-8"), filename=str(path))
        for node in ast.walk(tree):
            if not isinstance(node, ast.Import | ast.ImportFrom):
                continue
            for target in _targets(node, module, is_package):
                if target == PACKAGE or target.startswith(PACKAGE + "."):
                    yield path.relative_to(ROOT.parent), node.lineno, _unit(module), target


def test_every_unit_has_a_floor():
    units = {FACADE} | {
        p.stem for p in ROOT.iterdir()
        if (p.suffix == ".py" and p.stem != "__init__") or (p / "__init__.py").is_file()
    }
    missing = sorted(units - set(FLOOR_OF))
    assert not missing, f"top-level units with no floor in tests/test_floors.py: {missing}"


def test_imports_only_go_down():
    upward, known = [], set()
    for path, line, unit, target in _imports():
        target_unit = _unit(target)
        if target_unit == unit or target_unit not in FLOOR_OF or unit not in FLOOR_OF:
            continue  # same unit; units without a floor fail the test above
        if FLOOR_OF[target_unit] > FLOOR_OF[unit]:
            if (path.as_posix(), target) in KNOWN_UPWARD:
                known.add((path.as_posix(), target))
                continue
            upward.append(f"{path}:{line}: {unit} (floor {FLOOR_OF[unit]}) imports {target} "
                          f"({target_unit}, floor {FLOOR_OF[target_unit]})")
    assert not upward, "imports from a higher floor:\n" + "\n".join(upward)
    stale = sorted(KNOWN_UPWARD - known)
    assert not stale, f"KNOWN_UPWARD entries no longer needed, delete them: {stale}"


def test_the_import_resolver_sees_relative_absolute_and_nested_imports():
    imports = {(str(path), unit, target) for path, _, unit, target in _imports()}
    landmarks2d = str(Path(PACKAGE, "spaces", "landmarks2d.py"))
    assert (landmarks2d, "spaces", f"{PACKAGE}.maps.field") in imports
    viz_field = str(Path(PACKAGE, "viz", "field.py"))  # imported inside a function
    assert (viz_field, "viz", f"{PACKAGE}.maps.field") in imports


def test_importing_spaces_loads_no_application():
    code = (
        "import pkgutil, sys\n"
        "import clap_unified.spaces as spaces\n"
        "for info in pkgutil.iter_modules(spaces.__path__, spaces.__name__ + '.'):\n"
        "    __import__(info.name)\n"
        "print('\\n'.join(m for m in sys.modules if m.startswith(\n"
        "    ('clap_unified.localization', 'clap_unified.imaging'))))\n"
    )
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1")
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True,
                         check=True, env=env, cwd=ROOT.parent).stdout.split()
    assert out == [], f"importing clap_unified.spaces loaded applications: {out}"


def import_circles(edges: dict) -> list[list[str]]:
    """Every circle of ``edges`` (module -> modules it imports): the strongly connected
    components with more than one module (Tarjan's algorithm, iterative), each sorted."""
    index, low, stack, on_stack, circles = {}, {}, [], set(), []
    for root in sorted(edges):
        if root in index:
            continue
        work = [(root, iter(sorted(edges.get(root, ()))))]
        index[root] = low[root] = len(index)
        stack.append(root)
        on_stack.add(root)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(sorted(edges.get(child, ())))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    circles.append(sorted(component))
    return sorted(circles)


def test_the_circle_finder_finds_pairs_and_longer_circles():
    edges = {"a": {"b"}, "b": {"c"}, "c": {"a", "d"}, "d": {"e"}, "e": {"d"}, "f": {"a"}}
    assert import_circles(edges) == [["a", "b", "c"], ["d", "e"]]
    assert import_circles({"a": {"b"}, "b": {"c"}}) == []


def test_no_import_circles():
    """No module reaches itself through its imports (a pair importing each other or a longer
    circle; module level and inside functions alike). A package and its own submodules aside:
    ``__init__`` gathers what they define."""
    edges = {}
    for path, _line, _unit_name, target in _imports():
        module, _ = _module_name(ROOT.parent / path)
        if target.startswith(module + ".") or module.startswith(target + "."):
            continue  # a package importing its submodule, or a submodule its package
        edges.setdefault(module, set()).add(target)
    circles = import_circles(edges)
    assert not circles, "modules importing each other, in circles:\n" + "\n".join(
        " -> ".join(circle) for circle in circles)
