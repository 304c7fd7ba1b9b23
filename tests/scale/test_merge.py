"""``usdksl merge``: farm chunks (``check --time-range A B``) joined equal one run over their union, byte for
byte; gaps, chunks that leave out part of the shot's range (or of --time-range), disagreeing overlaps,
other shots, other options and off-sample cuts are refused."""

from pathlib import Path

import pytest
from click.testing import CliRunner

from builders import QUAD_POINTS, add_mesh, new_stage
from usdksl.cli.main import main

#: fold.usda is sampled at every frame 1..36; its strip first touches itself at about t = 31.9.
FOLD_FIRST_CONTACT = 31.9
FILES = ("fold.contacts.csv", "fold.summary.csv", "fold.regions.csv", "fold.usdksl.usda", "fold.usdksl-run.json", "fold.json",
         "fold.junit.xml")


def _run(*args):
    return CliRunner().invoke(main, [str(arg) for arg in args])


def _chunk(shot, folder, start, end, *extra):
    result = _run("check", shot, "--time-range", start, end, "--out", folder, *extra)
    rows = (folder / f"{Path(shot).stem}.contacts.csv").read_text().splitlines()[1:]
    assert result.exit_code == (1 if rows else 0), result.output
    if Path(shot).name == "fold.usda":   # a chunk of the fold holds contacts exactly when it ends after the first
        assert bool(rows) == (end > FOLD_FIRST_CONTACT), (start, end, rows[:1])
    return folder


def _reports(folder):
    return ("--json", folder / "fold.json", "--junit", folder / "fold.junit.xml")


@pytest.fixture
def fold(samples_dir):
    return samples_dir / "fold.usda"


@pytest.fixture
def whole(fold, tmp_path):
    """One run over 1..36, with every report."""
    out = tmp_path / "whole"
    result = _run("check", fold, "--time-range", 1, 36, "--out", out, *_reports(out))
    assert result.exit_code == 1, result.output
    return {name: (out / name).read_bytes() for name in FILES}


@pytest.mark.parametrize("cuts", [((1, 20), (20, 36)), ((1, 12), (12, 33), (33, 36)), ((18, 36), (1, 22))],
                         ids=["two", "three", "overlapping"])
def test_merged_chunks_equal_one_run_over_their_union(fold, tmp_path, whole, cuts):
    folders = [_chunk(fold, tmp_path / f"part{index}", start, end) for index, (start, end) in enumerate(cuts)]
    out = tmp_path / "merged"
    result = _run("merge", fold, *folders, "--out", out, *_reports(out))
    assert result.exit_code == 1, result.output
    assert {name: (out / name).read_bytes() for name in FILES} == whole
    assert result.stderr.startswith(f"usdksl: merged {len(cuts)} chunks: 1 problem in 1 mesh pair "
                                    f"(132 contacting face pairs)")


def test_merged_last_contacts_equal_one_run_over_their_union(fold, tmp_path):
    whole = tmp_path / "whole"
    assert _run("check", fold, "--time-range", 1, 36, "--out", whole, "--last-contact").exit_code == 1
    # the fold's face pairs touch from about t = 31.9 on, across the cut at 33
    folders = [_chunk(fold, tmp_path / f"part{index}", start, end, "--last-contact")
               for index, (start, end) in enumerate(((1, 33), (33, 36)))]
    out = tmp_path / "merged"
    result = _run("merge", fold, *folders, "--out", out)
    assert result.exit_code == 1, result.output
    for name in ("fold.contacts.csv", "fold.summary.csv", "fold.usdksl.usda"):
        assert (out / name).read_bytes() == (whole / name).read_bytes(), name
    assert "last_time" in (out / "fold.contacts.csv").read_text().splitlines()[0]


def test_merged_with_a_baseline_equals_one_run_with_it(fold, tmp_path, whole):
    baseline = tmp_path / "baseline.csv"
    lines = whole["fold.contacts.csv"].decode().splitlines(keepends=True)
    baseline.write_text("".join(lines[:1] + lines[2:]))               # the first face pair becomes new
    one = tmp_path / "one"
    assert _run("check", fold, "--time-range", 1, 36, "--out", one, "--baseline", baseline).exit_code == 1
    folders = [_chunk(fold, tmp_path / f"part{index}", start, end)
               for index, (start, end) in enumerate(((1, 20), (20, 36)))]
    out = tmp_path / "merged"
    result = _run("merge", fold, *folders, "--out", out, "--baseline", baseline)
    assert result.exit_code == 1, result.output
    for name in ("fold.contacts.csv", "fold.summary.csv"):
        assert (out / name).read_bytes() == (one / name).read_bytes(), name
    assert (out / "fold.contacts.csv").read_text().count(",new\n") == 1


