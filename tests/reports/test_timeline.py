"""--plot: the contact timeline (usdksl.reports.timeline), one row per mesh pair, frames across."""

import struct
import sys

import numpy as np
import pytest
from click.testing import CliRunner

from usdksl.cli.main import main
from usdksl.pipeline import CheckOptions, check_shot
from usdksl.reports.timeline import (DOTS_PER_INCH, FIGURE_WIDTH_INCHES, INSTALL_HINT, MARGIN_HEIGHT_INCHES,
                                     ROW_HEIGHT_INCHES, contact_spans, in_contact_counts, timeline_figure,
                                     timeline_rows)

from builders import QUAD_POINTS, add_mesh, new_stage


def test_spans_are_the_union_of_closed_intervals():
    first = np.array([7.0, 1.0, 2.0, 8.0, 12.0])
    last = np.array([8.0, 3.0, 5.0, 9.0, 12.0])
    assert contact_spans(first, last).tolist() == [[1.0, 5.0], [7.0, 9.0], [12.0, 12.0]]
    assert contact_spans(np.zeros(0), np.zeros(0)).shape == (0, 2)


def test_counts_step_through_the_intervals():
    times, counts = in_contact_counts(np.array([1.0, 2.0, 7.0]), np.array([3.0, 5.0, 8.0]))
    assert times.tolist() == [1.0, 2.0, 3.0, 5.0, 7.0, 8.0]
    assert counts.tolist() == [1, 2, 1, 0, 1, 0]


def _two_movers(path):
    """A floor quad; /World/Bounce passes down through it and back up (first ~6, last ~16); /World/Rest comes
    down onto it at 10 and stays to the end (24). The stage starts at 2, 12 time codes a second, 24 fps."""
    stage = new_stage(path, tcps=12.0, fps=24.0, start=2.0, end=24.0)
    add_mesh(stage, "/World/Floor", np.array([[-1, 0, -1], [5, 0, -1], [5, 0, 2], [-1, 0, 2]], float))
    add_mesh(stage, "/World/Bounce", None, samples={1.0: QUAD_POINTS + [0, 1, 0], 11.0: QUAD_POINTS + [0, -1, 0],
                                                     21.0: QUAD_POINTS + [0, 1, 0], 24.0: QUAD_POINTS + [0, 1, 0]})
    add_mesh(stage, "/World/Rest", None, samples={1.0: QUAD_POINTS + [3, 1, 0], 10.0: QUAD_POINTS + [3, 0, 0],
                                                   24.0: QUAD_POINTS + [3, 0, 0]})
    stage.GetRootLayer().Save()
    return path


def test_rows_hold_each_mesh_pair_in_frames(tmp_path):
    result = check_shot(str(_two_movers(tmp_path / "movers.usda")), CheckOptions(last_contact=True))
    rows = timeline_rows(result.table, result.clock)
    assert [row.label for row in rows] == ["/World/Bounce x /World/Floor", "/World/Floor x /World/Rest"]
    frame = result.clock.frame        # t * 24 / 12, whatever the stage's start
    assert frame(6.0) == 12.0 and frame(16.0) == 32.0
    bounce, rest = rows
    assert bounce.spans.shape == (1, 2) and rest.spans.shape == (1, 2)
    assert bounce.spans[0] == pytest.approx([frame(6.0), frame(16.0)], abs=1e-4)
    assert rest.spans[0] == pytest.approx([frame(10.0), frame(24.0)], abs=1e-4)
    assert bounce.new_ticks == pytest.approx([frame(6.0)], abs=1e-4) and bounce.known_ticks.size == 0
    assert rest.counts.tolist() == [1, 0]


def test_the_axis_runs_over_the_checked_span_in_stage_frames(tmp_path):
    result = check_shot(str(_two_movers(tmp_path / "movers.usda")), CheckOptions(last_contact=True))
    assert result.span == (1.0, 24.0)
    axes = timeline_figure(result.table, result.clock, result.span, "movers.usda").axes[0]
    assert axes.get_xlim() == (2.0, 48.0)           # time codes 1..24 at 12 a second, 24 frames a second
    assert axes.get_xlabel() == "frame (24 fps, 12 time codes/s)"


def _png_size(data):
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    return struct.unpack(">II", data[16:24])


def test_plot_option_writes_a_png_with_a_row_per_mesh_pair(tmp_path):
    shot = _two_movers(tmp_path / "movers.usda")
    plot = tmp_path / "timeline.png"
    result = CliRunner().invoke(main, ["check", str(shot), "--out", str(tmp_path / "out"), "--plot", str(plot)])
    assert result.exit_code == 1, result.output
    width, height = _png_size(plot.read_bytes())
    assert width == round(FIGURE_WIDTH_INCHES * DOTS_PER_INCH)
    assert height == round((MARGIN_HEIGHT_INCHES + 2 * ROW_HEIGHT_INCHES) * DOTS_PER_INCH)
    # --plot turns on last contacts: the CSV has them
    assert "last_time" in (tmp_path / "out" / "movers.contacts.csv").read_text().splitlines()[0]


def test_plot_takes_one_shot(samples_dir, tmp_path):
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), str(samples_dir / "drape.usda"),
                                       "--out", str(tmp_path), "--plot", str(tmp_path / "t.png")])
    assert result.exit_code == 2 and "--plot takes one shot; got 2" in result.stderr


def test_without_matplotlib_plot_is_a_usage_error(samples_dir, tmp_path, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    out = tmp_path / "out"
    result = CliRunner().invoke(main, ["check", str(samples_dir / "fold.usda"), "--out", str(out), "--plot",
                                       str(tmp_path / "t.png")])
    assert result.exit_code == 2
    assert result.stderr.splitlines() == [f"usdksl: error: {INSTALL_HINT}"]
    assert not out.exists()
