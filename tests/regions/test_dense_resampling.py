"""A shot resampled ten times denser along the same motion (sub-frame samples, as for motion blur) reports the
same regions as the shot itself: depth is measured on whole frames (docs/contracts.md, Regions), so the samples
between frames do not move a region's deepest frame, its depth or its box."""

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
def test_ten_times_denser_gives_the_same_depth_frame_and_box(name, transform_keys, tmp_path):
    original = regions_rows(SAMPLES / f"{name}.usda")
    dense = regions_rows(densify(SAMPLES / f"{name}.usda", tmp_path / f"{name}_x{FACTOR}.usdc"))
    assert original and len(dense) == len(original)
    for before, after in zip(original, dense):
        for column in ("prim_a", "prim_b", "kind", "depth_measure", "face_pairs", "max_depth_frame"):
            assert after[column] == before[column], column
        depth_and_box = [float(before[column]) for column in ("max_depth",) + BOX_COLUMNS]
        dense_depth_and_box = [float(after[column]) for column in ("max_depth",) + BOX_COLUMNS]
        if transform_keys:
            # pass_through's box moves by a translate keyed at two time codes: the core blends the original's
            # points between the keys, the dense copy holds USD's interpolated translate at every tenth, so the
            # points of the same frame agree up to rounding
            np.testing.assert_allclose(dense_depth_and_box, depth_and_box, rtol=0, atol=POSITION_ROUNDING)
        else:
            # points sampled on every frame: the dense copy keeps them, so a whole frame is measured bit for bit
            assert dense_depth_and_box == depth_and_box
        # Not compared: first_frame is the continuous first contact, found again over other steps (equal up to
        # rounding); last_frame is the last sample still in contact, which the dense copy has between frames;
        # max_intersection_length is the largest over the measured samples, and the dense copy's first and last
        # samples lie between frames, where the original has none.
