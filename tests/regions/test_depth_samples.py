"""Which samples a region's depth is measured at (docs/contracts.md, Regions): whole frames of the stage's clock,
a sub-frame sample only where the frame before it is not sampled, and always a region's first and last samples;
regions are grouped at the same samples, so a region ends on one of them."""

import numpy as np
import pytest

from regions.scenes import box, contacts, sheet
from usdksl.clock import StageClock
from usdksl.regions.closed import closed_meshes
from usdksl.regions.depth import WHOLE_FRAME_TOLERANCE, depth_sample_flags, region_depths
from usdksl.regions.find import find_regions
from usdksl.regions.grouping import group_regions


def test_one_sample_per_frame_measures_every_sample():
    times = np.arange(1001.0, 1049.0)
    assert depth_sample_flags(times).all()


def test_ten_samples_per_frame_measure_only_the_whole_frames():
    # as benchmarks/densify.py writes them: t0 + (t1 - t0) * k / 10, so whole frames are exact and the rest are not
    times = (1001.0 + np.arange(0, 471) / 10.0)
    flags = depth_sample_flags(times)
    assert flags.tolist() == (np.arange(471) % 10 == 0).tolist()
    assert flags.sum() == 48


def test_a_shot_sampled_only_between_frames_keeps_every_sample():
    times = np.arange(1001.5, 1030.0, 1.0)
    assert depth_sample_flags(times).all()
    # the same, with one sub-frame sample more after each: only the frame before decides, and it is never sampled
    quarters = np.sort(np.concatenate([times, times + 0.25]))
    assert depth_sample_flags(quarters).all()


def test_a_sub_frame_sample_beside_its_frame_is_left_out_only_when_that_frame_is_sampled():
    times = np.array([10.0, 10.5, 11.5, 12.0, 12.5])
    # 10.5: frame 10 is a sample; 11.5: frame 11 is none; 12.5: frame 12 is a sample
    assert depth_sample_flags(times).tolist() == [True, False, True, True, False]


def test_whole_frames_within_the_tolerance_of_the_clock():
    # 48 time codes and 24 frames a second: frames are half the time codes, so odd time codes lie between frames
    clock = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)
    times = np.arange(2002.0, 2030.0)
    flags = depth_sample_flags(times, clock.frames_per_time_code)
    assert flags.tolist() == (times % 2 == 0).tolist()
    # a time code off an even one by the tolerance (half of it in frames) is still on a whole frame; one off by
    # twenty times it is not, and frame 1002 before it is a sample
    near = np.array([2002.0, 2004.0 + WHOLE_FRAME_TOLERANCE, 2004.0 + 20 * WHOLE_FRAME_TOLERANCE])
    assert depth_sample_flags(near, clock.frames_per_time_code).tolist() == [True, True, False]


def _box_through_a_sheet(times):
    """A static sheet at z = 0 and a box of half-size 0.5 rising through it at a quarter unit per time code; its
    top reaches the sheet at time 2.4 and its bottom leaves it at 6.4, both between whole time codes."""
    flat = sheet(10, 10, (-1.03, -0.98, 0.0), (2.0, 0, 0), (0, 2.0, 0))
    return [flat, box(0.5, lambda t: (0, 0, -1.1 + 0.25 * t), times)]


def test_a_contact_that_begins_between_frames_is_measured_from_its_first_sample_and_ends_on_a_frame():
    times = np.arange(0.0, 9.0, 0.25)          # four samples a frame (frames = time codes)
    meshes = _box_through_a_sheet(times)
    table = contacts(meshes, [(0, 1)])
    first = int(np.searchsorted(times, table.time.min()))        # first sample at or after the first contact
    assert times[first] == 2.5, "the region starts between frames"

    regions = find_regions(meshes, table, times)
    assert regions.count == 1
    # grouped on frames: the box's bottom face first touches the sheet as it leaves it at 6.4, a contact over
    # by frame 7, so the region ends at that contact's own time and its span covers the step to frame 7; its
    # first sample is the one after its first contact
    assert regions.last_time[0] == pytest.approx(6.4, abs=1e-9)
    assert regions.samples.time.tolist() == [2.5, 3.0, 4.0, 5.0, 6.0, 7.0]
    # the measured rows are the rows of a measurement at every sample (grouped at every sample, the span
    # ends at 6.5, the last sample in contact), at those times
    grouping = group_regions(meshes, table, times, 0.0)
    assert times[int(grouping.row_span[:, 1].max())] == 6.5
    every = region_depths(meshes, table, grouping, times, closed_meshes(meshes))
    assert every.time.tolist() == times[first:int(grouping.row_span[:, 1].max()) + 1].tolist()
    shared = regions.samples.time < 6.5
    chosen = np.searchsorted(every.time, regions.samples.time[shared])
    assert regions.samples.penetration[shared].tobytes() == every.penetration[chosen].tobytes()
    assert regions.samples.intersection_length[shared].tobytes() == every.intersection_length[chosen].tobytes()
    assert regions.samples.penetration[0] > 0, "through the sheet by its first sample"
    assert regions.samples.penetration[-1] == 0, "out of the sheet by frame 7"
    # the largest of the measured samples: the sheet halves the box at time 4.4, between frames 4 and 5
    assert regions.max_depth_time.tolist() == [4.0]
    assert regions.max_depth[0] == regions.samples.penetration.max() < every.penetration.max()

    # the same motion sampled once a frame: the same region, ending at the same frame
    frames = np.arange(0.0, 9.0)
    coarse_meshes = _box_through_a_sheet(frames)
    coarse = find_regions(coarse_meshes, contacts(coarse_meshes, [(0, 1)]), frames)
    assert coarse.last_time[0] == pytest.approx(regions.last_time[0], abs=1e-5)
    assert coarse.max_depth.tobytes() == regions.max_depth.tobytes()


def test_region_depths_takes_the_flags_and_measures_every_sample_without_them():
    times = np.arange(0.0, 9.0, 0.25)
    meshes = _box_through_a_sheet(times)
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, times, 0.0)
    closed = closed_meshes(meshes)
    none = region_depths(meshes, table, grouping, times, closed, measured=np.zeros(times.size, bool))
    assert none.time.tolist() == [2.5, float(times[int(grouping.row_span[:, 1].max())])], "first and last only"
    every = region_depths(meshes, table, grouping, times, closed)
    flagged = region_depths(meshes, table, grouping, times, closed, measured=np.ones(times.size, bool))
    assert every.time.tobytes() == flagged.time.tobytes() and every.count > 10
