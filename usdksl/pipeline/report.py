"""The illustrated report of a run (``--report FILE.html``): the pictures of one shot's worst regions, made
while its meshes are loaded, and the page made of every shot's result.

:func:`region_pictures_of` runs inside a check (:func:`usdksl.pipeline.check.conclude`), because the pictures
need the meshes at the regions' deepest samples; the page (:func:`report_html`) is made once the run's shots are
checked, from their :class:`~usdksl.pipeline.result.CheckResult` (which carry the pictures as PNG bytes, so a
Dask worker's result brings them along).
"""

from __future__ import annotations

from typing import Dict, Optional, Sequence, Tuple

import numpy as np

from ..clock import StageClock
from ..contacts.table import ContactTable
from ..exit_codes import INPUT_ERROR
from ..regions.table import RegionTable
from ..unmasked import distinct_sorted
from .messages import ERROR, PLAN, WARNING
from .options import TimeRange
from .result import CheckResult


def region_pictures_of(segments, regions: RegionTable, table: ContactTable) -> Dict[int, bytes]:
    """{region row: PNG} of the worst regions (as many as the page shows), each drawn with the meshes of the
    constant-topology piece ([(range, Shot)]) its first contact lies in."""
    from ..reports.html_report import MAX_PICTURES
    from ..reports.pictures import region_pictures

    worst = regions.worst_first()[:MAX_PICTURES]
    if worst.size == 0:
        return {}
    piece = np.zeros(worst.size, np.int64)
    for index, (segment_range, _) in enumerate(segments[1:], start=1):
        if segment_range is not None:
            piece[regions.first_time[worst] >= segment_range[0]] = index
    pictures: Dict[int, bytes] = {}
    for index in distinct_sorted(piece).tolist():
        rows = worst[piece == index].tolist()
        shot = segments[index][1]
        pictures.update(region_pictures(shot.meshes, table, regions, rows,
                                        up_axis=str(shot.metadata.get("upAxis", "Y"))))
    return pictures


def report_html(results: Sequence[Tuple[str, Optional[CheckResult], int, Optional[str]]]) -> str:
    """The page of a run: one section per shot, in the order given, each ``(name, result or None, exit code,
    error line or None)``; a shot that could not be checked shows its error line."""
    from ..reports.html_report import ShotSection, html_report

    sections = []
    for name, result, exit_code, error in results:
        if result is None:
            sections.append(ShotSection(shot=name, summary=f"usdksl: error: {error or 'failed'}",
                                        exit_code=exit_code or INPUT_ERROR, clock=StageClock(), span=(0.0, 0.0),
                                        table=ContactTable.empty(None), regions=None))
            continue
        notes = [message.text for message in result.messages
                 if message.level in (WARNING, ERROR) or (message.level == PLAN and "not checked" in message.text)]
        span: TimeRange = result.span
        sections.append(ShotSection(shot=name, summary=result.summary, exit_code=result.exit_code, clock=result.clock,
                                    span=(float(span[0]), float(span[1])), table=result.table,
                                    regions=result.regions, pictures=dict(result.pictures), notes=notes))
    return html_report(sections)


def report_for_results(results: Sequence[CheckResult]) -> str:
    """The page of checked shots (:func:`usdksl.check_shot` results made with a report target)."""
    return report_html([(result.shot, result, result.exit_code, None) for result in results])


def report_line(path) -> str:
    """The console line that links the page: its file URL, which terminals open on a click."""
    from pathlib import Path

    return f"usdksl: report: {Path(path).resolve().as_uri()}"
