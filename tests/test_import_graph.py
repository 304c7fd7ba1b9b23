"""The Python modules stand on floors: no import runs up a floor, no import cycle, only the CLI imports the CLI.

Modules are read with ``ast`` (nothing is imported), each folder under the package name the wheel installs it
as (``[tool.scikit-build.wheel.packages]`` in pyproject.toml: usdksl/ as ``usdksl.*``, cli/ as ``usdksl.cli.*``),
and benchmarks/ as top-level script modules. Every import counts, also those inside functions; importing a
submodule does not count as importing its parent packages. The floors are read from the table under
"## Floors" in usdksl/README.md.
"""

import ast
import re
from pathlib import Path
from typing import Dict, List, Mapping, Optional, Sequence, Set

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
ROOT_PACKAGE = "usdksl"
SCRIPT_FOLDERS = [REPO_ROOT / "benchmarks"]
#: Modules that are not .py files in the tree: the compiled core, the version file the build writes.
EXTENSION_MODULES = {"usdksl._native", "usdksl._version"}
WHEEL_PACKAGES_SECTION = "[tool.scikit-build.wheel.packages]"
WHEEL_PACKAGE_ENTRY = re.compile(r'^\s*"?([\w/.]+)"?\s*=\s*"([^"]+)"\s*$')
FLOOR_ROW = re.compile(r"^\|\s*(\d+)\s*\|(.*)\|(.*)\|(.*)\|\s*$")
LISTED_NAME = re.compile(r"`([\w.]+)`")


def wheel_packages(pyproject: Path = REPO_ROOT / "pyproject.toml") -> Dict[str, Path]:
    """{package name: source folder} as the wheel installs them (``"usdksl/cli" = "cli"``: cli/ is usdksl.cli)."""
    section = pyproject.read_text().split(WHEEL_PACKAGES_SECTION, 1)[1].split("\n[", 1)[0]
    folders = {}
    for line in section.splitlines():
        match = WHEEL_PACKAGE_ENTRY.match(line)
        if match:
            folders[match.group(1).replace("/", ".")] = pyproject.parent / match.group(2)
    assert ROOT_PACKAGE in folders, f"{pyproject}: no wheel package {ROOT_PACKAGE!r}"
    return folders


def _modules(package_folders: Mapping[str, Path], script_folders: Sequence[Path]) -> Dict[str, tuple]:
    """{module name: (path, is_package)} of every module of the packages and the scripts."""
    found = {}
    for package, folder in package_folders.items():
        for path in sorted(folder.rglob("*.py")):
            parts = list(path.relative_to(folder).with_suffix("").parts)
            is_package = parts[-1] == "__init__"
            if is_package:
                parts = parts[:-1]
            found[".".join([package] + parts)] = (path, is_package)
    for folder in script_folders:
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


def _package_of(name: str, is_package: bool) -> str:
    return name if is_package else name.rpartition(".")[0]


def _relative_base(package: str, node: ast.ImportFrom) -> str:
    base_parts = package.split(".")[:len(package.split(".")) - node.level + 1]
    return ".".join(base_parts + ([node.module] if node.module else []))


