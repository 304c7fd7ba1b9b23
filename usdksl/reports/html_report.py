"""The ``--report FILE.html`` page: one self-contained HTML file per run that a person opens to see what to fix.

Per shot, in the order given: its summary line and exit code, the coverage lines and warnings, a contact
timeline (one bar per region from its first to its last contact, in frames, coloured by depth, the deepest on
top), the table of regions worst first (RegionTable.worst_first) and, for the worst :data:`MAX_PICTURES`
regions with a picture, that picture (usdksl.reports.pictures) with a caption saying which colour is which
side.

The page loads nothing: no script, no external URL; images are inline ``data:`` URIs and the CSS is in the
page, so it can be mailed, attached to a CI run or opened from a farm's disk. Every string that comes from a
shot (paths, prim names, messages) is escaped. The same sections give the same bytes (no date, no
generator stamp; the timeline PNG carries no metadata).

The timeline is drawn with matplotlib (the ``plot`` extra), on a ``Figure`` with the Agg canvas: pyplot and
the process-wide backend are left alone.
"""

from __future__ import annotations

import base64
import html
import io
from dataclasses import dataclass, field
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from ..clock import StageClock, console_number
from ..contacts.table import ContactTable
from ..errors import UsdkslUsageError
from ..exit_codes import CLEAN, CONTACTS_FOUND, CROSSCHECK_DISAGREES, INPUT_ERROR, INTERRUPTED, TERMINATED
from ..regions.table import INTERSECTION_LENGTH, PENETRATION, RegionTable
from .pictures import NEIGHBOURHOOD_BOX_SIZES, SIDE_A_COLOR, SIDE_B_COLOR

#: The line a user sees when matplotlib (the timeline) is missing.
INSTALL_HINT = "--report needs matplotlib for its timeline: pip install 'usdksl[report]'"
#: Regions shown with their picture, worst first.
MAX_PICTURES = 12
#: Rows of the region table at most (regions.csv lists every region); a note says how many more there are.
MAX_TABLE_ROWS = 500
#: Bars of the timeline at most (the worst regions); a note on the figure says how many more there are.
MAX_TIMELINE_ROWS = 40
#: Timeline figure: width, height per bar plus a fixed margin (inches); resolution of the PNG.
TIMELINE_WIDTH_INCHES = 9.0
TIMELINE_ROW_INCHES = 0.32
TIMELINE_MARGIN_INCHES = 1.4
TIMELINE_DPI = 100
#: A bar shorter than this share of the checked span is drawn this wide, so a one-sample region shows.
MIN_BAR_SHARE = 0.004
#: Colour map of depth (light: shallow, dark: deep) and the bars' outline.
DEPTH_COLORMAP = "YlOrRd"
BAR_EDGE_COLOR = "#444444"
#: Hatching of bars whose depth is an intersection length (no closed side), so the two measures are told apart.
INTERSECTION_HATCH = "///"
#: Label of a timeline bar longer than this keeps its end.
MAX_LABEL_CHARACTERS = 44
#: Significant digits of depths and coordinates on the page.
DIGITS = 4
#: How the page names each depth measure.
MEASURE_NAMES = {PENETRATION: "penetration", INTERSECTION_LENGTH: "intersection length"}
#: What each exit code means, as the page says it.
EXIT_MEANINGS = {CLEAN: "clean", CONTACTS_FOUND: "contacts found", INPUT_ERROR: "not checked (input or usage error)",
                 CROSSCHECK_DISAGREES: "cross-check disagrees", INTERRUPTED: "interrupted",
                 TERMINATED: "terminated"}

STYLE = """
body { font-family: system-ui, -apple-system, "Segoe UI", Roboto, sans-serif; margin: 1.5em auto; max-width: 1100px;
       padding: 0 1em; color: #1d1d1d; }
h1 { font-size: 1.5em; } h2 { font-size: 1.25em; margin-top: 2em; border-bottom: 1px solid #ccc; }
h3 { font-size: 1.05em; }
.summary { font-family: ui-monospace, Menlo, Consolas, monospace; background: #f4f4f4; padding: 0.5em; }
.exit-0 { color: #1b7f3b; } .exit-1, .exit-2, .exit-3, .exit-130, .exit-143 { color: #b42318; }
ul.notes { font-family: ui-monospace, Menlo, Consolas, monospace; font-size: 0.85em; }
table { border-collapse: collapse; font-size: 0.9em; }
th, td { border: 1px solid #ccc; padding: 0.25em 0.5em; text-align: left; vertical-align: top; }
th { background: #eee; } td.number { text-align: right; font-variant-numeric: tabular-nums; }
figure { margin: 1em 0; } figure img { max-width: 100%; border: 1px solid #ddd; }
figcaption { font-size: 0.9em; max-width: 640px; }
.swatch { display: inline-block; width: 0.9em; height: 0.9em; vertical-align: -0.1em; border: 1px solid #444; }
.regions-pictures { display: flex; flex-wrap: wrap; gap: 1em; }
"""


