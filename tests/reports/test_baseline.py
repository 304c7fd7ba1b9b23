"""--baseline: accepted contacts do not count for the exit code; new ones are named, vanished ones are fixed."""

import csv
import json

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.contacts.baseline import Baseline, compare, read_baseline
from usdksl.cli.main import main
from usdksl.contacts.table import ContactTable

from builders import snapshot

NEW_LINE = "usdksl: new: "
FIXED_LINE = "usdksl: fixed (in the baseline, no longer found): "


def _run(*args):
    return CliRunner().invoke(main, [str(arg) for arg in args])


@pytest.fixture
def fold(samples_dir):
    return samples_dir / "fold.usda"


@pytest.fixture
def own(fold, tmp_path):
    """The fold's own contacts.csv (132 face pairs of /World/Strip with itself)."""
    result = _run("check", fold, "--out", tmp_path / "earlier")
    assert result.exit_code == 1, result.output
    return tmp_path / "earlier" / "fold.contacts.csv"


def _rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_own_baseline_is_clean(fold, own, tmp_path):
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", own)
    assert result.exit_code == 0, result.output
    assert "usdksl: 0 new, 132 known, 0 fixed" in result.stderr
    assert {row["baseline"] for row in _rows(tmp_path / "now" / "fold.contacts.csv")} == {"known"}


def test_baseline_less_one_row_names_the_new_pair_and_a_stale_row_is_fixed(fold, own, tmp_path):
    lines = own.read_text().splitlines(keepends=True)
    dropped = next(csv.DictReader(lines[:1] + lines[2:3]))
    stale = "31.0,/World/Strip,0,/World/Strip,5,self,edge-edge,31.0,1.2916666666666667,1\n"   # faces 0 and 5 never touch
    baseline = tmp_path / "baseline.csv"
    baseline.write_text("".join(lines[:2] + lines[3:]) + stale)
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", baseline,
                  "--json", tmp_path / "now" / "fold.json")
    assert result.exit_code == 1, result.output
    new_lines = [line for line in result.stderr.splitlines() if line.startswith(NEW_LINE)]
    assert new_lines == [f"{NEW_LINE}{dropped['prim_a']} face {dropped['face_a']} x {dropped['prim_b']} face "
                         f"{dropped['face_b']}, first at frame 31.916 (t=31.916)"]
    fixed_lines = [line for line in result.stderr.splitlines() if line.startswith(FIXED_LINE)]
    assert fixed_lines == [f"{FIXED_LINE}/World/Strip face 0 x /World/Strip face 5 at t=31.0"]
    assert "usdksl: 1 new, 131 known, 1 fixed" in result.stderr
    rows = _rows(tmp_path / "now" / "fold.contacts.csv")
    assert [(row["face_a"], row["face_b"]) for row in rows if row["baseline"] == "new"] == \
        [(dropped["face_a"], dropped["face_b"])]
    document = json.loads((tmp_path / "now" / "fold.json").read_text())
    assert document["baseline"]["new"] == 1 and document["baseline"]["known"] == 131
    assert document["baseline"]["fixed"] == [{"prim_a": "/World/Strip", "face_a": 0, "prim_b": "/World/Strip",
                                              "face_b": 5, "time": 31.0}]
    assert _rows(tmp_path / "now" / "fold.summary.csv")[0]["new_face_pairs"] == "1"


def test_accept_list_with_any_face_and_sides_in_either_order(fold, tmp_path):
    accept = tmp_path / "accept.csv"
    accept.write_text("# reviewed: the strip may fold onto itself\nprim_b,prim_a\n/World/Strip,/World/Strip\n")
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", accept)
    assert result.exit_code == 0, result.output


def test_one_face_with_any_other_accepts_it_on_either_side(fold, own, tmp_path):
    rows = _rows(own)
    face = rows[0]["face_b"]
    touching = [row for row in rows if face in (row["face_a"], row["face_b"])]
    accept = tmp_path / "accept.csv"
    accept.write_text(f"prim_a,face_a,prim_b,face_b\n/World/Strip,*,/World/Strip,{face}\n")
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", accept)
    assert result.exit_code == 1
    known = [row for row in _rows(tmp_path / "now" / "fold.contacts.csv") if row["baseline"] == "known"]
    assert sorted((row["face_a"], row["face_b"]) for row in known) == \
        sorted((row["face_a"], row["face_b"]) for row in touching)
    assert any(row["face_a"] == face for row in known) and any(row["face_b"] == face for row in known)


