"""Shots whose topology changes over time: check each constant-topology stretch on its own.

A mesh whose faceVertexCounts / faceVertexIndices / holeIndices or points count changes between two
samples has no flightplan across that change (vertex k before and after need not be the same vertex).
``usdksl check`` then splits the checked range at every change of any mesh: between the last sample of
one topology and the first sample of the next nothing is checked (a warning names the gap and the mesh),
and every stretch in between is checked as a shot of its own. Face indices in the reports always refer
to the topology in force at the row's time.
"""

from __future__ import annotations

from typing import Iterable, List, Optional, Sequence, Tuple

Range = Tuple[float, float]


def is_topology_change(error) -> bool:
    """True for the loader's errors about topology or points count changing between samples."""
    text = getattr(error, "message", str(error))
    return text.startswith("topology") or text.startswith("points count changes")


def topology_gaps(stage, mesh_paths: Iterable[str]) -> List[Tuple[float, float, str]]:
    """(last sample of one topology, first sample of the next, mesh path) for every change."""
    from .meshes import topology_segments

    gaps = []
    for path in mesh_paths:
        segments = topology_segments(stage.GetPrimAtPath(path))
        for (_, last), (first, _) in zip(segments[:-1], segments[1:]):
            gaps.append((float(last), float(first), str(path)))
    return sorted(gaps)


def split_range(full: Range, gaps: Sequence[Tuple[float, float, str]]) -> List[Range]:
    """``full`` minus the open intervals of ``gaps``: the closed stretches to check, in time order."""
    start, end = float(full[0]), float(full[1])
    ranges: List[Range] = []
    cursor = start
    for gap_start, gap_end, _ in sorted(gaps):
        if gap_end <= cursor or gap_start >= end:
            if gap_start >= end:
                break
            continue
        if gap_start >= cursor:
            ranges.append((cursor, gap_start))
        cursor = max(cursor, gap_end)
    if cursor <= end:
        ranges.append((cursor, end))
    return ranges


def full_range(stage, mesh_paths: Iterable[str], time_range: Optional[Range]) -> Range:
    """The checked range: ``time_range`` or the span of every points and xform sample of the meshes."""
    if time_range is not None:
        return (float(time_range[0]), float(time_range[1]))
    from .meshes import mesh_sample_times

    times = [t for path in mesh_paths for t in mesh_sample_times(stage.GetPrimAtPath(path)).tolist()]
    if not times:
        return (0.0, 0.0)
    return (min(times), max(times))
