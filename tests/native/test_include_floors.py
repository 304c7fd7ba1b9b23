"""The native topics form floors: no ``#include`` runs from a lower floor to a higher one.

The floor order is read from the numbered list under "## Floors" in ``native/README.md`` (bottom
first; ```usdksl/``` is the ground, the files directly in ``include/usdksl/``). Files of
``native/include``, ``native/src`` and ``native/tests/<topic>/`` are read as text (nothing is
compiled): a quoted or angled include of ``usdksl/...`` names a public header, any other quoted
include is resolved beside the including file and, when it lands in ``native/src/<topic>/``, names
that topic's private helper, which only the same topic may include.
"""

import re
from pathlib import Path
from typing import Dict, List, Optional

import pytest

NATIVE = Path(__file__).resolve().parents[2] / "native"
GROUND = "usdksl"
FLOOR_ITEM = re.compile(r"^\d+\.\s+`([a-z_]+)/`")
INCLUDE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]', re.MULTILINE)
SOURCE_SUFFIXES = {".hpp", ".h", ".cpp", ".cc"}


def read_floors(readme: Path) -> Dict[str, int]:
    """{topic: floor index} from the "## Floors" list of the README, ground first."""
    text = readme.read_text()
    section = text.split("## Floors", 1)[1].split("\n## ", 1)[0]
    topics = [match.group(1) for line in section.splitlines() if (match := FLOOR_ITEM.match(line))]
    assert topics and topics[0] == GROUND, f"{readme}: the floor list must start with `{GROUND}/`"
    assert len(topics) == len(set(topics)), f"{readme}: a topic is listed twice"
    return {topic: index for index, topic in enumerate(topics)}


def topic_of(path: Path, native: Path) -> Optional[str]:
    """The topic a file of the native tree belongs to; None for shared test helpers."""
    parts = path.relative_to(native).parts
    if parts[0] == "include":
        return parts[2] if len(parts) > 3 else GROUND
    if parts[0] in ("src", "tests"):
        if len(parts) > 2:
            return parts[1]
        return GROUND if parts[0] == "src" else None
    return None


def include_violations(native: Path, floors: Dict[str, int]) -> List[str]:
    """Every include that runs up a floor, reaches into another topic's src/, or names an unlisted topic."""
    problems = []
    files = [path for folder in ("include", "src", "tests") for path in sorted((native / folder).rglob("*"))
             if path.suffix in SOURCE_SUFFIXES]
    for path in files:
        source_topic = topic_of(path, native)
        if source_topic is None:
            continue
        where = path.relative_to(native)
        if source_topic not in floors:
            problems.append(f"{where}: topic {source_topic!r} is not in the floor list")
            continue
        text = path.read_text()
        for match in INCLUDE.finditer(text):
            bracket, name = match.groups()
            line = text.count("\n", 0, match.start()) + 1
            if name.startswith(GROUND + "/"):
                target = native / "include" / name
            elif bracket == '"' and (path.parent / name).resolve().is_file():
                target = (path.parent / name).resolve()
                if target.is_relative_to(native / "src") and topic_of(target, native) != source_topic:
                    problems.append(f"{where}:{line}: includes {name}, private to topic {topic_of(target, native)}")
                    continue
            else:
                continue  # a system or third-party header
            target_topic = topic_of(target, native)
            if target_topic is None:
                continue  # a shared test helper beside the topic folders
            if target_topic not in floors:
                problems.append(f"{where}:{line}: includes {name} of unlisted topic {target_topic!r}")
            elif floors[target_topic] > floors[source_topic]:
                problems.append(f"{where}:{line}: {source_topic} (floor {floors[source_topic] + 1}) includes "
                                f"{name} from the higher floor {target_topic} ({floors[target_topic] + 1})")
    return problems


def test_every_topic_folder_is_a_listed_floor():
    floors = read_floors(NATIVE / "README.md")
    folders = {path.name for root in ("include/usdksl", "src", "tests") for path in (NATIVE / root).iterdir()
               if path.is_dir()}
    assert folders - set(floors) == set(), "topic folders missing from native/README.md's floor list"
    assert set(floors) - {GROUND} <= folders, "listed floors without a folder"


def test_no_native_include_runs_up_a_floor():
    floors = read_floors(NATIVE / "README.md")
    assert include_violations(NATIVE, floors) == []


def _write(root: Path, relative: str, text: str) -> None:
    path = root / relative
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(text)


@pytest.fixture
def small_tree(tmp_path):
    """A three-floor tree that keeps the rules: ground <- low <- high."""
    _write(tmp_path, "README.md", "# x\n\n## Floors\n\n1. `usdksl/` ground\n2. `low/` low\n3. `high/` high\n")
    _write(tmp_path, "include/usdksl/types.hpp", "#pragma once\n")
    _write(tmp_path, "include/usdksl/low/a.hpp", '#pragma once\n#include "usdksl/types.hpp"\n#include <vector>\n')
    _write(tmp_path, "include/usdksl/high/b.hpp", '#pragma once\n#include "usdksl/low/a.hpp"\n')
    _write(tmp_path, "src/low/helper.hpp", "#pragma once\n")
    _write(tmp_path, "src/low/a.cpp", '#include "usdksl/low/a.hpp"\n#include "helper.hpp"\n')
    _write(tmp_path, "src/high/b.cpp", '#include "usdksl/high/b.hpp"\n')
    _write(tmp_path, "tests/helpers.hpp", "#pragma once\n")
    _write(tmp_path, "tests/high/b_test.cpp", '#include "helpers.hpp"\n#include <usdksl/high/b.hpp>\n')
    return tmp_path


def test_the_checker_passes_a_tree_that_keeps_its_floors(small_tree):
    assert include_violations(small_tree, read_floors(small_tree / "README.md")) == []


@pytest.mark.parametrize("relative, text, expected", [
    ("include/usdksl/low/a.hpp", '#include "usdksl/high/b.hpp"\n', "includes usdksl/high/b.hpp from the higher floor"),
    ("src/low/a.cpp", "#include <usdksl/high/b.hpp>\n", "includes usdksl/high/b.hpp from the higher floor"),
    ("include/usdksl/types.hpp", '#include "usdksl/low/a.hpp"\n', "usdksl (floor 1) includes usdksl/low/a.hpp"),
    ("tests/low/a_test.cpp", '#include "usdksl/high/b.hpp"\n', "from the higher floor high"),
    ("src/high/b.cpp", '#include "../low/helper.hpp"\n', "private to topic low"),
    ("src/odd/c.cpp", '#include "usdksl/types.hpp"\n', "topic 'odd' is not in the floor list"),
])
def test_the_checker_fails_on_a_broken_rule(small_tree, relative, text, expected):
    _write(small_tree, relative, text)
    problems = include_violations(small_tree, read_floors(small_tree / "README.md"))
    assert len(problems) == 1 and expected in problems[0], problems