def test_time_tolerance(fold, own, tmp_path):
    shifted = tmp_path / "shifted.csv"
    lines = own.read_text().splitlines(keepends=True)
    shifted.write_text(lines[0] + "".join(f"{float(line.split(',', 1)[0]) + 0.5!r},{line.split(',', 1)[1]}"
                                          for line in lines[1:]))
    assert _run("check", fold, "--out", tmp_path / "a", "--baseline", shifted).exit_code == 0
    assert _run("check", fold, "--out", tmp_path / "b", "--baseline", shifted,
                "--baseline-time-tolerance", 1.0).exit_code == 0
    tight = _run("check", fold, "--out", tmp_path / "c", "--baseline", shifted, "--baseline-time-tolerance", 0.1)
    assert tight.exit_code == 1
    assert "usdksl: 132 new, 0 known, 132 fixed" in tight.stderr


@pytest.mark.parametrize("tolerance", ["0", "1e-9"])
def test_own_baseline_at_a_zero_or_tiny_time_tolerance_is_clean(fold, own, tmp_path, tolerance):
    # contacts.csv writes each time as repr(float), which reads back to the same double: every contact lies
    # exactly at its entry's time, within any tolerance, 0 included (docs/contracts.md, Baselines).
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", own, "--baseline-time-tolerance", tolerance)
    assert result.exit_code == 0, result.output
    assert "usdksl: 0 new, 132 known, 0 fixed" in result.stderr
    assert {row["baseline"] for row in _rows(tmp_path / "now" / "fold.contacts.csv")} == {"known"}


@pytest.mark.parametrize("text, words", [
    ("prim_a,face_a\n/A,1\n", "line 1: baseline header lacks column(s) prim_b"),
    ("prim_a,face_a,prim_b,face_b\n/A,one,/B,2\n", "line 2: face_a 'one' is not a face index"),
    ("# note\nprim_a,prim_b,time\n/A,/B,soon\n", "line 3: time 'soon' is not a number"),
])
def test_a_bad_baseline_is_one_line_exit_2_and_nothing_written(fold, tmp_path, text, words):
    baseline = tmp_path / "bad.csv"
    baseline.write_text(text)
    out = tmp_path / "now"
    result = _run("check", fold, "--out", out, "--baseline", baseline)
    assert result.exit_code == 2
    errors = [line for line in result.stderr.splitlines() if line.startswith("usdksl: error: ")]
    assert len(errors) == 1 and errors[0].startswith(f"usdksl: error: {baseline}: {words}"), result.stderr
    assert not out.exists() or snapshot(out) == {}


def test_a_folder_baseline_serves_several_shots(samples_dir, tmp_path):
    shots = [samples_dir / "fold.usda", samples_dir / "drape.usda"]
    earlier = tmp_path / "earlier"
    assert _run("check", *shots, "--out", earlier).exit_code == 1
    (earlier / "drape.contacts.csv").unlink()
    result = _run("check", *shots, "--out", tmp_path / "now", "--baseline", earlier)
    assert result.exit_code == 1                                      # the drape's contacts are new
    assert f"no baseline {earlier / 'drape.contacts.csv'}: every contact counts as new" in result.stderr
    assert {row["baseline"] for row in _rows(tmp_path / "now" / "fold.contacts.csv")} == {"known"}
    assert {row["baseline"] for row in _rows(tmp_path / "now" / "drape.contacts.csv")} == {"new"}


def test_a_baseline_file_for_several_shots_is_a_usage_error(samples_dir, own, tmp_path):
    result = _run("check", samples_dir / "fold.usda", samples_dir / "drape.usda", "--baseline", own,
                  "--out", tmp_path / "now")
    assert result.exit_code == 2 and "a baseline file serves one shot" in result.stderr


def _naive_known(table, entries, tolerance):
    """The reference: every contact against every entry, in Python."""
    prim_a, prim_b = table.prim_names()
    known = []
    for row in range(table.count):
        sides = (prim_a[row], int(table.face_a[row]), prim_b[row], int(table.face_b[row]))
        hit = False
        for ea, fa, eb, fb, t in entries:
            for a, x, b, y in (sides, (sides[2], sides[3], sides[0], sides[1])):
                if (a, b) == (ea, eb) and fa in ("*", x) and fb in ("*", y) and (
                        tolerance is None or t is None or abs(t - float(table.time[row])) <= tolerance):
                    hit = True
        known.append(hit)
    return np.array(known)


