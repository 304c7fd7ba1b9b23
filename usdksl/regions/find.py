"""The regions of one check: contacts grouped into problems, each measured (docs/contracts.md, Regions).

:func:`find_regions` runs the native grouping (:func:`usdksl.regions.grouping.group_regions`) and depth
(:func:`usdksl.regions.depth.region_depths`) over the meshes of one constant-topology piece and folds their
per-row and per-sample answers into one :class:`~usdksl.regions.table.RegionTable` row per region, with
numpy reductions (no Python loop over rows or regions).
"""

from __future__ import annotations

from typing import Optional, Sequence, Tuple

import numpy as np

from ..contacts.table import ContactTable
from ..reading.positions import vertex_points_at
from ..unmasked import distinct_sorted
from .closed import closed_meshes
from .depth import depth_sample_flags, region_depths
from .grouping import Grouping, group_regions
from .table import INTERSECTION_LENGTH, PENETRATION, DepthSamples, RegionTable


def find_regions(meshes: Sequence, table: ContactTable, sample_times: np.ndarray, thickness: float = 0.0,
                 time_range: Optional[Tuple[float, float]] = None, frames_per_time_code: float = 1.0) -> RegionTable:
    """The regions of ``table`` (the contacts of ``meshes``, one piece of constant topology), grouped at the
    samples on whole frames among ``sample_times`` (the piece's samples; only those inside ``time_range`` are
    used; :func:`usdksl.regions.depth.depth_sample_flags`, ``frames_per_time_code`` from the stage's clock,
    :attr:`usdksl.clock.StageClock.frames_per_time_code`) and the first and last of them, and measured at each
    region's first and last samples and the samples between on whole frames. With last contacts in ``table``
    a region's last_time is the latest continuous last contact of its face pairs."""
    if table.count == 0:
        return RegionTable.empty(table.paths)
    times = np.asarray(sample_times, dtype=np.float64)
    # flagged over the whole piece, so that a sample's flag does not depend on where a time range cuts it
    measured = depth_sample_flags(times, frames_per_time_code)
    if time_range is not None:
        inside = (times >= time_range[0]) & (times <= time_range[1])
        times, measured = times[inside], measured[inside]
    if times.size == 0:   # a piece of one instant: its contacts are all initial, at the range start
        times = distinct_sorted(table.time)
        measured = np.ones(times.size, bool)
    grouping = _group_at(meshes, table, times, measured, thickness)
    closed = closed_meshes(meshes)
    samples = region_depths(meshes, table, grouping, times, closed, measured=measured)
    return fold(meshes, table, grouping.row_region, grouping.region_count, grouping.row_last_sampled, samples,
                closed)


def _group_at(meshes: Sequence, table: ContactTable, times: np.ndarray, measured: np.ndarray,
              thickness: float) -> Grouping:
    """The grouping of ``table`` at the measured samples of ``times`` and its first and last (where the
    checked span begins and ends), its spans indexing ``times``: a sub-frame sample decides no region's
    extent, as it decides no depth."""
    grouped = measured.copy()
    grouped[[0, -1]] = True
    kept = np.flatnonzero(grouped)
    grouping = group_regions(meshes, table, times[kept], thickness)
    grouping.row_span = kept[grouping.row_span].astype(np.int32)
    return grouping


