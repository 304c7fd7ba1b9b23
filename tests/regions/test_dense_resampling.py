"""A shot resampled ten times denser along the same motion (sub-frame samples, as for motion blur) reports the
same regions as the shot itself: regions are grouped and measured on whole frames (docs/contracts.md,
Regions), so the samples between frames do not change which face pairs make a region, where it ends, its
deepest frame, its depth or its box."""

import csv
import io
from pathlib import Path

import numpy as np
import pytest
from pxr import Usd

from usdksl.pipeline.check import check_shot

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
#: In-between samples per sample step of the dense copy (benchmarks/densify.py's default).
FACTOR = 10
#: Scene units two positions of the same motion may differ by when one is USD's interpolation of a transform and
#: the other the core's blend of the points it moves (rounding of double arithmetic on unit-sized scenes).
POSITION_ROUNDING = 1e-12
#: Time codes two first contacts of the same motion may differ by: the narrow phase's time tolerance is a
#: fraction of a sample step (1e-6 of it by default), and the first contact is found on steps ten times shorter.
TIME_TOLERANCE = 1e-5
BOX_COLUMNS = ("min_x", "min_y", "min_z", "max_x", "max_y", "max_z", "center_x", "center_y", "center_z")


def densify(source: Path, target: Path) -> Path:
    """``source`` flattened, each attribute with two or more samples given FACTOR - 1 more per step at the values
    USD itself interpolates there (linear for points and translations), as benchmarks/densify.py writes it."""
    stage = Usd.Stage.Open(Usd.Stage.Open(str(source)).Flatten())
    fractions = np.arange(1, FACTOR) / FACTOR
    for prim in stage.Traverse():
        for attribute in prim.GetAttributes():
            times = np.asarray(attribute.GetTimeSamples(), dtype=np.float64)
            if times.size < 2:
                continue
            between = (times[:-1, None] + np.diff(times)[:, None] * fractions[None, :]).ravel().tolist()
            values = [(time, attribute.Get(time)) for time in between]     # read all before the first write
            for time, value in values:
                attribute.Set(value, time)
    stage.GetRootLayer().Export(str(target))
    return target


def regions_rows(shot: Path):
    result = check_shot(str(shot))
    text = next(data for path, data in result.files.items() if str(path).endswith(".regions.csv"))
    return list(csv.DictReader(io.StringIO(text)))


@pytest.mark.parametrize("name, transform_keys", [("fold", False), ("drape", False), ("pass_through", True)])
def test_ten_times_denser_gives_the_same_regions(name, transform_keys, tmp_path):
    original = regions_rows(SAMPLES / f"{name}.usda")
    dense = regions_rows(densify(SAMPLES / f"{name}.usda", tmp_path / f"{name}_x{FACTOR}.usdc"))
    assert original and len(dense) == len(original)
    for before, after in zip(original, dense):
        for column in ("region", "prim_a", "prim_b", "kind", "depth_measure", "face_pairs", "faces_a", "faces_b",
                       "max_depth_frame"):
            assert after[column] == before[column], column
        # the continuous first contact is found again over ten times the steps: the same up to the narrow
        # phase's time tolerance, a fraction of the dense copy's step; so is the last frame of a region whose
        # contacts are all over by the next frame (it ends at its last contact's own time), where one still in
        # contact at a frame ends at the same frame
        for column in ("first_frame", "last_frame"):
            assert float(after[column]) == pytest.approx(float(before[column]), abs=TIME_TOLERANCE), column
        measured = [float(before[column]) for column in ("max_depth", "max_intersection_length") + BOX_COLUMNS]
        dense_measured = [float(after[column]) for column in ("max_depth", "max_intersection_length") + BOX_COLUMNS]
        if transform_keys:
            # pass_through's box moves by a translate keyed at two time codes: the core blends the original's
            # points between the keys, the dense copy holds USD's interpolated translate at every tenth, so the
            # points of the same frame agree up to rounding
            np.testing.assert_allclose(dense_measured, measured, rtol=0, atol=POSITION_ROUNDING)
        else:
            # points sampled on every frame: the dense copy keeps them, so a whole frame is measured bit for bit
            assert dense_measured == measured
