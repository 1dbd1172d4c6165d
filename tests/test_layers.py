"""The package's layers: imports go downward only, no import circle, the wall solver apart.

Every ``import`` and ``from ... import`` of ``stonedem`` in ``src/stonedem`` is read with
``ast.walk``, so imports inside functions count too. The layers, bottom to top (one row
each; packages on one row may not import each other):

    version, errors, units < io < entry < options < kernels < reference < motion < engine
    < validation < study < fragility < figures < api < cli < __main__ and the package face

``wall`` stands beside the stack and imports only ``version``, ``errors``, ``entry`` and
``io``; only the public face (``api``) and the command line import it. ``api`` (what a
script needs) may import everything below it; only the command line and the package face
import it. The benchmarks (``benchmarks/``, not installed) sit above all of it: the package
never imports them.
"""

from __future__ import annotations

import ast
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "src" / "stonedem"
LAYERS = [
    {"version", "errors", "units", "_records"},
    {"io"},
    {"entry"},
    {"options"},
    {"kernels"},
    {"reference"},
    {"motion"},
    {"engine"},
    {"validation"},
    {"study"},
    {"fragility"},
    {"figures"},
    {"api"},
    {"cli"},
    {"__main__", ""},  # "": the package's own __init__, its public face
]
WALL_MAY_IMPORT = {"version", "errors", "units", "entry", "io", "wall"}
# the layers that may import the wall solver
WALL_IMPORTED_BY = {"api", "cli", "__main__", ""}


def module_name(path: Path) -> str:
    parts = list(path.relative_to(PACKAGE.parent).with_suffix("").parts)
    if parts[-1] == "__init__":
        parts.pop()
    return ".".join(parts)


MODULES = {module_name(p): p for p in PACKAGE.rglob("*.py")}


def imported_modules(path: Path) -> set[str]:
    """The stonedem modules a file imports, at any depth of its code."""
    found = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            names = [alias.name for alias in node.names]
        elif isinstance(node, ast.ImportFrom) and node.level == 0 and node.module:
            # "from a.b import c" imports the module a.b.c where there is one, else a.b
            names = [
                f"{node.module}.{alias.name}"
                if f"{node.module}.{alias.name}" in MODULES
                else node.module
                for alias in node.names
            ]
        else:
            continue
        found.update(name for name in names if name.split(".")[0] == "stonedem")
    return found


GRAPH = {name: imported_modules(path) - {name} for name, path in MODULES.items()}


def top_package(module: str) -> str:
    parts = module.split(".")
    return parts[1] if len(parts) > 1 else ""


def layer_of(package: str) -> int:
    return next(i for i, layer in enumerate(LAYERS) if package in layer)


def test_every_package_has_a_layer():
    packages = {top_package(m) for m in MODULES} - {"wall"}
    assert not [p for p in packages if not any(p in layer for layer in LAYERS)]


def test_imports_go_downward_only():
    wrong = []
    for module, targets in GRAPH.items():
        here = top_package(module)
        for target in targets:
            there = top_package(target)
            if here == there:
                continue
            if here == "wall":
                if there not in WALL_MAY_IMPORT:
                    wrong.append(
                        f"{module} -> {target} (wall imports only {sorted(WALL_MAY_IMPORT)})"
                    )
            elif there == "wall":
                if here not in WALL_IMPORTED_BY:
                    wrong.append(
                        f"{module} -> {target} (only the public face and the command line "
                        "import wall)"
                    )
            elif layer_of(there) >= layer_of(here):
                wrong.append(f"{module} -> {target} ({there} is not below {here})")
    assert not wrong, "\n".join(sorted(wrong))


def strongly_connected(graph: dict[str, set[str]]) -> list[list[str]]:
    """Tarjan's strongly connected components with more than one module."""
    index, low, stack, on_stack, found, counter = {}, {}, [], set(), [], [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in graph.get(v, ()):
            if w not in graph:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                found.append(sorted(component))

    for v in graph:
        if v not in index:
            visit(v)
    return found


def test_no_import_circle():
    assert strongly_connected(GRAPH) == []


def test_the_circle_finder_finds_a_circle():
    assert strongly_connected({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": {"a"}}) == [["a", "b", "c"]]


@pytest.mark.parametrize("package", ["wall", "io", "motion"])
def test_a_low_layer_loads_no_engine(package):
    """Importing the wall solver, the writer or the record tools never loads the 2D engine."""
    import subprocess
    import sys

    code = (
        f"import stonedem.{package}, pkgutil, importlib, sys\n"
        f"for m in pkgutil.walk_packages(stonedem.{package}.__path__, 'stonedem.{package}.'):\n"
        "    if not m.name.endswith('__main__'): importlib.import_module(m.name)\n"
        "print(sorted({n.split('.')[1] for n in sys.modules if n.startswith('stonedem.')}))"
    )
    out = subprocess.run(
        [sys.executable, "-c", code], capture_output=True, text=True, check=True
    ).stdout
    loaded = set(ast.literal_eval(out.strip()))
    assert not loaded & {"engine", "study", "validation", "fragility", "figures"}, loaded


def test_the_package_never_imports_the_benchmarks():
    """benchmarks/ is not installed, so an import of it from src would fail in a wheel."""
    wrong = []
    for module, path in MODULES.items():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            names = []
            if isinstance(node, ast.Import):
                names = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom) and node.module:
                names = [node.module]
            wrong += [f"{module} -> {n}" for n in names if n.split(".")[0] == "benchmarks"]
    assert not wrong, wrong
