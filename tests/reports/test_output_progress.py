"""All-or-nothing output and the progress bar."""

import io
import stat

import pytest

from usdksl.errors import UsdkslUsageError
from usdksl.pipeline.progress import Progress, progress_enabled
from usdksl.reports.output import OutputTransaction, check_writable_directory

from builders import snapshot


def test_transaction_publishes_all_files_with_normal_modes(tmp_path):
    transaction = OutputTransaction()
    transaction.write_text(tmp_path / "a.csv", "a\n")
    transaction.write_text(tmp_path / "new" / "deeper" / "b.csv", "b\n")
    assert snapshot(tmp_path) == {}          # nothing on disk before commit
    transaction.commit()
    assert (tmp_path / "a.csv").read_text() == "a\n"
    assert (tmp_path / "new" / "deeper" / "b.csv").read_text() == "b\n"
    assert stat.S_IMODE((tmp_path / "a.csv").stat().st_mode) & 0o044   # not mkstemp's private 0600
    assert not list(tmp_path.rglob(".usdksl-tmp-*"))


def test_failed_commit_leaves_nothing_behind(tmp_path):
    (tmp_path / "old.csv").write_text("keep me\n")
    (tmp_path / "blocker").write_text("a file where a directory is needed\n")
    before = snapshot(tmp_path)
    transaction = OutputTransaction()
    transaction.write_text(tmp_path / "old.csv", "new content\n")
    transaction.write_text(tmp_path / "fresh" / "x.csv", "x\n")
    transaction.write_text(tmp_path / "blocker" / "y.csv", "y\n")
    with pytest.raises(UsdkslUsageError) as raised:
        transaction.commit()
    assert "cannot write output" in str(raised.value)
    assert snapshot(tmp_path) == before
    assert not (tmp_path / "fresh").exists()


def test_exception_inside_the_block_discards_everything(tmp_path):
    with pytest.raises(RuntimeError):
        with OutputTransaction() as transaction:
            transaction.write_text(tmp_path / "a.csv", "a\n")
            raise RuntimeError("formatting failed")
    assert snapshot(tmp_path) == {}


def test_check_writable_directory(tmp_path):
    assert check_writable_directory(tmp_path / "missing" / "deeper") == tmp_path / "missing" / "deeper"
    assert not (tmp_path / "missing").exists()
    (tmp_path / "file").write_text("x")
    with pytest.raises(UsdkslUsageError, match="not a directory"):
        check_writable_directory(tmp_path / "file")
    with pytest.raises(UsdkslUsageError, match="not a directory"):
        check_writable_directory(tmp_path / "file" / "sub")


class FakeTty(io.StringIO):
    def isatty(self):
        return True


def test_progress_draws_only_on_a_tty_outside_ci():
    assert progress_enabled(FakeTty(), environ={})
    assert not progress_enabled(FakeTty(), environ={"CI": "true"})
    assert not progress_enabled(io.StringIO(), environ={})

    stream = FakeTty()
    clock = iter([0.0, 0.05, 1.0, 2.0]).__next__
    bar = Progress(0.0, 48.0, stream=stream, enabled=True, clock=clock)
    bar(12.0, 3)      # drawn
    bar(13.0, 4)      # within the redraw interval: skipped
    bar(24.0, 7)      # drawn
    text = stream.getvalue()
    assert "t=12 of 0..48  contacts: 3" in text and "contacts: 4" not in text
    assert "t=24 of 0..48  contacts: 7" in text and "[" + "#" * 15 + "." * 15 + "]" in text
    bar.close()
    assert stream.getvalue().endswith("\r")

    quiet = io.StringIO()
    silent = Progress(0.0, 48.0, stream=quiet, enabled=False)
    silent(24.0, 1)
    silent.close()
    assert quiet.getvalue() == "" and silent.contacts == 1 and silent.time_reached == 24.0


def test_a_check_draws_a_shown_bar_and_leaves_an_undrawn_one_alone(samples_dir):
    """check_shot hands the core's progress to a bar that is drawn (and to any other progress object), not
    to a usdksl Progress that is not drawn: its calls would show nothing and cost the core's threads the GIL."""
    from usdksl.pipeline import check_shot

    made = {}

    def factory(kind):
        def make(start, end, label=""):
            if kind == "drawn":
                made[kind] = Progress(start, end, stream=FakeTty(), enabled=True, clock=iter(range(10 ** 6)).__next__)
            elif kind == "undrawn":
                made[kind] = Progress(start, end, stream=io.StringIO(), enabled=False)
            else:
                made[kind] = calls = []
                return lambda reached, contacts: calls.append(reached)
            return made[kind]
        return make

    results = [check_shot(str(samples_dir / "fold.usda"), progress=factory(kind)).table.count
               for kind in ("drawn", "undrawn", "callable")]
    assert results[0] == results[1] == results[2] > 0
    drawn, undrawn, calls = made["drawn"], made["undrawn"], made["callable"]
    assert drawn.time_reached == drawn.end and f"t={drawn.end:g} of " in drawn.stream.getvalue()
    assert undrawn.time_reached == undrawn.start and undrawn.stream.getvalue() == ""
    assert calls and max(calls) == drawn.end
