"""Last contacts: the first contacts of the shot played backwards (docs/contracts.md, Last contacts).

The core finds the first moment two faces come within the thickness. Played backwards — every time
sample ``t`` moved to ``-t``, the samples in reverse order, the checked range ``[a, b]`` becoming
``[-b, -a]`` — the trajectories are the same lines, so the core's first contact at ``t'`` in reversed
time is the last moment ``-t'`` the faces are within the thickness: the end of their last contact
(the end of the range when they still touch there). Negating a double is exact, so nothing is
resampled.

The reversed run costs as much as the forward one (it is a whole second check), which is why it only
runs when asked (``CheckOptions.last_contact``, ``--last-contact``, ``--plot``). The forward run's
tolerance carries over mirrored: a last contact is late by at most the tolerance of its sample
interval, never early.
"""

from __future__ import annotations

from dataclasses import dataclass, replace
from typing import Callable, Optional, Sequence, Tuple

import numpy as np

from ..contacts.table import ContactTable, latest_per_face_pair, match_face_pairs
from .collision import find_contacts, found_pairs
from .memory_windows import plan_memory_windows, window_of

TimeRange = Tuple[float, float]


def reversed_mesh(mesh):
    """``mesh`` (usdksl.reading.loader.MeshData) played backwards: times ``-t`` ascending, points in the
    matching order (a C-contiguous copy)."""
    return replace(mesh, times=np.ascontiguousarray(-mesh.times[::-1]),
                   points=np.ascontiguousarray(mesh.points[::-1]))


def checked_range(meshes: Sequence, time_range: Optional[TimeRange]) -> TimeRange:
    """The range find_contacts checks: ``time_range``, or the union of the meshes' samples."""
    if time_range is not None:
        return (float(time_range[0]), float(time_range[1]))
    if not meshes:
        return (0.0, 0.0)
    return (min(float(mesh.times[0]) for mesh in meshes), max(float(mesh.times[-1]) for mesh in meshes))


@dataclass
class LastContacts:
    """Last contact per row of a first-contact table, and how the two runs disagree on face pairs."""

    last_time: np.ndarray   # float64[C], time codes, >= the row's first contact
    #: Face pairs the forward run found and the reversed run did not (their last time is their first).
    missing_in_reverse: int = 0
    #: Face pairs only the reversed run found (a contact the forward run missed; never expected).
    only_in_reverse: int = 0


def last_contacts(meshes: Sequence, pairs: np.ndarray, table: ContactTable, time_range: Optional[TimeRange],
                  method: str, tolerance: float, thickness: float,
                  progress: Optional[Callable[[float, int], None]] = None,
                  threads: Optional[int] = None, steps_per_window: Optional[int] = None,
                  frames_per_time_code: float = 0.0) -> LastContacts:
    """The last contact of every face pair of ``table`` (the first contacts of ``meshes`` over
    ``time_range`` with the same settings, ``threads``, ``steps_per_window`` and ``frames_per_time_code``
    as for them; played backwards, -t is a whole frame where t is).
    ``progress`` receives reversed times (``-t``). With memory windows (usdksl.checking.memory_windows)
    each window is played backwards on its own, the last first, and a face pair's last contact is the
    latest of its windows' (the mirror image of the earliest first contact)."""
    start, end = checked_range(meshes, time_range)
    windows = plan_memory_windows(meshes, np.asarray(pairs).reshape(-1, 2).tolist(), (start, end),
                                  steps_per_window)
    pieces = []
    results = []
    found_before = 0
    for window in reversed(windows):
        backwards = [reversed_mesh(window_of(mesh, window)) for mesh in meshes]
        report = None if progress is None else (
            lambda reached, count, before=found_before: progress(reached, before + count))
        # pairs a later window (earlier in reversed time) found have their last contact there
        result = find_contacts(backwards, pairs, method=method, time_range=(-window[1], -window[0]),
                               tolerance=tolerance, thickness=thickness, progress=report, threads=threads,
                               settled=found_pairs(results), frames_per_time_code=frames_per_time_code)
        results.append(result)
        pieces.append(result.face_contacts(backwards))
        found_before += len(result)
    if len(pieces) == 1:
        latest = replace(pieces[0], time=-pieces[0].time)
    else:
        latest = latest_per_face_pair(pieces[0].paths, *(np.concatenate([column(piece) for piece in pieces])
                                                     for column in (lambda p: -p.time, lambda p: p.mesh_a,
                                                                    lambda p: p.face_a, lambda p: p.mesh_b,
                                                                    lambda p: p.face_b)))
    found, only_in_reverse = match_face_pairs(table, latest)
    last = np.where(found >= 0, latest.time[np.maximum(found, 0)] if latest.count else table.time, table.time)
    return LastContacts(last_time=np.maximum(last, table.time), missing_in_reverse=int(np.count_nonzero(found < 0)),
                        only_in_reverse=int(np.count_nonzero(only_in_reverse)))


__all__ = ["LastContacts", "checked_range", "last_contacts", "reversed_mesh"]
