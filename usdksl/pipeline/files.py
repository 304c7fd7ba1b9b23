"""The files of one check: where they go (:class:`OutputTargets`) and what they hold (:func:`render_files`).

Nothing here writes: :func:`usdksl.reports.output.write_files` publishes what :func:`render_files` returns
all together.
"""

from __future__ import annotations

import os
from dataclasses import dataclass
from pathlib import Path
from typing import Dict, Optional, Sequence, Tuple, Union

import numpy as np

from ..clock import StageClock
from ..contacts.baseline import BaselineComparison
from ..contacts.csv_file import contacts_csv
from ..contacts.table import ContactTable
from ..errors import UsdkslUsageError
from ..reading.loader import open_stage
from ..reading.scope import Plan
from ..reading.segments import topology_epochs
from ..regions.csv_file import regions_csv
from ..regions.table import RegionTable
from ..reports.formats import json_report, summary_csv
from ..reports.output import check_writable_directory, resolve_output_path
from ..reports.override import override_layer, override_layer_name, provenance_data, shot_stem
from ..reports.shot_hash import file_sha256, text_sha256
from ..version import package_version
from .coverage import Coverage
from .options import CheckOptions, TimeRange

# Imported where they are used, so that a plain check does not pay for them at start-up: the JUnit
# writer (xml.etree), a farm chunk's manifest and the contact timeline.

#: What write_files publishes at a target: text, bytes, or None (remove the file if there is one).
FileData = Optional[Union[str, bytes]]


@dataclass(frozen=True)
class OutputTargets:
    """Where the files of one shot go. ``json_path``/``junit_path`` None: not written; ``json_to_stdout``:
    the JSON document goes to stdout instead of a file (``--json -``)."""

    out_dir: Path
    json_path: Optional[Path] = None
    junit_path: Optional[Path] = None
    json_to_stdout: bool = False
    #: --plot: the contact timeline PNG (usdksl.reports.timeline).
    plot_path: Optional[Path] = None
    #: --report: the run's illustrated page (usdksl.pipeline.report); a check with one draws its worst regions.
    report_path: Optional[Path] = None

    def contacts_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.contacts.csv"

    def summary_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.summary.csv"

    def regions_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.regions.csv"

    def override_layer(self, shot: str, binary: bool = False) -> Path:
        """``<stem>.usdksl.usda``, or ``.usdksl.usdc`` for a layer written as a crate file."""
        return self.out_dir / override_layer_name(shot, binary)

    def crosscheck_csv(self, shot: str) -> Path:
        return self.out_dir / f"{shot_stem(shot)}.crosscheck.csv"

    def manifest(self, shot: str) -> Path:
        from ..reports.manifest import manifest_name

        return self.out_dir / manifest_name(shot_stem(shot))


def output_targets(shot: str, out: Optional[str] = None, json_path: Optional[str] = None,
                   junit_path: Optional[str] = None, plot_path: Optional[str] = None,
                   report_path: Optional[str] = None) -> OutputTargets:
    """Resolve and check the output locations before any work is done: ``out`` defaults to the shot's
    folder; ``json_path`` '-' means stdout. Raises UsdkslInputError for a missing shot and
    UsdkslUsageError for a folder that cannot be written."""
    if not os.path.isfile(shot):
        open_stage(shot)   # a missing input is reported as such, before anything about the output folder
    out_dir = Path(out) if out else Path(shot).resolve().parent
    check_writable_directory(out_dir)
    extra = [resolve_output_path(value) for value in (json_path, junit_path, plot_path, report_path)]
    for target in extra:
        if target is not None:
            check_writable_directory(target.resolve().parent)
    if plot_path is not None:
        from ..reports.timeline import require_matplotlib

        require_matplotlib()
    if report_path is not None:
        require_report_libraries()
    return OutputTargets(out_dir=out_dir, json_path=extra[0], junit_path=extra[1],
                         json_to_stdout=json_path == "-", plot_path=extra[2], report_path=extra[3])


def require_report_libraries() -> None:
    """Exit 2 before any check when what --report needs is missing (matplotlib, PyVista and VTK)."""
    from ..reports.html_report import require_matplotlib as require_timeline
    from ..reports.pictures import require_pyvista

    require_timeline()
    require_pyvista()