def test_chunks_with_and_without_last_contacts_are_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 20),
                  _chunk(fold, tmp_path / "b", 20, 36, "--last-contact"), "--out", out)
    _refused(result, "other options", out)


def test_merged_output_merges_again(fold, tmp_path, whole):
    first = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 10), _chunk(fold, tmp_path / "b", 10, 20),
                 "--time-range", 1, 20, "--out", tmp_path / "ab")
    assert first.exit_code == 0, first.output                 # no contact before 20
    result = _run("merge", fold, tmp_path / "ab", _chunk(fold, tmp_path / "c", 20, 36), "--out", tmp_path / "abc")
    assert result.exit_code == 1, result.output
    assert (tmp_path / "abc" / "fold.contacts.csv").read_bytes() == whole["fold.contacts.csv"]


def _refused(result, words, out):
    assert result.exit_code == 2, result.output
    errors = [line for line in result.stderr.splitlines() if line.startswith("usdksl: error: ")]
    assert len(errors) == 1 and words in errors[0], result.stderr
    assert not out.exists()


def test_a_gap_is_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 15), _chunk(fold, tmp_path / "b", 20, 36),
                  "--out", out)
    _refused(result, "nothing covers 15..20", out)


def test_chunks_with_other_options_are_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 20),
                  _chunk(fold, tmp_path / "b", 20, 36, "--thickness", "0.01"), "--out", out)
    _refused(result, "other options", out)


def test_a_chunk_of_another_shot_is_refused(fold, tmp_path):
    edited = tmp_path / "edited" / "fold.usda"
    edited.parent.mkdir()
    edited.write_bytes(fold.read_bytes().replace(b"#usda 1.0", b"#usda 1.0\n# edited", 1))
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 20), _chunk(edited, tmp_path / "b", 20, 36),
                  "--out", out)
    _refused(result, "another shot", out)


def test_a_chunk_without_manifest_is_refused(fold, tmp_path):
    out = tmp_path / "merged"
    whole_run = tmp_path / "plain"
    assert _run("check", fold, "--out", whole_run).exit_code == 1        # no --time-range: no manifest
    result = _run("merge", fold, whole_run, "--out", out)
    _refused(result, "no run manifest", out)


def test_overlapping_chunks_that_disagree_are_refused(fold, tmp_path):
    first, second = _chunk(fold, tmp_path / "a", 1, 34), _chunk(fold, tmp_path / "b", 30, 36)
    contacts = second / "fold.contacts.csv"
    lines = contacts.read_text().splitlines(keepends=True)
    time, rest = lines[1].split(",", 1)
    lines[1] = f"{float(time) + 0.5!r},{rest}"                       # one pair touches later than it did
    contacts.write_text("".join(lines))
    out = tmp_path / "merged"
    _refused(_run("merge", fold, first, second, "--out", out), "overlap but disagree", out)


def test_cuts_between_samples_of_a_moving_mesh_are_refused(samples_dir, tmp_path):
    shot = samples_dir / "pass_through.usda"                # the mover is sampled at 1 and 24 only
    out = tmp_path / "merged"
    result = _run("merge", shot, _chunk(shot, tmp_path / "a", 1, 20), _chunk(shot, tmp_path / "b", 20, 24),
                  "--out", out)
    _refused(result, "between two time samples of /World/Mover/Box", out)


# --------------------------------------------------------------------------- the shot's whole range


def test_only_the_second_half_of_the_chunks_is_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "b", 18, 27), _chunk(fold, tmp_path / "c", 27, 36),
                  "--out", out)
    _refused(result, f"{fold}: the chunks cover 18..36, not 1..18 of the shot's range 1..36: a chunk is missing "
                     f"(or give --time-range 18 36 to merge a part)", out)
    assert sorted(path.name for path in tmp_path.iterdir()) == ["b", "c"]     # nothing written beside them


