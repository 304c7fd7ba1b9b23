"""``np.unique`` and ``np.median`` of plain arrays, without importing numpy's masked arrays.

Since numpy 2.3 a plain ``np.unique`` asks ``np.ma.is_masked`` and ``np.median`` asks
``np.ma.isMaskedArray``, and the first such question imports the ``numpy.ma`` package (about 15 ms,
once per process): a noticeable part of a short ``usdksl check``, which never uses masked arrays. The
functions here compute what numpy computes, by numpy's own method, and give the same array bit for bit:

* :func:`distinct_sorted` sorts and keeps each value that differs from the one before it (0.0 and -0.0
  collapse to the one sorted first, NaNs to one NaN), as ``np.unique``'s sorting method does; for integers
  ``np.unique`` hashes instead, which gives the same values.
* :func:`median` takes the middle order statistic, or the mean of the two middle ones, and is NaN where
  the data hold a NaN, as ``np.median`` does.
"""

from __future__ import annotations

from typing import Optional

import numpy as np


def distinct_sorted(values) -> np.ndarray:
    """``np.unique(values)`` for a plain (not masked) numeric array of any shape (flattened)."""
    ordered = np.sort(np.asarray(values).reshape(-1))
    keep = np.empty(ordered.shape, dtype=bool)
    keep[:1] = True
    if ordered.size and ordered.dtype.kind in "cfmM" and np.isnan(ordered[-1]):
        # NaNs sort last; np.unique (equal_nan=True) keeps the first of them
        if ordered.dtype.kind == "c":
            first_nan = int(np.searchsorted(np.isnan(ordered), True, side="left"))
        else:
            first_nan = int(np.searchsorted(ordered, ordered[-1], side="left"))
        if first_nan > 0:
            keep[1:first_nan] = ordered[1:first_nan] != ordered[:first_nan - 1]
        keep[first_nan] = True
        keep[first_nan + 1:] = False
    else:
        keep[1:] = ordered[1:] != ordered[:-1]
    return ordered[keep]


def median(values: np.ndarray, axis: Optional[int] = None, keepdims: bool = False):
    """``np.median(values, axis=axis, keepdims=keepdims)`` for a plain, non-empty float array: a float
    when ``axis`` is None and not ``keepdims``, else an array."""
    values = np.asarray(values)
    if axis is None:
        result = median(values.reshape(-1), axis=0)
        return np.reshape(result, (1,) * values.ndim) if keepdims else result
    size = values.shape[axis]
    half = size // 2
    middle = [half - 1, half] if size % 2 == 0 else [half]
    part = np.partition(values, middle + [-1], axis=axis)   # the last one: a NaN, when there is one
    result = np.mean(np.take(part, middle, axis=axis), axis=axis, keepdims=True)
    last = np.take(part, [-1], axis=axis)
    has_nan = np.isnan(last)
    if has_nan.any():
        result = np.where(has_nan, last, result)
    if not keepdims:
        result = np.squeeze(result, axis=axis)
    return result[()] if result.ndim == 0 else result


__all__ = ["distinct_sorted", "median"]