def render_files(shot: str, name: str, options: CheckOptions, targets: OutputTargets, segments, plan: Plan,
                 tables: Sequence[ContactTable], table: ContactTable, clock: StageClock, exit_code: int,
                 span: TimeRange, crosscheck_text: Optional[str] = None,
                 comparison: Optional[BaselineComparison] = None, coverage: Optional[Coverage] = None,
                 findings: Optional[list] = None, regions: Optional[RegionTable] = None,
                 root_layer_text: Optional[str] = None,
                 shot_sha256: Optional[str] = None) -> Tuple[Dict[Path, FileData], Optional[str]]:
    """({target: text or bytes} of every file of a check, None for a file to remove; the JSON text for
    stdout or None), in write order.

    ``segments``: [(range, loaded Shot)] as :func:`usdksl.pipeline.loading.load_segments` gives them,
    ``tables`` the contacts of each, ``table`` all of them as one (:func:`concatenate_pieces`), ``clock``
    the shot's (its stage metadata). A run over a time range (a farm chunk) also writes its manifest
    (usdksl.reports.manifest). ``root_layer_text``: the exported text of a root layer that lives in memory
    only (usdksl.pipeline.stage): the shot hash is that text's, and there is no override layer, which would
    have no file to sublayer. ``shot_sha256``: the shot's hash when it is known already (computed here when
    None)."""
    files: Dict[Path, FileData] = {}
    known = None if comparison is None else comparison.known
    files[targets.contacts_csv(shot)] = contacts_csv(table, clock, known,
                                                     None if regions is None else regions.row_ids)
    files[targets.summary_csv(shot)] = summary_csv(table, clock, known)
    if regions is not None:
        files[targets.regions_csv(shot)] = regions_csv(regions, table, clock, known)
    if crosscheck_text is not None:
        files[targets.crosscheck_csv(shot)] = crosscheck_text
    checked_meshes = sorted(set(plan.pairs.reshape(-1).tolist()))
    # one read of the root layer per check: the override layer and a farm chunk's manifest both name it
    if shot_sha256 is None:
        shot_sha256 = file_sha256(root_layer_file(shot)) if root_layer_text is None else text_sha256(root_layer_text)
    if root_layer_text is None:
        layer = override_layer(segments[0][1], checked_meshes, table, targets.override_layer(shot),
                               segments=[(r, seg, t) for (r, seg), t in zip(segments, tables)] if len(segments) > 1
                               else None, span=span, regions=regions, clock=clock,
                               provenance=provenance_data(shot_sha256, options.settings(), package_version()))
        files[targets.override_layer(shot, layer.binary)] = layer.data()
        files[targets.override_layer(shot, not layer.binary)] = None   # a layer of the other format is stale
    else:   # a root layer in memory: no file to sublayer, and none of an earlier check left beside the reports
        for binary in (False, True):
            files[targets.override_layer(shot, binary)] = None
    if options.time_range is not None:
        from ..reports.manifest import manifest_text

        files[targets.manifest(shot)] = manifest_text(name, shot_sha256, options.settings(), span, plan,
                                                      len(segments), package_version())
    stdout = None
    if targets.json_path is not None or targets.json_to_stdout:
        json_text = json_report(name, options.settings(), plan, table, exit_code, clock,
                                version=package_version(),
                                baseline=None if comparison is None else comparison.to_dict(), known=known,
                                coverage=None if coverage is None else coverage.to_dict(), findings=findings,
                                regions=regions)
        if targets.json_path is not None:
            files[targets.json_path] = json_text
        else:
            stdout = json_text
    if targets.junit_path is not None:
        from ..reports.junit import junit_report

        files[targets.junit_path] = junit_report(name, plan, table, clock, known)
    if targets.plot_path is not None:
        if table.last_time is None:
            raise UsdkslUsageError("the contact timeline needs last contacts (CheckOptions(last_contact=True))")
        from ..reports.timeline import timeline_png

        files[targets.plot_path] = timeline_png(table, clock, span, name, known)
    return files, stdout


def root_layer_file(shot: str) -> str:
    """The file on disk that holds the shot's root layer: the package for a package-relative path
    (``pkg.usdz[scene.usdc]``), whose hash then covers the layer inside it."""
    text = os.fspath(shot)
    if text.endswith("]") and "[" in text and not os.path.isfile(text):
        return text.split("[", 1)[0]
    return text


def concatenate_pieces(segments, tables: Sequence[ContactTable]) -> Tuple[ContactTable, np.ndarray]:
    """The contacts of a shot checked in pieces ([(range, Shot)], usdksl.reading.segments) as one table: a face
    pair whose meshes keep their faces across pieces is reported once, at its first contact; with the position
    of each of its rows among the pieces' rows (ContactTable.concatenate_rows)."""
    if len(tables) == 1:
        return tables[0], np.arange(tables[0].count, dtype=np.int64)
    return ContactTable.concatenate_rows(list(tables), topology_epochs([shot for _, shot in segments]))
