"""The ``--plot FILE.png`` contact timeline: when each mesh pair is in contact, in frames.

One row per mesh pair with contacts, in order of first contact (at most :data:`MAX_ROWS`; a note says
how many more there are), frames on the x axis (usdksl.clock: numbered as usdview numbers them):

* the row is shaded over the union of its face pairs' contact spans, each span running from the face
  pair's first to its last contact (a face pair that separates and touches again in between is shaded
  throughout: only the two ends are known);
* a darker step curve inside the row is the number of its face pairs in contact over time, scaled to
  the row's own peak (the label gives the peak);
* a tick marks each distinct first contact (with a baseline: new ones red, known ones grey).

It needs last contacts (``CheckOptions(last_contact=True)``; ``--plot`` turns them on) and matplotlib,
an optional dependency (``pip install 'usdksl[plot]'``). The figure is drawn on a matplotlib ``Figure``
with the Agg canvas: pyplot and the process-wide backend are left alone.
"""

from __future__ import annotations

import io
import os
from dataclasses import dataclass
from typing import List, Optional, Tuple

import numpy as np

from ..clock import StageClock
from ..contacts.table import ContactTable
from ..errors import UsdkslUsageError

#: Rows drawn at most; further mesh pairs are counted in a note.
MAX_ROWS = 40
#: Figure size: width, and height per row plus a fixed margin, in inches; resolution of the PNG.
FIGURE_WIDTH_INCHES = 9.0
ROW_HEIGHT_INCHES = 0.45
MARGIN_HEIGHT_INCHES = 1.3
DOTS_PER_INCH = 100
#: Height of a first-contact tick, in points.
TICK_SIZE_POINTS = 9
#: A label longer than this keeps its end ("…/Shirt").
MAX_LABEL_CHARACTERS = 48
#: Colours: contact span, face-pair count curve, new and known first contacts.
SPAN_COLOR = "#f4b6b0"
COUNT_COLOR = "#c0392b"
NEW_TICK_COLOR = "#8b0000"
KNOWN_TICK_COLOR = "#7f7f7f"
INSTALL_HINT = "--plot needs matplotlib: pip install 'usdksl[plot]'"


def require_matplotlib() -> None:
    """Raise UsdkslUsageError (exit 2) when matplotlib cannot be imported."""
    try:
        import matplotlib  # noqa: F401
    except ImportError:
        raise UsdkslUsageError(INSTALL_HINT) from None


def contact_spans(first: np.ndarray, last: np.ndarray) -> np.ndarray:
    """float64[S, 2]: the union of the closed intervals [first[i], last[i]] as disjoint sorted spans."""
    if first.size == 0:
        return np.zeros((0, 2))
    order = np.argsort(first, kind="stable")
    starts, ends = first[order], np.maximum.accumulate(last[order])
    # a new span starts where an interval begins after every earlier one has ended
    breaks = np.flatnonzero(starts[1:] > ends[:-1]) + 1
    begin = np.concatenate([[0], breaks])
    finish = np.concatenate([breaks - 1, [starts.size - 1]])
    return np.stack([starts[begin], ends[finish]], axis=1)


def in_contact_counts(first: np.ndarray, last: np.ndarray) -> Tuple[np.ndarray, np.ndarray]:
    """(times[E], counts[E]): a step function, the number of intervals [first, last) holding from each
    event time on, up to the next (an interval whose first equals its last adds nothing: its tick shows it)."""
    times = np.concatenate([first, last])
    steps = np.concatenate([np.ones(first.size, np.int64), -np.ones(last.size, np.int64)])
    order = np.argsort(times, kind="stable")
    times, counts = times[order], np.cumsum(steps[order])
    # the value after every event at a time is the one that holds from it on
    last_of_time = np.concatenate([times[1:] != times[:-1], [True]]) if times.size else np.zeros(0, bool)
    return times[last_of_time], counts[last_of_time]


@dataclass
class TimelineRow:
    """One mesh pair's row, in frames."""

    label: str
    spans: np.ndarray          # float64[S, 2]
    count_times: np.ndarray    # float64[E]
    counts: np.ndarray         # int64[E]
    new_ticks: np.ndarray      # float64[N], distinct first contacts (all of them without a baseline)
    known_ticks: np.ndarray    # float64[K]


