"""The --report page (usdksl.reports.html_report): self-contained, escaped, the regions worst first with their
depth and measure, the timeline deepest on top, pictures of the worst regions only, the same bytes every time.
(The page in a real browser: tests/browser.)"""

import base64
import io
import sys
from html.parser import HTMLParser

import numpy as np
import pytest
from PIL import Image

from usdksl.clock import StageClock
from usdksl.contacts.table import ContactTable
from usdksl.errors import UsdkslUsageError
from usdksl.regions.table import INTERSECTION_LENGTH, PENETRATION, RegionTable
from usdksl.reports.html_report import (INSTALL_HINT, MAX_PICTURES, MAX_TIMELINE_ROWS, ShotSection, html_report,
                                        timeline_figure, timeline_png)

from browser.report_scene import SPAN, contacts, hand_regions, scene

#: 48 time codes a second, 24 frames: frame = time / 2.
CLOCK = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)
DATA_PNG = "data:image/png;base64,"


class Page(HTMLParser):
    """What the tests read of a page: image sources, figure ids, the region table's cells, all tag names."""

    def __init__(self, text):
        super().__init__()
        self.images, self.figures, self.rows, self.tags = [], [], [], []
        self._cell, self._in_regions = None, False
        self.feed(text)

    def handle_starttag(self, tag, attrs):
        attrs = dict(attrs)
        self.tags.append(tag)
        if tag == "img":
            self.images.append(attrs["src"])
        elif tag == "figure" and "region" in attrs.get("class", ""):
            self.figures.append(attrs["id"])
        elif tag == "table" and attrs.get("class") == "regions":
            self._in_regions = True
        elif tag == "tr" and self._in_regions:
            self.rows.append([])
        elif tag == "td" and self._in_regions:
            self._cell = ""

    def handle_endtag(self, tag):
        if tag == "td" and self._cell is not None:
            self.rows[-1].append(self._cell)
            self._cell = None
        elif tag == "table":
            self._in_regions = False

    def handle_data(self, data):
        if self._cell is not None:
            self._cell += data


def png(color=(200, 30, 30), size=(8, 6)) -> bytes:
    buffer = io.BytesIO()
    Image.new("RGB", size, color).save(buffer, format="PNG")
    return buffer.getvalue()


def synthetic(depths, measures, paths=("/World/A", "/World/B")):
    """A contact table of one face pair per region (region r: faces r of A and B, first at time 10 + r) and its
    RegionTable with the given depths and measures; each region lasts 6 time codes."""
    count = len(depths)
    rows = np.arange(count)
    table = ContactTable.from_rows(list(paths), 10.0 + rows, np.zeros(count), rows, np.ones(count), rows)
    centre = np.stack([rows, rows * 0.5, -rows], axis=1).astype(float)
    regions = RegionTable(
        paths=list(paths), mesh_a=np.zeros(count, np.int32), mesh_b=np.ones(count, np.int32),
        first_time=10.0 + rows, last_time=16.0 + rows, face_pairs=np.ones(count, np.int64),
        depth_measure=np.array(measures, dtype=object), max_depth=np.array(depths, float),
        max_depth_time=12.0 + rows, max_intersection_length=np.ones(count), center=centre, box_min=centre - 0.1,
        box_max=centre + 0.1, row_region=rows.astype(np.int32))
    return table, regions


def section(table, regions, pictures=None, shot="shots/a.usda", summary="usdksl: contacts", notes=(), exit_code=1,
            span=(0.0, 40.0)):
    return ShotSection(shot=shot, summary=summary, exit_code=exit_code, clock=CLOCK, span=span, table=table,
                       regions=regions, pictures=dict(pictures or {}), notes=list(notes))


@pytest.fixture(scope="module")
def real_shot():
    meshes = scene()
    table = contacts(meshes)
    return table, hand_regions(meshes, table)


def test_the_page_is_self_contained(real_shot):
    table, regions = real_shot
    text = html_report([section(table, regions, {0: png(), 1: png((20, 90, 200))}, span=SPAN)])
    page = Page(text)
    assert text.startswith("<!DOCTYPE html>") and "<meta charset=\"utf-8\">" in text
    for outside in ("http:", "https:", "//cdn", "<script", "<link", "url(", "@import", "<iframe"):
        assert outside not in text.lower(), outside
    assert len(page.images) == 3                                     # the timeline and two regions
    for source in page.images:
        assert source.startswith(DATA_PNG)
        Image.open(io.BytesIO(base64.b64decode(source[len(DATA_PNG):]))).load()
    assert page.figures == ["shot-1-region-1", "shot-1-region-2"]


def test_every_string_from_the_shot_is_escaped():
    table, regions = synthetic([0.2], [PENETRATION], paths=("/World/<A>", "/World/B&C"))
    hostile = "<img src=x onerror=alert(1)>"
    text = html_report([section(table, regions, {0: png()}, shot='shots/<b>&"x".usda', summary="<script>x</script>",
                                notes=[hostile])], title="run <1>")
    page = Page(text)
    assert "<script" not in text and hostile not in text and "<b>" not in text and "/World/<A>" not in text
    assert "&lt;img src=x onerror=alert(1)&gt;" in text and "shots/&lt;b&gt;&amp;&quot;x&quot;.usda" in text
    assert "/World/&lt;A&gt; × /World/B&amp;C" in text and "<title>run &lt;1&gt;</title>" in text
    assert len(page.images) == 2 and "script" not in page.tags


