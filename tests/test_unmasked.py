"""distinct_sorted and median give np.unique's and np.median's answers, bit for bit, without importing
numpy.ma."""

import subprocess
import sys

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra import numpy as hnp

from usdksl.unmasked import distinct_sorted, median

SPECIAL_FLOATS = [0.0, -0.0, 1.0, -1.5, 2.25, np.inf, -np.inf, np.nan, 1e-300, 7.0, 0.1, 0.3]
FLOATS = hnp.arrays(np.float64, st.integers(0, 40), elements=st.sampled_from(SPECIAL_FLOATS))
INTEGERS = hnp.arrays(np.int32, st.integers(0, 40), elements=st.integers(-5, 5))
FLOAT_BLOCKS = hnp.arrays(np.float64, hnp.array_shapes(min_dims=1, max_dims=3, min_side=1, max_side=7),
                          elements=st.one_of(st.sampled_from(SPECIAL_FLOATS),
                                             st.floats(-1e6, 1e6, allow_nan=False)))


def _same_bits(a, b):
    a, b = np.asarray(a), np.asarray(b)
    return a.dtype == b.dtype and a.shape == b.shape and a.tobytes() == b.tobytes()


@settings(max_examples=300, deadline=None)
@given(FLOATS)
def test_distinct_floats_match_np_unique_bit_for_bit(values):
    assert _same_bits(distinct_sorted(values), np.unique(values))


@settings(max_examples=100, deadline=None)
@given(INTEGERS)
def test_distinct_integers_match_np_unique(values):
    assert _same_bits(distinct_sorted(values), np.unique(values))


def test_distinct_flattens_and_leaves_the_input_alone():
    values = np.array([[3.0, 1.0], [3.0, np.nan]])
    kept = values.copy()
    assert _same_bits(distinct_sorted(values), np.unique(values))
    assert np.array_equal(values, kept, equal_nan=True)
    assert distinct_sorted([2, 1, 2]).tolist() == [1, 2]


@settings(max_examples=400, deadline=None)
@given(FLOAT_BLOCKS, st.data())
def test_median_matches_np_median_bit_for_bit(values, data):
    axis = data.draw(st.sampled_from([None] + list(range(values.ndim))))
    keepdims = data.draw(st.booleans())
    kept = values.copy()
    ours, theirs = median(values, axis=axis, keepdims=keepdims), np.median(values, axis=axis, keepdims=keepdims)
    assert type(ours) is type(theirs)
    assert _same_bits(ours, theirs)
    assert np.array_equal(values, kept, equal_nan=True)


def test_median_of_an_even_count_is_the_mean_of_the_middle_two():
    assert median(np.array([4.0, 1.0, 3.0, 2.0])) == 2.5
    assert np.isnan(median(np.array([1.0, np.nan, 2.0])))


def test_neither_imports_numpy_ma():
    code = ("import sys, numpy as np; from usdksl.unmasked import distinct_sorted, median; "
            "distinct_sorted(np.array([2.0, 1.0, 2.0])); median(np.ones((3, 4, 3)), axis=1, keepdims=True); "
            "median(np.array([1.0, 2.0])); print('numpy.ma' in sys.modules)")
    completed = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert completed.stdout.strip() == "False"