def timeline_rows(table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> List[TimelineRow]:
    """The rows of the timeline (every mesh pair with contacts, by first contact). Needs last times."""
    if table.last_time is None:
        raise ValueError("the timeline needs last contacts (CheckOptions(last_contact=True))")
    known = np.zeros(table.count, bool) if known is None else np.asarray(known, bool)
    first_frames, last_frames = clock.frames(table.time), clock.frames(table.last_time)
    width = np.int64(max(len(table.paths or []), int(max(table.mesh_a.max(initial=-1),
                                                          table.mesh_b.max(initial=-1))) + 1, 1))
    names = list(table.paths) if table.paths is not None else [str(i) for i in range(int(width))]
    index = {path: position for position, path in enumerate(names)}
    keys = table.mesh_a.astype(np.int64) * width + table.mesh_b
    by_key = np.argsort(keys, kind="stable")
    sorted_keys = keys[by_key]
    rows = []
    for summary in table.summary():        # one per mesh pair, by first contact
        key = index.get(summary["prim_a"], -1) * width + index.get(summary["prim_b"], -1)
        members = by_key[np.searchsorted(sorted_keys, key, "left"):np.searchsorted(sorted_keys, key, "right")]
        first, last = first_frames[members], last_frames[members]
        times, counts = in_contact_counts(first, last)
        label = summary["prim_a"] if summary["kind"] == "self" else f"{summary['prim_a']} x {summary['prim_b']}"
        rows.append(TimelineRow(label=_short(label), spans=contact_spans(first, last), count_times=times,
                                counts=counts, new_ticks=np.unique(first[~known[members]]),
                                known_ticks=np.unique(first[known[members]])))
    return rows


def _short(label: str) -> str:
    return label if len(label) <= MAX_LABEL_CHARACTERS else "…" + label[-(MAX_LABEL_CHARACTERS - 1):]


def timeline_figure(table: ContactTable, clock: StageClock, span: Tuple[float, float], title: str,
                    known: Optional[np.ndarray] = None):
    """The matplotlib Figure of the timeline over the checked ``span`` (time codes); ``title`` names the shot
    (its file name is shown)."""
    title = os.path.basename(title) or title
    require_matplotlib()
    from matplotlib.backends.backend_agg import FigureCanvasAgg
    from matplotlib.figure import Figure

    rows = timeline_rows(table, clock, known)
    shown = rows[:MAX_ROWS]
    height = MARGIN_HEIGHT_INCHES + ROW_HEIGHT_INCHES * max(len(shown), 1)
    figure = Figure(figsize=(FIGURE_WIDTH_INCHES, height), dpi=DOTS_PER_INCH)
    FigureCanvasAgg(figure)
    axes = figure.add_subplot(1, 1, 1)
    start, end = clock.frame(span[0]), clock.frame(span[1])
    axes.set_xlim(start, end if end > start else start + 1.0)
    axes.set_ylim(len(shown) - 0.5, -0.5)
    for index, row in enumerate(shown):
        axes.broken_barh([(a, b - a) for a, b in row.spans.tolist()], (index - 0.4, 0.8), facecolors=SPAN_COLOR,
                         edgecolors=COUNT_COLOR, linewidth=0.5)
        peak = int(row.counts.max()) if row.counts.size else 0
        if peak:
            level = index + 0.4 - 0.8 * row.counts / peak
            axes.fill_between(np.append(row.count_times, end), np.append(level, level[-1]), index + 0.4,
                              step="post", color=COUNT_COLOR, alpha=0.6, linewidth=0)
        for ticks, color in ((row.known_ticks, KNOWN_TICK_COLOR), (row.new_ticks, NEW_TICK_COLOR)):
            if ticks.size:
                axes.plot(ticks, np.full(ticks.size, index - 0.4), linestyle="none", marker="|",
                          markersize=TICK_SIZE_POINTS, markeredgewidth=1.2, color=color)
        axes.text(1.005, index, f"peak {peak}", transform=axes.get_yaxis_transform(), va="center", fontsize=7)
    axes.set_yticks(range(len(shown)))
    axes.set_yticklabels([row.label for row in shown], fontsize=8)
    axes.set_xlabel(f"frame ({clock.frames_per_second:g} fps, {clock.time_codes_per_second:g} time codes/s)")
    note = f"  (+{len(rows) - MAX_ROWS} more mesh pairs)" if len(rows) > MAX_ROWS else ""
    axes.set_title(f"{title}: {table.count} face pairs in contact{note}" if rows else f"{title}: no contacts",
                   fontsize=10)
    axes.grid(axis="x", color="#dddddd", linewidth=0.5)
    axes.set_axisbelow(True)
    figure.tight_layout()
    return figure


def timeline_png(table: ContactTable, clock: StageClock, span: Tuple[float, float], title: str,
                 known: Optional[np.ndarray] = None) -> bytes:
    """The timeline as PNG bytes (no software or date metadata, so the same input gives the same bytes)."""
    buffer = io.BytesIO()
    timeline_figure(table, clock, span, title, known).savefig(buffer, format="png", dpi=DOTS_PER_INCH,
                                                              metadata={"Software": None})
    return buffer.getvalue()


__all__ = ["MAX_ROWS", "TimelineRow", "contact_spans", "in_contact_counts", "require_matplotlib",
           "timeline_figure", "timeline_png", "timeline_rows"]
