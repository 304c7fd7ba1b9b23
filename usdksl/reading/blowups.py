"""Simulation blow-ups: vertices that jump far beyond their mesh's size between two samples.

Cloth solvers blow up: a vertex shoots off for a frame or two and comes back. The check goes on
(the contacts such a vertex causes are real contacts on the cache and are reported like any other;
the core's tolerances are local, so the rest of the shot costs and answers the same), but the
user is told where the cache is broken.

Detection, per deforming mesh and per pair of consecutive samples (numpy over vertices and over
blocks of steps, Python only over the blocks):

* the mesh's common motion over the step is the per-axis median of its vertices' displacements
  (a rigidly translating mesh has no excess anywhere);
* a vertex's excess is the length of its displacement minus that common motion;
* the mesh's size is the median, over its samples, of the diagonal of its bounding box (a
  blown-up sample cannot inflate it);
* a vertex blows up on that step when its excess exceeds :data:`BLOWUP_SIZE_FACTOR` times the
  mesh's size. Any rigid motion moves a vertex by at most twice the size relative to the median
  (a half turn), so rigid or ordinary deformation never reaches the threshold.
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import List, Sequence

import numpy as np

from ..unmasked import median

#: A vertex whose motion between two samples, beyond its mesh's common motion, exceeds this many
#: times the mesh's size (median bounding-box diagonal) is reported as a blow-up.
BLOWUP_SIZE_FACTOR = 10.0

#: Displacement values (steps x vertices x 3) examined at once: bounds the temporary arrays of a mesh
#: with many samples (32 MB of float64) while keeping per-step numpy calls out of the Python loop.
BLOWUP_BLOCK_VALUES = 1 << 22

#: A vertex's excess is at most its displacement plus the length of the common motion, and each axis of
#: that per-axis median lies within the vertices' displacements on that axis, so its length is at most
#: sqrt(3) times the largest displacement: a step whose largest displacement times this factor stays
#: within the threshold has no blow-up, and its median (the costly part) is not computed. The last
#: factor covers the rounding of the computed lengths.
EXCESS_BOUND_FACTOR = (1.0 + float(np.sqrt(3.0))) * (1.0 + 1e-9)

#: At most this many blown-up vertices are named per mesh; the rest are counted.
BLOWUP_VERTICES_NAMED_PER_MESH = 5


@dataclass(frozen=True)
class Blowup:
    """One vertex that jumps between two consecutive samples (time codes) of its mesh."""

    prim: str
    vertex: int
    time_before: float
    time_after: float
    excess: float       # scene units moved beyond the mesh's common motion
    mesh_size: float    # median bounding-box diagonal of the mesh, scene units


def mesh_size(points: np.ndarray) -> float:
    """Median over samples of the bounding-box diagonal of float[K, N, 3] points (scene units)."""
    diagonals = np.empty(points.shape[0], dtype=np.float64)
    samples_per_block = max(1, BLOWUP_BLOCK_VALUES // max(1, 3 * points.shape[1]))
    for first in range(0, points.shape[0], samples_per_block):
        # [k, 3, N] copies: numpy reduces a contiguous row of N values many times faster than the
        # stride-3 column of [k, N, 3]; minimum and maximum are exact either way
        coordinates = np.ascontiguousarray(points[first:first + samples_per_block].transpose(0, 2, 1))
        extent = coordinates.max(axis=2) - coordinates.min(axis=2)
        diagonals[first:first + samples_per_block] = np.linalg.norm(extent, axis=1)
    return float(median(diagonals))


def find_blowups(prim: str, times: np.ndarray, points: np.ndarray) -> List[Blowup]:
    """Every (vertex, step) of one mesh whose excess motion exceeds the threshold, in time order."""
    if points.shape[0] < 2 or points.shape[1] == 0:
        return []
    size = mesh_size(points)
    threshold = BLOWUP_SIZE_FACTOR * size
    found: List[Blowup] = []
    steps_per_block = max(1, BLOWUP_BLOCK_VALUES // (3 * points.shape[1]))
    for first in range(0, points.shape[0] - 1, steps_per_block):
        last = min(first + steps_per_block, points.shape[0] - 1)
        steps = points[first + 1:last + 1] - points[first:last]
        largest = np.sqrt(np.einsum("kni,kni->kn", steps, steps).max(axis=1))
        suspect = np.nonzero(~(EXCESS_BOUND_FACTOR * largest <= threshold))[0]  # NaN stays suspect
        if suspect.size == 0:
            continue
        steps = steps[suspect]
        excess = np.linalg.norm(steps - median(steps, axis=1, keepdims=True), axis=2)
        for row, vertex in zip(*np.nonzero(excess > threshold)):
            k = suspect[row]
            found.append(Blowup(prim=prim, vertex=int(vertex), time_before=float(times[first + k]),
                                time_after=float(times[first + k + 1]), excess=float(excess[row, vertex]),
                                mesh_size=size))
    return found


def shot_blowups(meshes: Sequence) -> List[Blowup]:
    """Blow-ups of every deforming mesh of a loaded shot (MeshData with path, kind, times, points)."""
    found: List[Blowup] = []
    for mesh in meshes:
        if getattr(mesh, "kind", "deforming") == "deforming":
            found.extend(find_blowups(mesh.path, mesh.times, mesh.points))
    return found


def describe_blowups(blowups: Sequence[Blowup], file: str) -> List[str]:
    """One warning line per blown-up vertex (a vertex's consecutive steps joined), at most
    BLOWUP_VERTICES_NAMED_PER_MESH per mesh plus one line counting the rest."""
    lines: List[str] = []
    by_vertex = {}
    for blowup in blowups:
        by_vertex.setdefault((blowup.prim, blowup.vertex), []).append(blowup)
    named_per_prim = {}
    hidden_per_prim = {}
    for (prim, vertex), steps in by_vertex.items():
        if named_per_prim.get(prim, 0) >= BLOWUP_VERTICES_NAMED_PER_MESH:
            hidden_per_prim[prim] = hidden_per_prim.get(prim, 0) + 1
            continue
        named_per_prim[prim] = named_per_prim.get(prim, 0) + 1
        worst = max(steps, key=lambda s: s.excess)
        lines.append(
            f"{file}: {prim}: vertex {vertex} blows up between time {steps[0].time_before:g} and "
            f"{steps[-1].time_after:g}: it moves {worst.excess:.3g} units beyond the mesh's motion, "
            f"{worst.excess / worst.mesh_size:.3g}x the mesh's size ({worst.mesh_size:.3g}); "
            f"contacts it causes are reported like any others")
    for prim, hidden in hidden_per_prim.items():
        lines.append(f"{file}: {prim}: {hidden} more vertices blow up (first {BLOWUP_VERTICES_NAMED_PER_MESH} named)")
    return lines