def fold(meshes: Sequence, table: ContactTable, row_region: np.ndarray, region_count: int,
         row_last_sampled: np.ndarray, samples: DepthSamples, closed: np.ndarray) -> RegionTable:
    """One RegionTable row per region from the per-row grouping and the per-sample depths."""
    row_region = np.asarray(row_region, dtype=np.int32)
    count = int(region_count)
    if row_region.size and (row_region.min() < 0 or row_region.max() >= count):
        raise ValueError("every contact row needs a region")
    # rows are in time order, so a region's first row is its first contact and sets its sides
    first_row = np.full(count, table.count, np.int64)
    np.minimum.at(first_row, row_region, np.arange(table.count))
    mesh_a, mesh_b = table.mesh_a[first_row], table.mesh_b[first_row]
    first_time = table.time[first_row]
    ends = table.last_time if table.last_time is not None else np.asarray(row_last_sampled, np.float64)
    last_time = np.full(count, -np.inf)
    np.maximum.at(last_time, row_region, ends)
    last_time = np.maximum(last_time, first_time)
    face_pairs = np.bincount(row_region, minlength=count).astype(np.int64)

    closed = np.asarray(closed, bool)
    penetrates = (mesh_a != mesh_b) & (closed[mesh_a] | closed[mesh_b])
    measure = np.where(penetrates, PENETRATION, INTERSECTION_LENGTH).astype(object)

    region = np.asarray(samples.region, dtype=np.int64)
    value = np.where(penetrates[region], np.nan_to_num(samples.penetration, nan=0.0), samples.intersection_length)
    max_depth, depth_sample = _argmax_per_group(value, region, count)
    max_length, _ = _argmax_per_group(samples.intersection_length, region, count)
    deep = (depth_sample >= 0) & (max_depth > 0)
    max_depth_time = np.where(deep, samples.time[np.maximum(depth_sample, 0)], first_time)

    at = np.maximum(depth_sample, 0)
    sample_box_known = (deep & np.all(np.isfinite(samples.box_min[at]), axis=1) if samples.count
                        else np.zeros(count, bool))
    # the other regions are placed where their contacts began: only their rows are looked at
    box_min, box_max = contact_boxes(meshes, table, np.flatnonzero(~sample_box_known[row_region]), row_region, count)
    box_min[sample_box_known] = samples.box_min[at[sample_box_known]]
    box_max[sample_box_known] = samples.box_max[at[sample_box_known]]
    return RegionTable(paths=table.paths and list(table.paths), mesh_a=mesh_a.astype(np.int32),
                       mesh_b=mesh_b.astype(np.int32), first_time=first_time, last_time=last_time,
                       face_pairs=face_pairs, depth_measure=measure, max_depth=max_depth,
                       max_depth_time=max_depth_time, max_intersection_length=max_length,
                       center=(box_min + box_max) / 2, box_min=box_min, box_max=box_max, row_region=row_region,
                       samples=samples)


def _argmax_per_group(value: np.ndarray, group: np.ndarray, count: int) -> Tuple[np.ndarray, np.ndarray]:
    """(float64[count]: the largest value of each group, 0 for a group with none; int64[count]: the index of
    its first occurrence, -1 for none)."""
    best = np.zeros(count)
    where = np.full(count, -1, np.int64)
    if value.size == 0:
        return best, where
    value = np.nan_to_num(np.asarray(value, np.float64), nan=0.0)
    # by group, then value descending, then index: the first row of each group is its (first) maximum
    order = np.lexsort((np.arange(value.size), -value, group))
    lead = np.ones(order.size, bool)
    lead[1:] = group[order][1:] != group[order][:-1]
    chosen = order[lead]
    best[group[chosen]] = value[chosen]
    where[group[chosen]] = chosen
    return best, where


def contact_boxes(meshes: Sequence, table: ContactTable, rows: np.ndarray, row_region: np.ndarray,
                  count: int) -> Tuple[np.ndarray, np.ndarray]:
    """(box_min, box_max) float64[count, 3]: per region, where its contacts among ``rows`` (row indices of
    ``table``) began: the union over them of the overlap of the two faces' boxes at the row's first contact
    (the union of both boxes where they do not overlap, as for a contact within a thickness); +inf/-inf for a
    region with none of ``rows``."""
    time = table.time[rows]
    low_a, high_a = _face_boxes(meshes, table.mesh_a[rows], table.face_a[rows], time)
    low_b, high_b = _face_boxes(meshes, table.mesh_b[rows], table.face_b[rows], time)
    low, high = np.maximum(low_a, low_b), np.minimum(high_a, high_b)
    apart = np.any(low > high, axis=1)
    low = np.where(apart[:, None], np.minimum(low_a, low_b), low)
    high = np.where(apart[:, None], np.maximum(high_a, high_b), high)
    box_min = np.full((count, 3), np.inf)
    box_max = np.full((count, 3), -np.inf)
    np.minimum.at(box_min, row_region[rows], low)
    np.maximum.at(box_max, row_region[rows], high)
    return box_min, box_max


