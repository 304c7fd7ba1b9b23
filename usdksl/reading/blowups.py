"""Simulation blow-ups: vertices that jump far beyond their mesh's size between two samples.

Cloth solvers blow up: a vertex shoots off for a frame or two and comes back. The check goes on
(the contacts such a vertex causes are real contacts on the cache and are reported like any other;
the core's tolerances are local, so the rest of the shot costs and answers the same), but the
user is told where the cache is broken.

Detection, per deforming mesh and per pair of consecutive samples (the longest step of every pair in one
native pass, usdksl._native.longest_steps; numpy over the vertices of the few pairs it cannot rule out, in
blocks of steps, Python only over the blocks):

* the mesh's common motion over the step is the per-axis median of its vertices' displacements
  (a rigidly translating mesh has no excess anywhere);
* a vertex's excess is the length of its displacement minus that common motion;
* the mesh's size is the median, over its samples, of the diagonal of its bounding box (a
  blown-up sample cannot inflate it);
* a vertex blows up on that step when its excess exceeds :data:`BLOWUP_SIZE_FACTOR` times the
  mesh's size. Any rigid motion moves a vertex by at most twice the size relative to the median
  (a half turn), so rigid or ordinary deformation never reaches the threshold.

Caches also glitch as a whole: the cloth (or a sleeve and the torso, more than half of it) sits far
away at one sample and is back at the next. The median follows the larger part, so the test above
sees nothing when the whole mesh jumps, and names the vertices that stayed when most of it does.
Detection, per moving mesh (deforming, and rigid: a transform cache glitches as a point cache does,
and a rigid body's contacts with the cloth are checked) and per window of 1 to
:data:`GLITCH_MAX_SAMPLES` consecutive interior samples (numpy over vertices, Python over windows):

* a vertex's deviation at a sample of the window is its position there minus its position on the
  straight line, in time, between its positions at the samples just before and just after the window;
* the mesh's common deviation at that sample is the per-axis median of its vertices' deviations;
* the window holds a glitch when the common deviation is longer than :data:`GLITCH_SIZE_FACTOR`
  times the mesh's size at every sample of the window. Two windows meet when one, or a sample just
  around it, holds a sample of the other. A jump also bends the lines of the windows next to it, which
  end at it, and of the windows inside it, which end at a still sample; these see a fraction of it,
  while the window that holds exactly the jump sees all of it: a window is left out when one that
  meets it sees more than :data:`GLITCH_DOMINANCE` times as much. Two jumps a few samples apart leave
  the samples between them just as far off the line between the jumps, so of the windows left the
  shorter ones are taken first, then the ones that see more, and a window that meets one already
  taken is dropped. Bounds from the samples' bounding boxes, for the whole mesh and then per window
  (:data:`GLITCH_ROUNDING`), leave out what cannot hold a glitch before any median is taken;
* the vertices farther than the threshold from their own line at some sample of the window are the
  part that jumped (the whole mesh, or most of it); on the steps into and out of the window only
  they can blow up: the others are where their own motion takes them, and their excess only says
  that the median went with the glitch.

The first and last samples have one neighbour each, so no window holds them. A jump there is measured
against the line through the two samples beside it, extended, and competes with the windows it bends
(so that sample 1 is not named for a jump at sample 0), but it is not named: a cache may start or end
with the mesh elsewhere (a rest pose before it is snapped onto the character), and extended lines
give honest motion twice the room. The blow-up test there is as before (when most of a mesh jumps at
an end sample, the vertices that stay may be named as blowing up). A jump held for more than
GLITCH_MAX_SAMPLES samples is a move and a move back, each seen (when at all) as a glitch of the
samples at its ends. Glitches only warn (docs/contracts.md, "Contacts"): the contacts in and around
the window are real contacts on the cache and are reported like any others.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from functools import lru_cache
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

from .. import _native
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

#: A window of samples whose common deviation (scene units, module docstring) from the line between the
#: samples around it exceeds this many times the mesh's size at each of its samples is a glitch. Honest
#: motion leaves that line only by what its velocity changes inside the window. For one sample the
#: deviation of a point is (1 - w) * step_before - w * step_after (w in [0, 1] places the sample
#: between its neighbours): at most the longer step, and that only when the motion reverses exactly
#: at the sample; for a longer window the deviation at its first sample is at most its step in plus
#: its share of the span, so at most twice the longest step (samples evenly spaced). Turning and
#: deforming add at most twice the size (a half turn per step). So a body at any steady speed, a
#: thrown body (gravity bends its path by g * dt^2 / 2, 9 mm per frame at 24 fps) or a running
#: character (a fraction of its height per frame) stays far below; a ball moving 3x its size per frame
#: that bounces back at a sample while spinning a half turn per frame reaches at most 3 + 2 = 5x on
#: one sample and 2 * 3 + 2 = 8x on a window. Only a body turning sharply at more than 4x its size
#: per frame could be named.
GLITCH_SIZE_FACTOR = 10.0

#: Longest window (consecutive time samples) tested as one glitch: a bad frame written as several
#: subframes, or two bad frames. Windows longer than one sample halve the margin of honest motion once
#: (GLITCH_SIZE_FACTOR), whatever their length; each more sample adds a pass over the bounding boxes.
GLITCH_MAX_SAMPLES = 4

#: Each axis of a sample's common deviation lies within its vertices' deviations on that axis, which lie
#: within what the bounding boxes of the sample and of the window's ends allow: a window whose bound
#: stays within the threshold at one of its samples holds no glitch, and its medians (the costly part)
#: are not computed. The bound is computed from other roundings than the deviations: this fraction of
#: the mesh's largest coordinate (a few roundings of it) is added to it.
GLITCH_ROUNDING = 1e-12

#: A glitched window is left out when a window that meets it (module docstring) sees more than this many
#: times its shortest common deviation: beside a jump, or inside a jump held for several samples, a window
#: sees at most half of it (samples evenly spaced), while the window holding exactly the jump sees all of
#: it; the margin keeps that apart through what honest motion adds to both.
GLITCH_DOMINANCE = 1.5

#: At most this many glitches are named per mesh; the rest are counted.
GLITCHES_NAMED_PER_MESH = 5

#: Mesh kinds (usdksl.reading.meshes) that move, hence can glitch; a static mesh has one sample.
MOVING_KINDS = ("rigid", "deforming")


@dataclass(frozen=True)
class Blowup:
    """One vertex that jumps between two consecutive samples (time codes) of its mesh."""

    prim: str
    vertex: int
    time_before: float
    time_after: float
    excess: float       # scene units moved beyond the mesh's common motion
    mesh_size: float    # median bounding-box diagonal of the mesh, scene units


@dataclass(frozen=True)
class Glitch:
    """Consecutive samples (time codes ``time`` to ``time_last``) at which a mesh, or the larger part of
    it, lies far off the straight line between its positions at the samples around them: it jumps away
    and comes back."""

    prim: str
    time: float         # first sample away, time code
    time_last: float    # last sample away (== time for a one-sample glitch)
    time_before: float  # the samples around them, time codes
    time_after: float
    distance: float     # longest common deviation from the line, scene units
    mesh_size: float    # median bounding-box diagonal of the mesh, scene units
    #: bool[N]: the vertices farther than the threshold from their own line (the part that jumped)
    jumped: np.ndarray = field(compare=False, repr=False)

    @property
    def whole_mesh(self) -> bool:
        return bool(self.jumped.all())

    def what(self) -> str:
        """'the whole mesh' or 'part of the mesh (n of N vertices)'."""
        if self.whole_mesh:
            return "the whole mesh"
        return f"part of the mesh ({int(self.jumped.sum())} of {self.jumped.size} vertices)"

    def describe(self) -> str:
        """What happened, without file or prim: the samples, the distance and its ratio to the size."""
        when = (f"at time {self.time:g}" if self.time_last == self.time
                else f"at times {self.time:g} to {self.time_last:g}")
        return (f"{self.what()} jumps away and back between time {self.time_before:g} and {self.time_after:g} "
                f"({when}): it lies {self.distance:.3g} units off its motion, "
                f"{self.distance / self.mesh_size:.3g}x the mesh's size ({self.mesh_size:.3g})")


def sample_boxes(points: np.ndarray, threads: int = 1) -> Tuple[np.ndarray, np.ndarray]:
    """(lowest, highest): float64[K, 3] bounding box of each sample of float[K, N, 3] points (scene units), on up
    to ``threads`` threads."""
    lowest, highest = _native.sample_boxes(points, threads)   # one pass, no copy; minimum and maximum are exact
    return lowest, highest


def mesh_size(points: np.ndarray, boxes: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> float:
    """Median over samples of the bounding-box diagonal of float[K, N, 3] points (scene units);
    ``boxes``: their :func:`sample_boxes` when already known."""
    lowest, highest = sample_boxes(points) if boxes is None else boxes
    return float(median(np.linalg.norm(highest - lowest, axis=1)))


def find_blowups(prim: str, times: np.ndarray, points: np.ndarray, glitches: Sequence[Glitch] = (),
                 size: Optional[float] = None, threads: int = 1) -> List[Blowup]:
    """Every (vertex, step) of one mesh whose excess motion exceeds the threshold, in time order.

    ``glitches``: the mesh's glitches (:func:`find_glitches`); on the steps into and out of each, vertices
    outside the part that jumped are not blow-ups. ``size``: the mesh's size when already known. ``threads``:
    how many the first pass over every step may use."""
    if points.shape[0] < 2 or points.shape[1] == 0:
        return []
    size = mesh_size(points) if size is None else size
    threshold = BLOWUP_SIZE_FACTOR * size
    found: List[Blowup] = []
    # one native pass over every step (no float64 copy of the samples); only the suspects are measured
    largest = _native.longest_steps(points, threads)
    suspects = np.nonzero(~(EXCESS_BOUND_FACTOR * largest <= threshold))[0]  # NaN stays suspect
    steps_per_block = max(1, BLOWUP_BLOCK_VALUES // (3 * points.shape[1]))
    for first in range(0, suspects.size, steps_per_block):
        suspect = suspects[first:first + steps_per_block]
        # float32 points: the same doubles
        steps = points[suspect + 1].astype(np.float64) - points[suspect].astype(np.float64)
        excess = np.linalg.norm(steps - median(steps, axis=1, keepdims=True), axis=2)
        for row, vertex in zip(*np.nonzero(excess > threshold)):
            k = suspect[row]
            found.append(Blowup(prim=prim, vertex=int(vertex), time_before=float(times[k]),
                                time_after=float(times[k + 1]), excess=float(excess[row, vertex]),
                                mesh_size=size))
    if glitches and found:
        part_on_step = {}   # (time before, time after) of a step into or out of a glitch: the part that jumped
        for glitch in glitches:
            part_on_step[(glitch.time_before, glitch.time)] = glitch.jumped
            part_on_step[(glitch.time_last, glitch.time_after)] = glitch.jumped
        found = [blowup for blowup in found
                 if part_on_step.get((blowup.time_before, blowup.time_after)) is None
                 or part_on_step[(blowup.time_before, blowup.time_after)][blowup.vertex]]
    return found


def _deviation(points: np.ndarray, times: np.ndarray, first: int, last: int, start: int, end: int) -> np.ndarray:
    """float[last - first + 1, N, 3]: each vertex at samples first..last minus its position on the line, in
    time, through its positions at samples ``start`` and ``end`` (scene units)."""
    weights = (times[first:last + 1] - times[start]) / (times[end] - times[start])
    at_start, at_end = (points[k].astype(np.float64, copy=False) for k in (start, end))
    deviation = (at_end - at_start)[None] * -weights[:, None, None]
    deviation += points[first:last + 1]
    deviation -= at_start
    return deviation


def _common_deviation(points: np.ndarray, times: np.ndarray, first: int, last: int, start: int,
                      end: int) -> np.ndarray:
    """float[last - first + 1]: length of the common deviation (per-axis median over the vertices) of each
    sample first..last from the line through samples ``start`` and ``end`` (scene units)."""
    return np.linalg.norm(median(_deviation(points, times, first, last, start, end), axis=1), axis=1)


@lru_cache(maxsize=16)
def _windows(count: int) -> Tuple[np.ndarray, np.ndarray, np.ndarray, np.ndarray]:
    """(first, last, sample, row_start) of every window of 1 to GLITCH_MAX_SAMPLES interior samples of a mesh
    with ``count`` samples: int[W] first and last samples of each window, int[R] each window's samples one
    after the other, int[W] where each window's rows start. Meshes of a shot share their sample count (the
    instances of an instancer), so the arrays are made once."""
    lengths = range(1, min(GLITCH_MAX_SAMPLES, count - 2) + 1)
    first = np.concatenate([np.arange(1, count - length) for length in lengths])
    length = np.concatenate([np.full(count - 1 - length, length) for length in lengths])
    row_start = np.concatenate([[0], np.cumsum(length)[:-1]])
    window_of_row = np.repeat(np.arange(first.size), length)
    sample = first[window_of_row] + np.arange(window_of_row.size) - row_start[window_of_row]
    arrays = (first, first + length - 1, sample, row_start)
    for array in arrays:
        array.flags.writeable = False
    return arrays


def _window_reach(times: np.ndarray, lowest: np.ndarray, highest: np.ndarray) -> Tuple[np.ndarray, np.ndarray,
                                                                                         np.ndarray]:
    """(first, last, reach): for each window of :func:`_windows`, the least over its samples of the bound on
    the common deviation that the bounding boxes of the sample and of the samples around the window allow
    (scene units)."""
    first, last, sample, row_start = _windows(times.size)
    lengths = np.diff(np.append(row_start, sample.size))
    before, after = np.repeat(first - 1, lengths), np.repeat(last + 1, lengths)
    weights = ((times[sample] - times[before]) / (times[after] - times[before]))[:, None]
    up = highest[sample] - ((1.0 - weights) * lowest[before] + weights * lowest[after])
    down = lowest[sample] - ((1.0 - weights) * highest[before] + weights * highest[after])
    # np.minimum keeps a nan (coordinates overflowing): such a window stays a suspect
    reach = np.minimum.reduceat(np.linalg.norm(np.maximum(np.abs(up), np.abs(down)), axis=1), row_start)
    return first, last, reach


def _take_windows(windows: Sequence[Tuple[float, int, int, float]]) -> List[Tuple[int, int, float]]:
    """(first, last, longest common deviation) of the windows taken (module docstring), in time order, out
    of the glitched windows (shortest common deviation, first, last, longest common deviation)."""
    by_first: Dict[int, list] = {}
    for window in windows:
        by_first.setdefault(window[1], []).append(window)

    def meeting(window):
        # a window meets another when it or the samples around it hold one of the other's samples
        _, first, last, _ = window
        for other_first in range(first - GLITCH_MAX_SAMPLES - 1, last + 2):
            for other in by_first.get(other_first, ()):
                if other is not window and other[2] + 1 >= first:
                    yield other

    kept = [window for window in windows
            if not any(other[0] > GLITCH_DOMINANCE * window[0] for other in meeting(window))]
    taken: List[Tuple[int, int, float]] = []
    for _, first, last, longest in sorted(kept, key=lambda w: (w[2] - w[1], -w[0], w[1])):
        if all(last + 1 < other_first or other_last + 1 < first for other_first, other_last, _ in taken):
            taken.append((first, last, longest))
    return sorted(taken)


def find_glitches(prim: str, times: np.ndarray, points: np.ndarray, size: Optional[float] = None,
                  boxes: Optional[Tuple[np.ndarray, np.ndarray]] = None) -> List[Glitch]:
    """Every window of interior samples at which one mesh, or most of it, jumps away from the straight
    line between the samples around it (module docstring), in time order. ``times``: time codes;
    ``points``: float[K, N, 3] scene units; ``size`` and ``boxes`` (:func:`sample_boxes`) when known."""
    count, vertices = points.shape[0], points.shape[1]
    if count < 3 or vertices == 0:
        return []
    times = np.asarray(times, dtype=np.float64)
    lowest, highest = sample_boxes(points) if boxes is None else boxes
    size = mesh_size(points, (lowest, highest)) if size is None else size
    threshold = GLITCH_SIZE_FACTOR * size
    windows = []   # (shortest common deviation, first, last, longest common deviation)
    # coordinates near the float range overflow to inf and nan here; such windows are not glitches
    with np.errstate(over="ignore", invalid="ignore"):
        slack = GLITCH_ROUNDING * max(float(np.abs(lowest).max()), float(np.abs(highest).max()))
        # any window's bound is at most the largest extent plus as many of the largest steps of a box side
        # as the window has samples: a mesh within the threshold so holds no glitch, at no per-window cost
        # (which counts for the many instances of an instancer)
        side_step = np.maximum(np.abs(np.diff(lowest, axis=0)).max(axis=0),
                               np.abs(np.diff(highest, axis=0)).max(axis=0))
        reach_all = np.linalg.norm((highest - lowest).max(axis=0) + GLITCH_MAX_SAMPLES * side_step)
        if reach_all + slack <= threshold:
            return []
        firsts, lasts, reach = _window_reach(times, lowest, highest)
        suspect = ~(reach + slack <= threshold)   # nan stays suspect
        for first, last in zip(firsts[suspect].tolist(), lasts[suspect].tolist()):
            common = _common_deviation(points, times, first, last, first - 1, last + 1)
            shortest = float(common.min())
            if shortest > threshold:
                windows.append((shortest, first, last, float(common.max())))
        # the first and last samples, off the line through the two samples beside them, compete with the
        # windows their jump bends (which start at sample 1 or end at sample K - 2) but are not named
        ends = [(0, 1, 2)] if any(window[1] == 1 for window in windows) else []
        ends += [(count - 1, count - 3, count - 2)] if any(window[2] == count - 2 for window in windows) else []
        for sample, start, end in ends:
            common = float(_common_deviation(points, times, sample, sample, start, end)[0])
            if common > threshold:
                windows.append((common, sample, sample, common))
    found: List[Glitch] = []
    for first, last, longest in _take_windows(windows):
        if first == 0 or last == count - 1:
            continue
        with np.errstate(over="ignore", invalid="ignore"):
            deviation = _deviation(points, times, first, last, first - 1, last + 1)
            jumped = (np.sqrt(np.einsum("kni,kni->kn", deviation, deviation)) > threshold).any(axis=0)
        found.append(Glitch(prim=prim, time=float(times[first]), time_last=float(times[last]),
                            time_before=float(times[first - 1]), time_after=float(times[last + 1]),
                            distance=longest, mesh_size=size, jumped=jumped))
    return found


def mesh_faults(mesh, threads: int = 1) -> Tuple[List[Blowup], List[Glitch]]:
    """(blow-ups, glitches) of one mesh (MeshData with path, kind, times, points): glitches of a moving
    mesh, blow-ups of a deforming one. ``threads``: how many the passes over every sample may use."""
    kind = getattr(mesh, "kind", "deforming")
    if kind not in MOVING_KINDS or mesh.points.shape[0] < 2 or mesh.points.shape[1] == 0:
        return [], []
    boxes = sample_boxes(mesh.points, threads)
    size = mesh_size(mesh.points, boxes)
    glitches = find_glitches(mesh.path, mesh.times, mesh.points, size, boxes)
    if kind != "deforming":
        return [], glitches
    return find_blowups(mesh.path, mesh.times, mesh.points, glitches, size, threads), glitches


def shot_faults(meshes: Sequence, threads: int = 1) -> Tuple[List[Blowup], List[Glitch]]:
    """(blow-ups, glitches) of every mesh of a loaded shot (:func:`mesh_faults`), mesh by mesh, each pass over
    a mesh's samples on up to ``threads`` threads."""
    blowups: List[Blowup] = []
    glitches: List[Glitch] = []
    for mesh in meshes:
        mesh_blowups, mesh_glitches = mesh_faults(mesh, threads)
        blowups.extend(mesh_blowups)
        glitches.extend(mesh_glitches)
    return blowups, glitches


