"""Shots where a mesh cannot be followed across some samples: check every stretch it can be followed on.

A mesh has no straight-line motion across

* a **topology change**: faceVertexCounts / faceVertexIndices / holeIndices or the points count differ
  between two samples (vertex k before and after need not be the same vertex);
* an **empty sample**: a ``points`` sample that is ``[]`` or value-blocked (``Sdf.ValueBlock``), or a sample
  with no faces: USD shows no surface there.

Such a mesh is checked over its *stretches*: the runs of samples with points and one topology. The interval
between two stretches (from the last sample of one to the first of the next; before the first or after the last
stretch when the mesh starts or ends empty) is a *gap* of that mesh only: the checked range is cut at every gap's
ends, each piece is loaded and checked as a shot of its own, and in a piece a mesh's gap covers it is left out
(every other mesh is checked there). Each gap is one warning and an unchecked stretch of the coverage account.
Face indices in the reports refer to the topology in force at the row's time; a face pair whose meshes keep their
topology across a cut is reported once, at its first contact (docs/contracts.md, Topology).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Dict, Iterable, List, Optional, Sequence, Tuple

import numpy as np

from ..warning_kinds import EMPTY_SAMPLE, TOPOLOGY_CHANGE

Range = Tuple[float, float]


def is_topology_change(error) -> bool:
    """True for the loader's errors about topology or points count changing between samples."""
    text = getattr(error, "message", str(error))
    return text.startswith("topology") or text.startswith("points count changes")


@dataclass(frozen=True)
class Stretch:
    """Consecutive samples (time codes, ends included) of one mesh with one topology; ``valid`` is False
    when USD shows no surface there (no points, no faces)."""

    first: float
    last: float
    valid: bool


@dataclass(frozen=True)
class Gap:
    """An open interval (time codes) over which one mesh cannot be checked; ``start`` is -inf when the mesh
    starts without a surface, ``end`` +inf when it ends without one. ``kind``: usdksl.warning_kinds."""

    start: float
    end: float
    path: str
    kind: str
    #: The samples that make the gap (empty or blocked ones), for the warning.
    bad_times: Tuple[float, ...] = ()

    def covers(self, piece: Range) -> bool:
        """Whether the gap overlaps the inside of ``piece``."""
        return self.start < piece[1] and self.end > piece[0]

    def describe(self, file: str) -> str:
        """One warning line: file, prim, times and why."""
        where = (f"before time {self.end:g}" if self.start == -np.inf else
                 f"after time {self.start:g}" if self.end == np.inf else
                 f"between time {self.start:g} and {self.end:g}")
        if self.kind == TOPOLOGY_CHANGE:
            return f"{file}: {self.path}: topology changes {where}; that interval is not checked for this mesh"
        samples = ", ".join(f"{t:g}" for t in self.bad_times[:3]) + (" ..." if len(self.bad_times) > 3 else "")
        return f"{file}: {self.path}: points are empty or blocked at time {samples}: not checked {where}"


def mesh_stretches(prim) -> List[Stretch]:
    """The stretches of a UsdGeom.Mesh prim over all its ``points`` and topology samples, in time order
    (reads every points sample: only for meshes whose samples the loader could not follow)."""
    from .meshes import topology_stretches

    return [Stretch(first, last, _shows_surface(key)) for first, last, key in topology_stretches(prim)]


def _shows_surface(key) -> bool:
    counts, _, _, point_count = key
    return point_count > 0 and counts.size > 0


def mesh_gaps(path: str, stretches: Sequence[Stretch]) -> List[Gap]:
    """The gaps of one mesh: between its valid stretches, and before the first or after the last one when
    the mesh starts or ends without a surface (USD holds that empty value beyond it). A mesh with no valid
    stretch has no gap: it is empty, and the loader skips it."""
    valid = [index for index, stretch in enumerate(stretches) if stretch.valid]
    if not valid:
        return []

    def bad_times(run: Sequence[Stretch]) -> Tuple[float, ...]:
        return tuple(dict.fromkeys(t for stretch in run if not stretch.valid for t in (stretch.first, stretch.last)))

    gaps = []
    if valid[0] > 0:
        gaps.append(Gap(-np.inf, stretches[valid[0]].first, path, EMPTY_SAMPLE, bad_times(stretches[:valid[0]])))
    for before, after in zip(valid, valid[1:]):
        between = stretches[before + 1:after]
        gaps.append(Gap(stretches[before].last, stretches[after].first, path,
                        EMPTY_SAMPLE if between else TOPOLOGY_CHANGE, bad_times(between)))
    if valid[-1] < len(stretches) - 1:
        gaps.append(Gap(stretches[valid[-1]].last, np.inf, path, EMPTY_SAMPLE, bad_times(stretches[valid[-1] + 1:])))
    return gaps


def cut_range(full: Range, gaps: Sequence[Gap]) -> List[Range]:
    """``full`` cut at every gap end inside it: the pieces checked as shots of their own, in time order."""
    start, end = float(full[0]), float(full[1])
    cuts = sorted({start, end} | {t for gap in gaps for t in (gap.start, gap.end) if start < t < end})
    if len(cuts) == 1:
        return [(start, end)]
    return list(zip(cuts[:-1], cuts[1:]))


def absent_meshes(piece: Range, gaps: Sequence[Gap], stretches: Dict[str, Sequence[Stretch]]) -> Dict[str, float]:
    """{mesh path: time of a sample with a surface} for the meshes a gap leaves out of ``piece``: the loader
    loads each still at that time (faces of its nearest stretch) so that every piece has the same meshes, and the
    plan leaves it out of every pair there."""
    absent: Dict[str, float] = {}
    for gap in gaps:
        if gap.path in absent or not gap.covers(piece):
            continue
        valid = [stretch for stretch in stretches[gap.path] if stretch.valid]
        after = [stretch for stretch in valid if stretch.first >= gap.end]
        absent[gap.path] = after[0].first if after else valid[-1].last
    return absent


def full_range(sample_times: Iterable[np.ndarray], time_range: Optional[Range]) -> Range:
    """The checked range: ``time_range``, or the span of the meshes' sample times (0..0 when none has one)."""
    if time_range is not None:
        return (float(time_range[0]), float(time_range[1]))
    times = [array for array in sample_times if len(array)]
    if not times:
        return (0.0, 0.0)
    return (min(float(array[0]) for array in times), max(float(array[-1]) for array in times))


def topology_epochs(shots: Sequence) -> np.ndarray:
    """int[pieces, meshes] for the loaded pieces of one shot (same meshes in the same order): a mesh's epoch in
    a piece is the first piece where it has the same faces (triangles and face count), so two pieces with equal
    epochs number its faces alike."""
    count = len(shots[0].meshes) if shots else 0
    epochs = np.zeros((len(shots), count), dtype=np.int64)
    for index in range(count):
        for piece, shot in enumerate(shots):
            mesh = shot.meshes[index]
            epochs[piece, index] = next(
                earlier for earlier in range(piece + 1)
                if shots[earlier].meshes[index].face_count == mesh.face_count
                and np.array_equal(shots[earlier].meshes[index].triangles, mesh.triangles)
                and np.array_equal(shots[earlier].meshes[index].triangle_face, mesh.triangle_face))
    return epochs
