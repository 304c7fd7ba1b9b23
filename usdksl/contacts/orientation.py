"""The canonical orientation of a face pair: which of its two sides is side a (docs/contracts.md, Contacts).

A face pair names two sides, each a prim and a face. In canonical orientation an inter pair has the prim
that comes first in string order of the prim paths on side a, and a self pair (both sides on one prim)
has the lower face on side a. The contact table, the cross-check's face-pair keys and the baseline's
entries all orient pairs by :func:`canonical_swap`, so a face pair reads the same in every file.
"""

from __future__ import annotations

from typing import Tuple

import numpy as np


def canonical_swap(prim_a, face_a, prim_b, face_b) -> np.ndarray:
    """bool[C]: the rows whose two sides swap into canonical orientation: self rows (``prim_a == prim_b``)
    with ``face_a > face_b``, inter rows with ``prim_a > prim_b``.

    ``prim_a``, ``prim_b``: anything whose order is the string order of the prim paths, one per row: the
    paths themselves (object arrays) or their ranks (int arrays, usdksl.contacts.table.path_rank; ranks
    must differ between different prims). ``face_a``, ``face_b``: int arrays of authored face indices.
    """
    prim_a, prim_b = np.asarray(prim_a), np.asarray(prim_b)
    return np.asarray(np.where(prim_a == prim_b, np.asarray(face_a) > np.asarray(face_b), prim_a > prim_b),
                      dtype=bool)


def swap_sides(swap: np.ndarray, side_a, side_b) -> Tuple[np.ndarray, np.ndarray]:
    """(side_a, side_b) with the two exchanged in the rows where ``swap`` (bool[C]) is set."""
    return np.where(swap, side_b, side_a), np.where(swap, side_a, side_b)


__all__ = ["canonical_swap", "swap_sides"]
