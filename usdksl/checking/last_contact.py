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

from ..contacts.table import ContactTable, match_face_pairs
from .collision import find_contacts

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
                  threads: Optional[int] = None) -> LastContacts:
    """The last contact of every face pair of ``table`` (the first contacts of ``meshes`` over
    ``time_range`` with the same settings, ``threads`` as for them). ``progress`` receives reversed
    times (``-t``)."""
    start, end = checked_range(meshes, time_range)
    backwards = [reversed_mesh(mesh) for mesh in meshes]
    result = find_contacts(backwards, pairs, method=method, time_range=(-end, -start), tolerance=tolerance,
                           thickness=thickness, progress=progress, threads=threads)
    reversed_table = result.face_contacts(backwards)
    latest = replace(reversed_table, time=-reversed_table.time)
    found, only_in_reverse = match_face_pairs(table, latest)
    last = np.where(found >= 0, latest.time[np.maximum(found, 0)] if latest.count else table.time, table.time)
    return LastContacts(last_time=np.maximum(last, table.time), missing_in_reverse=int(np.count_nonzero(found < 0)),
                        only_in_reverse=int(np.count_nonzero(only_in_reverse)))


__all__ = ["LastContacts", "checked_range", "last_contacts", "reversed_mesh"]
