"""The repository speaks of the product as it is: no session or issue numbers in any tracked file or file name
(history belongs in git)."""

import re
import subprocess
from pathlib import Path

import pytest

REPO_ROOT = Path(__file__).resolve().parent.parent
#: A session or issue number, in text or in a file name (with a space, '_' or '-' before the number, or none).
HISTORY = re.compile(r"(session|issue)[ _-]?[0-9]", re.IGNORECASE)
#: Tracked files that are not text.
NOT_TEXT = {".usdc", ".usd", ".usdz", ".npz", ".png", ".pyc"}


def tracked_files():
    try:
        listed = subprocess.run(["git", "ls-files", "-z"], cwd=REPO_ROOT, capture_output=True, check=True)
    except (OSError, subprocess.CalledProcessError):
        pytest.skip("not a git checkout: the tracked files are unknown")
    return [REPO_ROOT / name for name in listed.stdout.decode().split("\0") if name]


def history_lines(paths, root=REPO_ROOT):
    found = []
    for path in paths:
        if not path.is_file():
            continue
        lines = [path.name] if path.suffix in NOT_TEXT else [path.name] + path.read_text(errors="replace").splitlines()
        found += [f"{path.relative_to(root)}:{number}: {line[:120]}"
                  for number, line in enumerate(lines) if HISTORY.search(line)]
    return found


def test_no_session_or_issue_numbers_in_tracked_files():
    assert history_lines(tracked_files()) == []


def test_the_scan_finds_them(tmp_path):
    session, issue = "Session", "issue"   # spelled apart, or this file would hold what it looks for
    for name, text in (("notes.md", f"until {session} 19 it was slow\n"), (f"ksl_{issue}19.txt", "fine\n"),
                       ("ok.md", "an issue of style, 19 sessions\n")):
        (tmp_path / name).write_text(text)
    found = history_lines(sorted(tmp_path.iterdir()), tmp_path)
    assert [line.split(":")[-1].strip() for line in found] == [f"ksl_{issue}19.txt", f"until {session} 19 it was slow"]