def test_only_the_first_half_of_the_chunks_is_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 18), "--out", out)
    _refused(result, "the chunks cover 1..18, not 18..36 of the shot's range 1..36", out)


def test_a_middle_chunk_names_both_missing_stretches(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "m", 10, 20), "--out", out)
    _refused(result, "the chunks cover 10..20, not 1..10 and 20..36 of the shot's range 1..36", out)


def test_chunks_reaching_past_the_shot_cover_it(fold, tmp_path, whole):
    # a farm's last chunk ends one frame past the shot: nothing moves after the last sample
    folders = [_chunk(fold, tmp_path / f"part{index}", start, end) for index, (start, end) in
               enumerate(((1, 20), (20, 37)))]
    result = _run("merge", fold, *folders, "--out", tmp_path / "merged")
    assert result.exit_code == 1, result.output


def test_a_part_merged_with_its_time_range_equals_one_run_over_it(fold, tmp_path):
    one = tmp_path / "one"
    assert _run("check", fold, "--time-range", 18, 36, "--out", one).exit_code == 1
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "b", 18, 27), _chunk(fold, tmp_path / "c", 27, 36),
                  "--time-range", 18, 36, "--out", out)
    assert result.exit_code == 1, result.output
    for name in ("fold.contacts.csv", "fold.summary.csv", "fold.usdksl.usda"):
        assert (out / name).read_bytes() == (one / name).read_bytes(), name


def test_a_time_range_wider_than_the_chunks_is_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "b", 18, 27), "--time-range", 9, 36, "--out", out)
    _refused(result, "the chunks cover 18..27, not 9..18 and 27..36 of --time-range 9..36: a chunk is missing", out)


def test_chunks_reaching_outside_the_time_range_are_refused(fold, tmp_path):
    out = tmp_path / "merged"
    result = _run("merge", fold, _chunk(fold, tmp_path / "a", 1, 20), _chunk(fold, tmp_path / "b", 20, 36),
                  "--time-range", 20, 36, "--out", out)
    _refused(result, "the chunks cover 1..36, beyond --time-range 20..36 (1..20)", out)


def _falling_every_frame(last_frame, offset=(0.0, 0.0, 0.0)):
    """A quad falling one unit a frame, sampled at every frame 1..last_frame (chunks may cut at any frame)."""
    return {float(frame): QUAD_POINTS + offset + [0.0, -float(frame), 0.0] for frame in range(1, last_frame + 1)}


@pytest.fixture
def short_and_long(tmp_path):
    """/World/Short is sampled over 1..12; /World/Long, far from it, over 1..24."""
    path = tmp_path / "shot.usda"
    stage = new_stage(path)
    add_mesh(stage, "/World/Short", None, samples=_falling_every_frame(12))
    add_mesh(stage, "/World/Long", None, samples=_falling_every_frame(24, offset=(10.0, 0.0, 0.0)))
    stage.GetRootLayer().Save()
    return path


def test_the_range_is_that_of_the_meshes_the_chunks_checked(short_and_long, tmp_path):
    shot = short_and_long
    short_only = [_chunk(shot, tmp_path / f"short{index}", start, end, "--prims", "/World/Short")
                  for index, (start, end) in enumerate(((1, 6), (6, 12)))]
    result = _run("merge", shot, *short_only, "--out", tmp_path / "short")
    assert result.exit_code == 0, result.output
    every_mesh = [_chunk(shot, tmp_path / f"all{index}", start, end)
                  for index, (start, end) in enumerate(((1, 6), (6, 12)))]
    out = tmp_path / "all"
    _refused(_run("merge", shot, *every_mesh, "--out", out), "not 12..24 of the shot's range 1..24", out)


def test_a_shot_where_nothing_moves_is_covered_by_any_chunk(tmp_path):
    shot = tmp_path / "still.usda"
    stage = new_stage(shot)
    add_mesh(stage, "/World/Floor", QUAD_POINTS)
    add_mesh(stage, "/World/Table", QUAD_POINTS + [0.0, 1.0, 0.0])
    stage.GetRootLayer().Save()
    result = _run("merge", shot, _chunk(shot, tmp_path / "a", 5, 10), "--out", tmp_path / "merged")
    assert result.exit_code == 0, result.output
