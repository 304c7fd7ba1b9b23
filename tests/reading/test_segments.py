"""Splitting the checked range at topology changes."""

from usdksl.errors import UsdkslInputError
from usdksl.reading.segments import is_topology_change, split_range


def test_split_range_drops_the_open_gaps():
    gaps = [(6.0, 12.0, "/A"), (15.0, 18.0, "/B")]
    assert split_range((1.0, 24.0), gaps) == [(1.0, 6.0), (12.0, 15.0), (18.0, 24.0)]


def test_split_range_with_overlapping_gaps_and_a_narrow_time_range():
    gaps = [(6.0, 12.0, "/A"), (8.0, 14.0, "/B"), (30.0, 40.0, "/C")]
    assert split_range((1.0, 24.0), gaps) == [(1.0, 6.0), (14.0, 24.0)]
    assert split_range((7.0, 20.0), gaps) == [(14.0, 20.0)]
    assert split_range((2.0, 5.0), gaps) == [(2.0, 5.0)]
    assert split_range((7.0, 9.0), gaps) == []


def test_topology_errors_are_recognised():
    assert is_topology_change(UsdkslInputError("topology (faceVertexCounts) changes here", file="f"))
    assert is_topology_change(UsdkslInputError("points count changes from 4 (time 1) to 5", file="f"))
    assert not is_topology_change(UsdkslInputError("point 3 is NaN or infinite", file="f"))
