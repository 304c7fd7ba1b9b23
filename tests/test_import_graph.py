"""The Python modules form layers: no import cycle, and only the CLI imports the CLI.

Modules are read with ``ast`` (nothing is imported): usdksl/ as ``usdksl.*``, cli/ as ``usdksl.cli.*``
(where the wheel installs it) and benchmarks/ as top-level script modules. Every import counts, also
those inside functions; importing a submodule does not count as importing its parent packages.
"""

import ast
from pathlib import Path
from typing import Dict, List, Optional, Set

REPO_ROOT = Path(__file__).resolve().parent.parent
PACKAGE_FOLDERS = {"usdksl": REPO_ROOT / "usdksl", "usdksl.cli": REPO_ROOT / "cli"}
SCRIPT_FOLDERS = [REPO_ROOT / "benchmarks"]
#: Modules that are not .py files in the tree (the compiled core).
EXTENSION_MODULES = {"usdksl._native"}


def _modules() -> Dict[str, tuple]:
    """{module name: (path, is_package)} of every module of the product and the benchmarks."""
    found = {}
    for package, folder in PACKAGE_FOLDERS.items():
        for path in sorted(folder.rglob("*.py")):
            parts = list(path.relative_to(folder).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            found[".".join([package] + parts)] = (path, is_package)
    for folder in SCRIPT_FOLDERS:
        for path in sorted(folder.glob("*.py")):
            found[path.stem] = (path, False)
    return found


def _known(name: str, known: Set[str]) -> Optional[str]:
    """The longest known module that ``name`` is or lies in (None for third-party modules)."""
    parts = name.split(".")
    for end in range(len(parts), 0, -1):
        candidate = ".".join(parts[:end])
        if candidate in known:
            return candidate
    return None


def import_graph() -> Dict[str, Set[str]]:
    modules = _modules()
    known = set(modules) | EXTENSION_MODULES
    graph: Dict[str, Set[str]] = {name: set() for name in known}
    for name, (path, is_package) in modules.items():
        package = name if is_package else name.rpartition(".")[0]
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            targets: List[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                if node.level:
                    base_parts = package.split(".")[:len(package.split(".")) - node.level + 1]
                    base = ".".join(base_parts + ([node.module] if node.module else []))
                else:
                    base = node.module or ""
                # `from package import submodule` imports the submodule; `from module import name` the module
                targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                           for alias in node.names]
            for target in targets:
                resolved = _known(target, known)
                if resolved is not None and resolved != name:
                    graph[name].add(resolved)
    return graph


def find_cycle(graph: Dict[str, Set[str]]) -> Optional[List[str]]:
    """One import cycle as [a, b, ..., a], or None."""
    state: Dict[str, int] = {}   # 1 on the current path, 2 done
    path: List[str] = []

    def visit(node: str) -> Optional[List[str]]:
        state[node] = 1
        path.append(node)
        for successor in sorted(graph.get(node, ())):
            if state.get(successor) == 1:
                return path[path.index(successor):] + [successor]
            if successor not in state:
                cycle = visit(successor)
                if cycle:
                    return cycle
        path.pop()
        state[node] = 2
        return None

    for start in sorted(graph):
        if start not in state:
            cycle = visit(start)
            if cycle:
                return cycle
    return None


def test_cycle_finder_finds_a_cycle_and_accepts_layers():
    assert find_cycle({"a": {"b"}, "b": {"c"}, "c": {"a"}}) == ["a", "b", "c", "a"]
    assert find_cycle({"a": {"b", "c"}, "b": {"c"}, "c": set()}) is None


def test_graph_reads_relative_and_function_level_imports():
    graph = import_graph()
    assert "usdksl._native" in graph["usdksl.checking.collision"]        # from .. import _native
    assert "usdksl.reading.loader" in graph["usdksl.checking.pipeline"]   # from ..reading.loader import ...
    assert "usdksl.checking.pipeline" in graph["usdksl.cli.check"]
    assert "suite" in graph["report"] and "suite" in graph["run"]


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_only_the_cli_imports_the_cli():
    offenders = sorted(name for name, targets in import_graph().items()
                       if not name.startswith("usdksl.cli") and any(t.startswith("usdksl.cli") for t in targets))
    assert offenders == []