@dataclass
class ShotSection:
    """What the page shows of one shot."""

    shot: str                                   # the shot as given (path or asset path)
    summary: str                                # its summary line, as the console prints it
    exit_code: int
    clock: StageClock
    span: Tuple[float, float]                   # the checked range (time codes)
    table: ContactTable
    regions: Optional[RegionTable]
    pictures: Dict[int, bytes] = field(default_factory=dict)   # {region row: PNG bytes}
    notes: List[str] = field(default_factory=list)             # coverage lines and warnings


def _e(value) -> str:
    return html.escape(str(value), quote=True)


def _number(value: float) -> str:
    return f"{float(value):.{DIGITS}g}"


def _data_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def _names(regions: RegionTable, table: ContactTable) -> List[str]:
    """The name of each mesh index: its prim path (the index as text for tables without paths)."""
    return list(regions.paths) if regions.paths is not None else table.mesh_names()


def _pair_label(names: Sequence[str], a: int, b: int) -> str:
    return names[a] if a == b else f"{names[a]} × {names[b]}"


def _short(label: str) -> str:
    return label if len(label) <= MAX_LABEL_CHARACTERS else "…" + label[-(MAX_LABEL_CHARACTERS - 1):]


def require_matplotlib() -> None:
    """Raise UsdkslUsageError (exit 2, one line naming the extra) when matplotlib cannot be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsdkslUsageError(INSTALL_HINT) from None


def timeline_figure(regions: RegionTable, table: ContactTable, clock: StageClock, span: Tuple[float, float],
                    title: str):
    """The matplotlib Figure of the region timeline over the checked ``span`` (time codes): a bar per region
    (the worst MAX_TIMELINE_ROWS) from its first to its last contact in frames, coloured by depth, deepest on
    top; hatched where the depth is an intersection length."""
    require_matplotlib()
    from matplotlib import colormaps
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.cm import ScalarMappable
    from matplotlib.colors import Normalize
    from matplotlib.figure import Figure

    order = regions.worst_first()
    shown = order[:MAX_TIMELINE_ROWS]
    names = _names(regions, table)
    start, end = clock.frame(span[0]), clock.frame(span[1])
    end = end if end > start else start + 1.0
    first, last = clock.frames(regions.first_time[shown]), clock.frames(regions.last_time[shown])
    width = np.maximum(last - first, MIN_BAR_SHARE * (end - start))
    depth = regions.max_depth[shown]
    norm = Normalize(vmin=0.0, vmax=float(regions.max_depth.max()) if regions.count and regions.max_depth.max() > 0
                     else 1.0)
    colormap = colormaps[DEPTH_COLORMAP]

    height = TIMELINE_MARGIN_INCHES + TIMELINE_ROW_INCHES * max(len(shown), 1)
    figure = Figure(figsize=(TIMELINE_WIDTH_INCHES, height), dpi=TIMELINE_DPI)
    FigureCanvasAgg(figure)
    axes = figure.add_subplot(1, 1, 1)
    rows = np.arange(len(shown))
    hatches = [INTERSECTION_HATCH if measure == INTERSECTION_LENGTH else "" for measure in
               regions.depth_measure[shown].tolist()]
    axes.barh(rows, width, left=first, height=0.7, color=colormap(norm(depth)), edgecolor=BAR_EDGE_COLOR,
              linewidth=0.6, hatch=hatches)
    axes.set_xlim(start, end)
    axes.set_ylim(len(shown) - 0.5, -0.5)
    labels = [_short(f"{int(row) + 1}  {_pair_label(names, int(regions.mesh_a[row]), int(regions.mesh_b[row]))}")
              for row in shown.tolist()]
    axes.set_yticks(rows)
    axes.set_yticklabels(labels, fontsize=8)
    axes.set_xlabel(f"frame ({clock.frames_per_second:g} fps, {clock.time_codes_per_second:g} time codes/s)")
    note = f" (the worst {len(shown)}; +{regions.count - len(shown)} more)" if regions.count > len(shown) else ""
    axes.set_title(f"{title}: {regions.count} region{'s' if regions.count != 1 else ''} by depth{note}",
                   fontsize=10)
    axes.grid(axis="x", color="#dddddd", linewidth=0.5)
    axes.set_axisbelow(True)
    colorbar = figure.colorbar(ScalarMappable(norm=norm, cmap=colormap), ax=axes, pad=0.01)
    colorbar.set_label("depth (scene units)", fontsize=8)
    figure.tight_layout()
    return figure


def timeline_png(regions: RegionTable, table: ContactTable, clock: StageClock, span: Tuple[float, float],
                 title: str) -> bytes:
    """The region timeline as PNG bytes (no software or date metadata: the same input gives the same bytes)."""
    buffer = io.BytesIO()
    timeline_figure(regions, table, clock, span, title).savefig(buffer, format="png", dpi=TIMELINE_DPI,
                                                                 metadata={"Software": None})
    return buffer.getvalue()


def _region_table(section: ShotSection, regions: RegionTable, names: Sequence[str], anchor: str) -> List[str]:
    clock = section.clock
    order = regions.worst_first()
    pictured = set(_pictured_rows(section, regions).tolist())
    lines = ["<table class=\"regions\">",
             "<thead><tr><th>region</th><th>prims</th><th>kind</th><th>first frame</th><th>last frame</th>"
             "<th>face pairs</th><th>depth</th><th>measure</th><th>where (at the deepest frame)</th></tr></thead>",
             "<tbody>"]
    for row in order[:MAX_TABLE_ROWS].tolist():
        a, b = int(regions.mesh_a[row]), int(regions.mesh_b[row])
        region_id = row + 1
        label = f"<a href=\"#{anchor}-region-{region_id}\">{region_id}</a>" if row in pictured else str(region_id)
        centre = ", ".join(_number(value) for value in regions.center[row].tolist())
        where = f"({centre}) at {clock.describe(float(regions.max_depth_time[row]))}"
        lines.append(
            f"<tr><td class=\"number\">{label}</td><td>{_e(_pair_label(names, a, b))}</td>"
            f"<td>{'self' if a == b else 'inter'}</td>"
            f"<td class=\"number\">{_e(console_number(clock.frame(float(regions.first_time[row]))))}</td>"
            f"<td class=\"number\">{_e(console_number(clock.frame(float(regions.last_time[row]))))}</td>"
            f"<td class=\"number\">{int(regions.face_pairs[row])}</td>"
            f"<td class=\"number\">{_e(_number(regions.max_depth[row]))}</td>"
            f"<td>{_e(MEASURE_NAMES.get(regions.depth_measure[row], regions.depth_measure[row]))}</td>"
            f"<td>{_e(where)}</td></tr>")
    lines.append("</tbody></table>")
    if regions.count > MAX_TABLE_ROWS:
        lines.append(f"<p>{regions.count - MAX_TABLE_ROWS} more regions are in the regions.csv report.</p>")
    return lines


def _pictured_rows(section: ShotSection, regions: RegionTable) -> np.ndarray:
    """Region rows whose picture the page shows: the worst MAX_PICTURES of those with one."""
    order = regions.worst_first()
    has = np.isin(order, np.array(sorted(section.pictures), dtype=np.int64))
    return order[has][:MAX_PICTURES]


def _picture(section: ShotSection, regions: RegionTable, names: Sequence[str], row: int, anchor: str) -> List[str]:
    a, b = int(regions.mesh_a[row]), int(regions.mesh_b[row])
    faces_a, faces_b = regions.faces(row, section.table)
    region_id = row + 1
    measure = MEASURE_NAMES.get(regions.depth_measure[row], regions.depth_measure[row])
    if a == b:
        sides = (f"{len(faces_a)} faces of {_e(names[a])} on one side of its face pairs",
                 f"{len(faces_b)} on the other; grey: the rest of the mesh")
    else:
        sides = (f"{len(faces_a)} faces of {_e(names[a])}",
                 f"{len(faces_b)} faces of {_e(names[b])}; grey: the rest of both meshes")
    caption = (
        f"Region {region_id}: {_e(_pair_label(names, a, b))}, {_e(measure)} {_e(_number(regions.max_depth[row]))} "
        f"at {_e(section.clock.describe(float(regions.max_depth_time[row])))}. "
        f"<span class=\"swatch\" style=\"background:{SIDE_A_COLOR}\"></span> {sides[0]}, "
        f"<span class=\"swatch\" style=\"background:{SIDE_B_COLOR}\"></span> {sides[1]}, within "
        f"{NEIGHBOURHOOD_BOX_SIZES:g} region sizes of its centre.")
    alt = f"region {region_id}: {_pair_label(names, a, b)} at {section.clock.describe(float(regions.max_depth_time[row]))}"
    return [f"<figure class=\"region\" id=\"{anchor}-region-{region_id}\">",
            f"<img src=\"{_data_uri(section.pictures[row])}\" alt=\"{_e(alt)}\">",
            f"<figcaption>{caption}</figcaption></figure>"]


def _section(section: ShotSection, index: int) -> List[str]:
    anchor = f"shot-{index + 1}"
    exit_code = int(section.exit_code)
    meaning = EXIT_MEANINGS.get(exit_code, "")
    lines = [f"<section id=\"{anchor}\">", f"<h2>{_e(section.shot)}</h2>",
             f"<p class=\"summary\">{_e(section.summary)}</p>",
             f"<p class=\"exit-{exit_code}\">exit code {exit_code}{': ' + _e(meaning) if meaning else ''}</p>"]
    if section.notes:
        lines.append("<ul class=\"notes\">")
        lines += [f"<li>{_e(note)}</li>" for note in section.notes]
        lines.append("</ul>")
    regions = section.regions
    if regions is None or regions.count == 0:
        said = "no contacts" if section.table.count == 0 else f"{section.table.count} contacting face pairs, no regions"
        lines += [f"<p>{_e(said)} in what was checked.</p>", "</section>"]
        return lines
    names = _names(regions, section.table)
    timeline = timeline_png(regions, section.table, section.clock, section.span, section.shot)
    lines += ["<h3>Contact timeline</h3>",
              f"<figure class=\"timeline\"><img src=\"{_data_uri(timeline)}\" "
              f"alt=\"{_e('contact timeline of ' + section.shot)}\"><figcaption>One bar per region from its first to "
              f"its last contact, deepest on top, coloured by depth (hatched: the depth is the length of the "
              f"intersection, neither side is closed).</figcaption></figure>",
              f"<h3>Regions, worst first ({regions.count}; {section.table.count} contacting face pairs)</h3>"]
    lines += _region_table(section, regions, names, anchor)
    pictured = _pictured_rows(section, regions)
    if pictured.size:
        lines += [f"<h3>The worst region{'s' if pictured.size != 1 else ''}</h3>", "<div class=\"regions-pictures\">"]
        for row in pictured.tolist():
            lines += _picture(section, regions, names, row, anchor)
        lines.append("</div>")
    lines.append("</section>")
    return lines


def html_report(sections: Sequence[ShotSection], title: str = "usdksl report") -> str:
    """The page (text) for the shots of one run, in the order given."""
    lines = ["<!DOCTYPE html>", "<html lang=\"en\">", "<head>", "<meta charset=\"utf-8\">",
             "<meta name=\"viewport\" content=\"width=device-width, initial-scale=1\">", f"<title>{_e(title)}</title>",
             f"<style>{STYLE}</style>", "</head>", "<body>", f"<h1>{_e(title)}</h1>"]
    if len(sections) > 1:
        lines.append("<ul class=\"shots\">")
        lines += [f"<li><a href=\"#shot-{index + 1}\">{_e(section.shot)}</a>: exit code {int(section.exit_code)}</li>"
                  for index, section in enumerate(sections)]
        lines.append("</ul>")
    for index, section in enumerate(sections):
        lines += _section(section, index)
    lines += ["</body>", "</html>", ""]
    return "\n".join(lines)


__all__ = ["INSTALL_HINT", "MAX_PICTURES", "ShotSection", "html_report", "require_matplotlib", "timeline_figure",
           "timeline_png"]