def shot_blowups(meshes: Sequence) -> List[Blowup]:
    """Blow-ups of every deforming mesh of a loaded shot (MeshData with path, kind, times, points)."""
    return shot_faults([mesh for mesh in meshes if getattr(mesh, "kind", "deforming") == "deforming"])[0]


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


def describe_glitches(glitches: Sequence[Glitch], file: str) -> List[str]:
    """One warning line per glitch, at most GLITCHES_NAMED_PER_MESH per mesh plus one line counting the rest."""
    lines: List[str] = []
    named_per_prim: Dict[str, int] = {}
    hidden_per_prim: Dict[str, int] = {}
    for glitch in glitches:
        if named_per_prim.get(glitch.prim, 0) >= GLITCHES_NAMED_PER_MESH:
            hidden_per_prim[glitch.prim] = hidden_per_prim.get(glitch.prim, 0) + 1
            continue
        named_per_prim[glitch.prim] = named_per_prim.get(glitch.prim, 0) + 1
        lines.append(f"{file}: {glitch.prim}: cache glitch: {glitch.describe()}; "
                     f"contacts it causes are still reported")
    for prim, hidden in hidden_per_prim.items():
        lines.append(f"{file}: {prim}: {hidden} more cache glitches (first {GLITCHES_NAMED_PER_MESH} named)")
    return lines