@pytest.mark.parametrize("tolerance", [None, 0.3])
def test_vectorised_matching_equals_the_naive_reference(tmp_path, tolerance):
    rng = np.random.default_rng(3)
    paths = ["/b", "/a", "/c"]
    count = 400
    table = ContactTable.from_rows(paths, np.round(rng.uniform(0, 10, count), 1), rng.integers(0, 3, count),
                                   rng.integers(0, 6, count), rng.integers(0, 3, count), rng.integers(0, 6, count))
    entries = []
    for _ in range(150):
        a, b = (str(p) for p in rng.choice(paths + ["/gone"], 2))
        fa, fb = ("*" if rng.random() < 0.2 else int(rng.integers(0, 6)) for _ in range(2))
        t = None if rng.random() < 0.3 else float(np.round(rng.uniform(0, 10), 1))
        entries.append((a, fa, b, fb, t))
    path = tmp_path / "accept.csv"
    path.write_text("prim_a,face_a,prim_b,face_b,time\n" + "".join(
        f"{a},{fa},{b},{fb},{'' if t is None else t}\n" for a, fa, b, fb, t in entries))
    comparison = compare(table, read_baseline(path, tolerance))
    expected = _naive_known(table, entries, tolerance)
    assert 0 < expected.sum() < table.count
    assert np.array_equal(comparison.known, expected)
    # an entry is fixed exactly when it matches no contact
    for index, entry in enumerate(entries):
        single = tmp_path / "one.csv"
        a, fa, b, fb, t = entry
        single.write_text(f"prim_a,face_a,prim_b,face_b,time\n{a},{fa},{b},{fb},{'' if t is None else t}\n")
        matches = compare(table, read_baseline(single, tolerance)).known.any()
        assert (index in comparison.fixed.tolist()) == (not matches)


def test_an_empty_table_fixes_every_entry():
    baseline = Baseline("b", np.array(["/a"], object), np.array([-1]), np.array(["/a"], object), np.array([-1]),
                        np.array([np.nan]))
    comparison = compare(ContactTable.empty(["/a"]), baseline)
    assert comparison.new_count == 0 and comparison.fixed.tolist() == [0]


MISMATCH = "usdksl: warning: {}: {} of {} prims in the baseline are not meshes of {}: made from another shot?"


def test_a_baseline_of_another_shot_warns_once(samples_dir, fold, tmp_path):
    earlier = _run("check", samples_dir / "drape.usda", "--out", tmp_path / "earlier")
    assert earlier.exit_code == 1, earlier.output
    drape = tmp_path / "earlier" / "drape.contacts.csv"
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", drape, "--json", tmp_path / "r.json")
    assert result.exit_code == 1
    lines = [line for line in result.stderr.splitlines() if "in the baseline are not meshes of" in line]
    assert lines == [MISMATCH.format(drape, 2, 2, fold)], result.stderr
    findings = json.loads((tmp_path / "r.json").read_text())["findings"]
    assert [f["kind"] for f in findings if "in the baseline" in f["text"]] == ["usdksl:BaselineMismatch"]


def test_the_shots_own_baseline_does_not_warn(fold, own, tmp_path):
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", own)
    assert result.exit_code == 0 and "made from another shot" not in result.stderr, result.stderr


@pytest.mark.parametrize("prims, warns", [
    (["/World/Strip", "/Other/A"], False),                    # half foreign: not more than half
    (["/World/Strip", "/Other/A", "/Other/B"], True),
    (["/World/Strip", "/World", "/World/Strip[2]"], True),   # an Xform and a bad path are not meshes
])
def test_more_than_half_of_the_prims_foreign_warns(fold, tmp_path, prims, warns):
    accept = tmp_path / "accept.csv"
    accept.write_text("prim_a,prim_b\n" + "".join(f"{prim},{prim}\n" for prim in prims))
    result = _run("check", fold, "--out", tmp_path / "now", "--baseline", accept)
    assert result.exit_code in (0, 1), result.output
    assert ("made from another shot" in result.stderr) == warns, result.stderr


def test_a_mesh_left_out_by_prims_is_still_a_mesh_of_the_shot(samples_dir, tmp_path):
    drape = samples_dir / "drape.usda"
    assert _run("check", drape, "--out", tmp_path / "earlier").exit_code == 1
    result = _run("check", drape, "--out", tmp_path / "now", "--prims", "/World/Cloth",
                  "--baseline", tmp_path / "earlier" / "drape.contacts.csv")
    assert result.exit_code in (0, 1), result.output
    assert "made from another shot" not in result.stderr, result.stderr
