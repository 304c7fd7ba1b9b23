"""The loader keeps authored world-space float points as float32; the regions read them in place as the
same doubles: every region column and depth sample equals what float64 copies of the points give."""

import dataclasses
from pathlib import Path

import numpy as np
import pytest

from usdksl.checking.collision import find_contacts
from usdksl.reading.loader import load_shot
from usdksl.reading.scope import ScopeOptions, plan_shot
from usdksl.regions.find import find_regions

SAMPLES = Path(__file__).resolve().parents[2] / "samples"


@pytest.mark.parametrize("name", ["drape", "fold", "pass_through"])
def test_float_points_give_the_regions_of_their_doubles(name):
    shot = load_shot(SAMPLES / f"{name}.usda")
    assert any(mesh.points.dtype == np.float32 for mesh in shot.meshes), "kept as authored"
    doubles = [dataclasses.replace(mesh, points=mesh.points.astype(np.float64)) for mesh in shot.meshes]
    plan = plan_shot(shot, ScopeOptions(), None)
    table = find_contacts(shot.meshes, plan.pairs).face_contacts(shot.meshes)
    assert table.count > 0
    assert find_contacts(doubles, plan.pairs).face_contacts(doubles).time.tobytes() == table.time.tobytes()
    as_loaded = find_regions(shot.meshes, table, shot.times)
    as_doubles = find_regions(doubles, table, shot.times)
    assert as_loaded.count > 0
    for field in dataclasses.fields(as_loaded):
        a, b = getattr(as_loaded, field.name), getattr(as_doubles, field.name)
        if isinstance(a, np.ndarray):
            assert (a.tolist() == b.tolist() if a.dtype == object else a.tobytes() == b.tobytes()), field.name
    for field in dataclasses.fields(as_loaded.samples):
        a, b = getattr(as_loaded.samples, field.name), getattr(as_doubles.samples, field.name)
        assert np.asarray(a).tobytes() == np.asarray(b).tobytes(), field.name