def import_graph(package_folders: Optional[Mapping[str, Path]] = None,
                 script_folders: Sequence[Path] = SCRIPT_FOLDERS,
                 extension_modules: Set[str] = frozenset(EXTENSION_MODULES)) -> Dict[str, Set[str]]:
    """{module: modules it imports} over the packages (default: the wheel's) and the scripts."""
    modules = _modules(wheel_packages() if package_folders is None else package_folders, script_folders)
    known = set(modules) | set(extension_modules)
    graph: Dict[str, Set[str]] = {name: set() for name in known}
    for name, (path, is_package) in modules.items():
        package = _package_of(name, is_package)
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            targets: List[str] = []
            if isinstance(node, ast.Import):
                targets = [alias.name for alias in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = _relative_base(package, node) if node.level else node.module or ""
                # `from package import submodule` imports the submodule; `from module import name` the module
                targets = [f"{base}.{alias.name}" if f"{base}.{alias.name}" in known else base
                           for alias in node.names]
            for target in targets:
                resolved = _known(target, known)
                if resolved is not None and resolved != name:
                    graph[name].add(resolved)
    return graph


def relative_imports_leaving_their_folder(package_folders: Mapping[str, Path]) -> List[str]:
    """Relative imports that climb out of the package a folder is installed as: in the checkout they lead
    to another folder's modules, or nowhere (``from ..pipeline`` in cli/), so such a module reads differently
    in the checkout and in the wheel."""
    problems = []
    for name, (path, is_package) in _modules(package_folders, []).items():
        folder_package = max((p for p in package_folders if name == p or name.startswith(p + ".")), key=len)
        for node in ast.walk(ast.parse(path.read_text(), filename=str(path))):
            if isinstance(node, ast.ImportFrom) and node.level:
                base = _relative_base(_package_of(name, is_package), node)
                if not (base == folder_package or base.startswith(folder_package + ".")):
                    where = path.relative_to(package_folders[folder_package].parent)
                    problems.append(f"{where}:{node.lineno}: {name} imports {base} relatively from outside "
                                    f"{folder_package}: import it by its absolute name")
    return problems


def read_floors(readme: Path) -> Dict[str, int]:
    """{package or module: floor} from the table under "## Floors" in the README, ground (0) first. The
    "may import" column of floor N must read "floor 0" (N = 0) or "floors 0 to N"."""
    section = readme.read_text().split("## Floors", 1)[1].split("\n## ", 1)[0]
    floors: Dict[str, int] = {}
    numbers = []
    for line in section.splitlines():
        match = FLOOR_ROW.match(line)
        if not match:
            continue
        number, _, listed, may_import = match.groups()
        floor = int(number)
        numbers.append(floor)
        expected = "floor 0" if floor == 0 else f"floors 0 to {floor}"
        assert may_import.strip() == expected, f"{readme}: floor {floor} may import {expected!r}, the table says " \
                                               f"{may_import.strip()!r}"
        for name in LISTED_NAME.findall(listed):
            assert name not in floors, f"{readme}: {name} is on floors {floors[name]} and {floor}"
            floors[name] = floor
    assert numbers == list(range(len(numbers))) and numbers, f"{readme}: floors must be numbered 0, 1, 2, ..."
    return floors


def floor_of(module: str, floors: Mapping[str, int]) -> Optional[int]:
    """The floor of the longest listed name that ``module`` is or lies in; the root package stands for its
    own ``__init__`` only (every other module is listed under a name of its own)."""
    parts = module.split(".")
    for end in range(len(parts), 0, -1):
        candidate = ".".join(parts[:end])
        if candidate in floors and (candidate != ROOT_PACKAGE or end == len(parts)):
            return floors[candidate]
    return None


def floor_violations(graph: Mapping[str, Set[str]], floors: Mapping[str, int]) -> List[str]:
    """Every product module (the root package's) on no floor, every listed name that is no module, and every
    import from a higher floor."""
    product = sorted(name for name in graph if name == ROOT_PACKAGE or name.startswith(ROOT_PACKAGE + "."))
    problems = [f"{name} is on no floor" for name in product if floor_of(name, floors) is None]
    problems += [f"{listed} is listed on floor {floor} but is no module" for listed, floor in sorted(floors.items())
                 if not any(name == listed or name.startswith(listed + ".") for name in product)]
    for name in product:
        own = floor_of(name, floors)
        for target in sorted(graph[name]):
            theirs = floor_of(target, floors)
            if own is not None and theirs is not None and theirs > own:
                problems.append(f"{name} (floor {own}) imports {target} from the higher floor {theirs}")
    return problems


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


def test_the_wheel_installs_cli_as_usdksl_cli():
    assert wheel_packages() == {"usdksl": REPO_ROOT / "usdksl", "usdksl.cli": REPO_ROOT / "cli"}


def test_graph_reads_relative_and_function_level_imports():
    graph = import_graph()
    assert "usdksl._native" in graph["usdksl.checking.collision"]        # from .. import _native
    assert "usdksl.reading.loader" in graph["usdksl.pipeline.files"]      # from ..reading.loader import ...
    assert "usdksl.checking.last_contact" in graph["usdksl.pipeline.check"]   # inside check_segment
    assert "usdksl.pipeline.check" in graph["usdksl.cli.check"]           # from usdksl.pipeline.check import ...
    assert "usdksl.cli.options" in graph["usdksl.cli.check"]              # from .options import ...
    assert "suite" in graph["report"] and "suite" in graph["run"]


def test_no_import_cycle():
    cycle = find_cycle(import_graph())
    assert cycle is None, "import cycle: " + " -> ".join(cycle)


def test_only_the_cli_imports_the_cli():
    offenders = sorted(name for name, targets in import_graph().items()
                       if not name.startswith("usdksl.cli") and any(t.startswith("usdksl.cli") for t in targets))
    assert offenders == []


def test_no_import_runs_up_a_floor():
    assert floor_violations(import_graph(), read_floors(REPO_ROOT / "usdksl" / "README.md")) == []


def test_the_cli_imports_the_library_by_absolute_name():
    assert relative_imports_leaving_their_folder(wheel_packages()) == []


def _write(root: Path, relative: str, text: str = "") -> None:
    path = root / relative
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


SMALL_FLOORS = """# x

## Floors

| floor | what | packages and modules | may import |
|---|---|---|---|
| 0 | base | `usdksl.base` | floor 0 |
| 1 | low | `usdksl.low` | floors 0 to 1 |
| 2 | high | `usdksl.high`, `usdksl` | floors 0 to 2 |
| 3 | command line | `usdksl.cli` | floors 0 to 3 |

## After
"""


@pytest.fixture
def small_package(tmp_path):
    """A four-floor package that keeps the rules (base <- low <- high and the root <- cli), with cli/ beside it."""
    _write(tmp_path, "README.md", SMALL_FLOORS)
    _write(tmp_path, "usdksl/__init__.py", "from .high.run import run\n")
    _write(tmp_path, "usdksl/base.py", "import os\n")
    _write(tmp_path, "usdksl/low/__init__.py", "from .thing import thing\n")
    _write(tmp_path, "usdksl/low/thing.py", "from .. import base\nfrom ..base import os\n")
    _write(tmp_path, "usdksl/high/__init__.py")
    _write(tmp_path, "usdksl/high/run.py", "from usdksl.low import thing\n\n\ndef run():\n    from ..base import os\n")
    _write(tmp_path, "cli/__init__.py")
    _write(tmp_path, "cli/main.py", "import usdksl\nfrom usdksl.high.run import run\nfrom .options import option\n")
    _write(tmp_path, "cli/options.py", "import click\n")
    return tmp_path


def _small_folders(root: Path) -> Dict[str, Path]:
    return {"usdksl": root / "usdksl", "usdksl.cli": root / "cli"}


def _small_problems(root: Path) -> List[str]:
    graph = import_graph(_small_folders(root), script_folders=[], extension_modules=set())
    return floor_violations(graph, read_floors(root / "README.md")) + relative_imports_leaving_their_folder(
        _small_folders(root))


def test_the_checker_passes_a_package_that_keeps_its_floors(small_package):
    assert _small_problems(small_package) == []


@pytest.mark.parametrize("relative, text, expected", [
    ("usdksl/low/thing.py", "from ..high.run import run\n",
     "usdksl.low.thing (floor 1) imports usdksl.high.run from the higher floor 2"),
    ("usdksl/base.py", "def later():\n    import usdksl.low.thing\n",
     "usdksl.base (floor 0) imports usdksl.low.thing from the higher floor 1"),
    ("usdksl/low/thing.py", "from usdksl import high\n", "usdksl.low.thing (floor 1) imports usdksl.high from"),
    ("usdksl/low/thing.py", "import usdksl\n", "usdksl.low.thing (floor 1) imports usdksl from the higher floor 2"),
    ("usdksl/high/run.py", "from usdksl.cli.main import run\n",
     "usdksl.high.run (floor 2) imports usdksl.cli.main from the higher floor 3"),
    ("usdksl/odd.py", "", "usdksl.odd is on no floor"),
    ("cli/main.py", "from ..high.run import run\n", "usdksl.cli.main imports usdksl.high.run relatively from outside"),
])
def test_the_checker_fails_on_a_broken_rule(small_package, relative, text, expected):
    _write(small_package, relative, text)
    problems = _small_problems(small_package)
    assert len(problems) == 1 and expected in problems[0], problems


def test_the_checker_fails_on_a_listed_name_that_is_no_module(small_package):
    readme = small_package / "README.md"
    readme.write_text(SMALL_FLOORS.replace("`usdksl.base`", "`usdksl.base`, `usdksl.gone`"))
    problems = _small_problems(small_package)
    assert problems == ["usdksl.gone is listed on floor 0 but is no module"], problems


def test_the_floor_table_says_what_the_checker_enforces(small_package):
    readme = small_package / "README.md"
    readme.write_text(SMALL_FLOORS.replace("floors 0 to 2 |", "floors 0 to 3 |"))
    with pytest.raises(AssertionError, match="floor 2 may import 'floors 0 to 2'"):
        read_floors(readme)