def _face_boxes(meshes: Sequence, mesh: np.ndarray, face: np.ndarray, time: np.ndarray):
    """(low, high) float64[C, 3]: the box of each row's face (all its triangles' vertices) at its time, with
    points linear between samples and held outside them."""
    low = np.empty((mesh.size, 3))
    high = np.empty((mesh.size, 3))
    for index in distinct_sorted(mesh).tolist():          # one pass per mesh, vectorised over its rows
        rows = np.flatnonzero(mesh == index)
        data = meshes[index]
        first_triangle, triangle_count = _face_triangles(data)
        faces = face[rows]
        counts = triangle_count[faces]
        row_of = np.repeat(np.arange(rows.size), counts)
        starts = np.repeat(first_triangle[faces], counts)
        within = np.arange(row_of.size) - np.repeat(np.cumsum(counts) - counts, counts)
        order = np.argsort(data.triangle_face, kind="stable")
        triangles = order[starts + within]
        vertices = data.triangles[triangles].reshape(-1)        # three per triangle
        owner = np.repeat(row_of, 3)
        points = vertex_points_at(data, vertices, time[rows][owner])
        box_low = np.full((rows.size, 3), np.inf)
        box_high = np.full((rows.size, 3), -np.inf)
        np.minimum.at(box_low, owner, points)
        np.maximum.at(box_high, owner, points)
        low[rows], high[rows] = box_low, box_high
    return low, high


def _face_triangles(data) -> Tuple[np.ndarray, np.ndarray]:
    """(first index into the face-sorted triangle order, triangle count) per authored face."""
    counts = np.bincount(data.triangle_face, minlength=int(data.face_count)).astype(np.int64)
    return np.cumsum(counts) - counts, counts


def concatenate_regions(pieces: Sequence[RegionTable], table: ContactTable, kept: np.ndarray) -> RegionTable:
    """The regions of a shot checked in constant-topology pieces as one table over ``table``, the pieces'
    contacts joined (``kept``: the position of each of its rows among the pieces' rows stacked, from
    :meth:`ContactTable.concatenate_rows`). A region lies in one piece; one whose rows were all found
    again in an earlier piece is dropped, and regions are numbered again by their first row."""
    if len(pieces) == 1:
        return pieces[0]
    offsets = np.cumsum([0] + [piece.count for piece in pieces])
    stacked = np.concatenate([piece.row_region.astype(np.int64) + offset
                              for piece, offset in zip(pieces, offsets[:-1])])
    row_region = stacked[np.asarray(kept, np.int64)]
    total = int(offsets[-1])
    first_row = np.full(total, table.count, np.int64)
    np.minimum.at(first_row, row_region, np.arange(table.count))
    alive = np.flatnonzero(first_row < table.count)
    alive = alive[np.argsort(first_row[alive], kind="stable")]      # by first row: the region ids' order
    number = np.full(total, -1, np.int64)
    number[alive] = np.arange(alive.size)
    row_region = number[row_region].astype(np.int32)

    def column(name):
        return np.concatenate([getattr(piece, name) for piece in pieces])[alive]

    first_time = table.time[first_row[alive]]
    samples = _concatenate_samples([piece.samples for piece in pieces], offsets, number)
    return RegionTable(paths=table.paths and list(table.paths), mesh_a=column("mesh_a"), mesh_b=column("mesh_b"),
                       first_time=first_time, last_time=np.maximum(column("last_time"), first_time),
                       face_pairs=np.bincount(row_region, minlength=alive.size).astype(np.int64),
                       depth_measure=column("depth_measure"), max_depth=column("max_depth"),
                       max_depth_time=column("max_depth_time"),
                       max_intersection_length=column("max_intersection_length"), center=column("center"),
                       box_min=column("box_min"), box_max=column("box_max"), row_region=row_region, samples=samples)


def _concatenate_samples(pieces: Sequence[Optional[DepthSamples]], offsets: np.ndarray,
                         number: np.ndarray) -> Optional[DepthSamples]:
    """The pieces' depth samples over the renumbered regions (rows of dropped regions left out)."""
    if any(piece is None for piece in pieces):
        return None
    region = number[np.concatenate([piece.region.astype(np.int64) + offset
                                    for piece, offset in zip(pieces, offsets[:-1])])]
    keep = region >= 0
    order = np.lexsort((np.concatenate([piece.time for piece in pieces])[keep], region[keep]))

    def column(name):
        return np.concatenate([getattr(piece, name) for piece in pieces])[keep][order]

    return DepthSamples(region=region[keep][order].astype(np.int32), time=column("time"),
                        penetration=column("penetration"), intersection_length=column("intersection_length"),
                        box_min=column("box_min"), box_max=column("box_max"))
