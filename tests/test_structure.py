"""The shape of the code: imports go one way, modules and classes stay small (the core and the
app alike).

Read from the sources (no import): every module of ``gogreen_core`` and ``app``, its
module-level imports (those under ``if TYPE_CHECKING:`` and inside functions do not run when the
module loads, so they do not count).
"""

from __future__ import annotations

import ast
from pathlib import Path

ROOT = Path(__file__).resolve().parent.parent
PACKAGES = ("gogreen_core", "app")
#: Generated code (scripts/make_kernels.py) is not held to the limits below.
GENERATED = ("gogreen_core/_angular/",)
MAX_MODULE_LINES = 600
MAX_CLASS_METHODS = 40
#: Modules over the line limit for now, each with its owner (issue 24).
LINE_EXEMPT = {
    # being split into a package per file format on branch h-mesh (issue 24.5)
    "gogreen_core/mesh_io.py",
}


def _modules(package: str) -> dict[str, Path]:
    """Dotted module name → source file, for every module of ``package``."""
    found = {}
    for path in sorted((ROOT / package).rglob("*.py")):
        parts = path.relative_to(ROOT).with_suffix("").parts
        name = ".".join(parts[:-1] if parts[-1] == "__init__" else parts)
        found[name] = path
    return found


def _is_type_checking(test: ast.expr) -> bool:
    return (isinstance(test, ast.Name) and test.id == "TYPE_CHECKING") or (
        isinstance(test, ast.Attribute) and test.attr == "TYPE_CHECKING"
    )


def _module_level_imports(tree: ast.Module) -> list[ast.Import | ast.ImportFrom]:
    """Imports that run when the module loads: top level, and inside top-level ``if`` /
    ``try`` / ``with`` blocks, except ``if TYPE_CHECKING:`` ones."""
    found: list[ast.Import | ast.ImportFrom] = []

    def visit(body: list[ast.stmt]) -> None:
        for node in body:
            if isinstance(node, (ast.Import, ast.ImportFrom)):
                found.append(node)
            elif isinstance(node, ast.If):
                if not _is_type_checking(node.test):
                    visit(node.body)
                visit(node.orelse)
            elif isinstance(node, ast.Try):
                for block in (node.body, node.orelse, node.finalbody):
                    visit(block)
                for handler in node.handlers:
                    visit(handler.body)
            elif isinstance(node, ast.With):
                visit(node.body)

    visit(tree.body)
    return found


def _resolve(module: str, path: Path, node: ast.ImportFrom) -> str:
    """The absolute module name of a ``from ... import`` (relative ones resolved)."""
    if not node.level:
        return node.module or ""
    package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
    base = package[: len(package) - (node.level - 1)]
    return ".".join([*base, node.module] if node.module else base)


def import_graph() -> dict[str, set[str]]:
    """Module → the project modules it imports when it loads. ``from package import name``
    counts as importing the submodule ``package.name`` when there is one, else the package."""
    modules: dict[str, Path] = {}
    for package in PACKAGES:
        modules.update(_modules(package))
    graph: dict[str, set[str]] = {name: set() for name in modules}
    for name, path in modules.items():
        tree = ast.parse(path.read_text(encoding="utf-8"), str(path))
        for node in _module_level_imports(tree):
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            else:
                base = _resolve(name, path, node)
                targets = [
                    f"{base}.{alias.name}" if f"{base}.{alias.name}" in modules else base
                    for alias in node.names
                ]
            graph[name].update(t for t in targets if t in modules and t != name)
    return graph


def find_cycle(graph: dict[str, set[str]]) -> list[str] | None:
    """One import cycle of ``graph`` as a path [a, b, ..., a], or None."""
    state: dict[str, int] = {}  # 1: on the current path, 2: done
    path: list[str] = []

    def visit(node: str) -> list[str] | None:
        state[node] = 1
        path.append(node)
        for target in sorted(graph[node]):
            if state.get(target) == 1:
                return [*path[path.index(target) :], target]
            if target not in state:
                cycle = visit(target)
                if cycle:
                    return cycle
        path.pop()
        state[node] = 2
        return None

    for node in sorted(graph):
        if node not in state:
            cycle = visit(node)
            if cycle:
                return cycle
    return None


def test_the_cycle_finder_finds_cycles():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}, "d": set()}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b"}, "b": set(), "c": {"a", "b"}}) is None


def test_the_import_graph_sees_relative_and_package_imports():
    graph = import_graph()
    assert "gogreen_core.brushes.table" in graph["gogreen_core.brushes.brush"]
    assert "gogreen_core.sculptor" in graph["gogreen_core"]  # the package re-exports it
    # an import used only for type hints is no edge
    assert "gogreen_core.sculptor" not in graph["gogreen_core.session"]


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " → ".join(cycle or [])


def _source_files(packages: tuple[str, ...] = PACKAGES) -> list[tuple[str, Path]]:
    files = []
    for package in packages:
        for path in sorted((ROOT / package).rglob("*.py")):
            relative = path.relative_to(ROOT).as_posix()
            if not relative.startswith(GENERATED):
                files.append((relative, path))
    return files


def test_the_limits_read_both_packages():
    names = {relative for relative, _path in _source_files()}
    assert "app/main_window.py" in names and "gogreen_core/sculptor.py" in names
    assert not any(name.startswith(GENERATED) for name in names)


def test_no_module_is_over_600_lines():
    long = {
        relative: n
        for relative, path in _source_files()
        if (n := len(path.read_text(encoding="utf-8").splitlines())) > MAX_MODULE_LINES
    }
    assert set(long) <= LINE_EXEMPT, f"modules over {MAX_MODULE_LINES} lines: {long}"


def test_no_class_has_over_40_methods():
    crowded = {}
    for relative, path in _source_files():
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ClassDef):
                methods = [
                    n for n in node.body if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))
                ]
                if len(methods) > MAX_CLASS_METHODS:
                    crowded[f"{relative}:{node.name}"] = len(methods)
    assert not crowded, f"classes with over {MAX_CLASS_METHODS} methods: {crowded}"
