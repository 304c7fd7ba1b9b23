"""A stage written with sub-frame samples (two a frame, as a simulator writes them for motion blur): ``usdksl
check`` reads the stage's clock and steps over them from whole frame to whole frame, and its contacts are
brute force's, which checks every sample."""

import numpy as np
import pytest

from builders import grid_sheet, new_stage, write_mesh
from usdksl.pipeline.check import check_shot
from usdksl.pipeline.options import CheckOptions

#: The clock: 48 time codes a second, 24 frames a second, so whole frames fall on even time codes.
TIME_CODES_PER_SECOND, FRAMES_PER_SECOND = 48.0, 24.0
#: Time codes sampled (every one: two samples a frame).
LAST_TIME_CODE = 40


def falling_sheet(path):
    """A sheet of 8 x 8 quads wobbling gently (its sub-frame samples bend far less than 1/64 of an edge
    off the frames' chords) while it falls through a still slab."""
    stage = new_stage(path, tcps=TIME_CODES_PER_SECOND, fps=FRAMES_PER_SECOND, start=0.0, end=LAST_TIME_CODE)
    points, counts, indices = grid_sheet(1.0, 8, z=0.5)
    samples = {}
    for t in range(LAST_TIME_CODE + 1):
        moved = points.copy()
        moved[:, 2] += -0.025 * t + 0.02 * np.sin(0.1 * t + 3.0 * points[:, 0])
        samples[float(t)] = moved
    write_mesh(stage, "/World/Cloth", counts, indices, samples=samples)
    slab, slab_counts, slab_indices = grid_sheet(0.6, 2, z=0.0, origin=(0.2, 0.2))
    write_mesh(stage, "/World/Slab", slab_counts, slab_indices, points=slab)
    stage.Save()
    return str(path)


def contact_rows(result):
    table = result.table
    return [np.asarray(column).tolist() for column in (table.time, table.mesh_a, table.face_a, table.mesh_b,
                                                        table.face_b)]


@pytest.mark.parametrize("threads", [1, 2])
def test_sub_frame_samples_are_stepped_over_with_brute_force_s_answer(tmp_path, threads):
    shot = falling_sheet(tmp_path / "falling.usda")
    kinetic = check_shot(shot, CheckOptions(threads=threads))
    brute = check_shot(shot, CheckOptions(method="brute", threads=threads))
    assert kinetic.table.count > 0
    assert contact_rows(kinetic) == contact_rows(brute)
    # One kinetic step a frame, not one a sample (40 without the clock): the clock reached the core.
    assert kinetic.counters["bv_change_events"] == LAST_TIME_CODE // 2