def test_regions_are_listed_worst_first_with_their_measure():
    depths = [0.1, 0.7, 0.3, 0.7]
    measures = [PENETRATION, PENETRATION, INTERSECTION_LENGTH, INTERSECTION_LENGTH]
    table, regions = synthetic(depths, measures)
    page = Page(html_report([section(table, regions)]))
    ids = [int(row[0]) for row in page.rows if row]
    assert ids == [2, 1, 4, 3]           # penetrations first, deepest first; then intersection lengths, longest first
    by_id = {int(row[0]): row for row in page.rows if row}
    assert by_id[2][1:8] == ["/World/A × /World/B", "inter", "5.5", "8.5", "1", "0.7", "penetration"]
    assert by_id[3][7] == "intersection length"
    assert by_id[3][8] == "(2, 1, -2) at frame 7 (t=14)"          # the centre at the deepest time


def test_only_the_worst_regions_with_a_picture_are_shown():
    count = MAX_PICTURES + 3
    depths = np.linspace(0.1, 1.5, count)                          # region r + 1 is deeper than region r
    table, regions = synthetic(depths.tolist(), [PENETRATION] * count)
    without = 2                                                    # the deepest but two has no picture
    pictures = {row: png() for row in range(count) if row != count - 1 - without}
    page = Page(html_report([section(table, regions, pictures)]))
    worst_with_pictures = [row for row in range(count - 1, -1, -1) if row in pictures][:MAX_PICTURES]
    assert page.figures == [f"shot-1-region-{row + 1}" for row in worst_with_pictures]
    assert len(page.images) == MAX_PICTURES + 1


def test_the_timeline_has_a_bar_per_region_deepest_on_top():
    table, regions = synthetic([0.1, 0.7, 0.3], [PENETRATION, PENETRATION, INTERSECTION_LENGTH])
    figure = timeline_figure(regions, table, CLOCK, (0.0, 40.0), "shots/a.usda")
    axes = figure.axes[0]
    labels = [label.get_text() for label in axes.get_yticklabels()]
    assert [label.split()[0] for label in labels] == ["2", "1", "3"]   # penetrations, then intersection lengths
    assert axes.get_xlim() == (0.0, 20.0)                          # frames of the checked span
    bars = axes.patches
    assert [bar.get_x() for bar in bars] == [5.5, 5.0, 6.0]         # first frames, worst first
    assert [bar.get_width() for bar in bars] == [3.0, 3.0, 3.0]
    darkness = [sum(bar.get_facecolor()[:3]) for bar in bars]
    assert darkness[0] < darkness[2] < darkness[1]                  # deeper is darker: 0.7, 0.3, 0.1
    assert [bool(bar.get_hatch()) for bar in bars] == [False, False, True]


def test_the_timeline_shows_the_worst_regions_when_there_are_many():
    count = MAX_TIMELINE_ROWS + 5
    table, regions = synthetic(np.arange(count, dtype=float).tolist(), [PENETRATION] * count)
    axes = timeline_figure(regions, table, CLOCK, (0.0, 200.0), "a").axes[0]
    assert len(axes.patches) == MAX_TIMELINE_ROWS and "+5 more" in axes.get_title()
    assert axes.get_yticklabels()[0].get_text().split()[0] == str(count)


def test_the_same_sections_give_the_same_page(real_shot):
    table, regions = real_shot
    sections = [section(table, regions, {0: png()}, span=SPAN),
                section(ContactTable.empty(None), RegionTable.empty(None), shot="clean.usda", exit_code=0)]
    assert html_report(sections) == html_report(sections)
    assert timeline_png(regions, table, CLOCK, SPAN, "a") == timeline_png(regions, table, CLOCK, SPAN, "a")


def test_shots_are_listed_with_their_exit_code_and_a_clean_shot_says_so(real_shot):
    table, regions = real_shot
    text = html_report([section(table, regions, span=SPAN, notes=["usdksl: warning: a gap"]),
                        section(ContactTable.empty(None), RegionTable.empty(None), shot="clean.usda",
                                summary="usdksl: clean", exit_code=0)])
    assert "<a href=\"#shot-1\">shots/a.usda</a>: exit code 1" in text
    assert "<a href=\"#shot-2\">clean.usda</a>: exit code 0" in text
    assert "exit code 1: contacts found" in text and "exit code 0: clean" in text
    assert "<li>usdksl: warning: a gap</li>" in text
    clean = text[text.index("<section id=\"shot-2\">"):]
    assert "no contacts in what was checked" in clean and "<img" not in clean and "<table" not in clean


def test_a_result_without_regions_says_how_many_face_pairs(real_shot):
    table, _ = real_shot
    text = html_report([section(table, None, span=SPAN)])
    assert f"{table.count} contacting face pairs, no regions in what was checked" in text


def test_without_matplotlib_the_error_names_the_extra(real_shot, monkeypatch):
    monkeypatch.setitem(sys.modules, "matplotlib", None)
    table, regions = real_shot
    with pytest.raises(UsdkslUsageError) as raised:
        html_report([section(table, regions, span=SPAN)])
    assert str(raised.value) == INSTALL_HINT and "pip install 'usdksl[report]'" in INSTALL_HINT


def test_an_unknown_region_measure_is_written_as_it_is():
    table, regions = synthetic([0.2], ["volume"])
    page = Page(html_report([section(table, regions)]))
    assert page.rows[-1][7] == "volume"
