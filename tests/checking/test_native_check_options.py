"""The core's options cross into C++ as one struct with named fields (``usdksl._native.CheckOptions``), built once
by ``usdksl.checking.collision.find_contacts``; every method and the narrow phase read its thickness."""

import numpy as np
import pytest

from builders import sheets_passing
from usdksl import _native
from usdksl.ccd_defaults import DEFAULT_MAX_ITERATIONS, DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from usdksl.checking import collision
from usdksl.checking.collision import METHODS, find_contacts

#: Every field of the bound struct with a value other than its default.
CHANGED = {"method": "swept", "t_begin": -2.5, "t_end": 7.25, "tolerance": 1e-4, "thickness": 0.125,
           "max_iterations": 4321, "discrete_substeps": 3, "threads": 2, "frames_per_time_code": 0.5}
#: The sheets of sheets_passing() start 1 scene unit apart and close at 0.5 per time code: they meet at time 2.
MEETING_TIME = 2.0
CLOSING_SPEED = 0.5
#: How close (time codes) a reported first contact is to the closed form: the narrow phase is conservative.
TIME_SLACK = 1e-3


def test_the_struct_has_named_fields_with_the_cores_defaults():
    options = _native.CheckOptions()
    assert (options.method, options.t_begin, options.t_end) == ("ksl", 0.0, 0.0)
    assert options.tolerance == DEFAULT_TOLERANCE and options.thickness == DEFAULT_THICKNESS
    assert options.max_iterations == DEFAULT_MAX_ITERATIONS
    assert (options.discrete_substeps, options.threads, options.frames_per_time_code) == (1, 1, 0.0)


def test_fields_are_set_and_read_by_name():
    built = _native.CheckOptions(**CHANGED)
    assert {name: getattr(built, name) for name in CHANGED} == CHANGED
    written = _native.CheckOptions()
    for name, value in CHANGED.items():
        setattr(written, name, value)
    assert {name: getattr(written, name) for name in CHANGED} == CHANGED
    assert all(f"{name}={value!r}" in repr(built) for name, value in CHANGED.items())
    with pytest.raises(TypeError):
        _native.CheckOptions("swept")   # by name only
    with pytest.raises(ValueError, match="unknown method"):
        written.method = "fastest"
    assert [_native.CheckOptions(method=method).method for method in METHODS] == list(METHODS)


def _native_meshes(meshes):
    return [(mesh.times, mesh.points, mesh.triangles, mesh.triangle_face) for mesh in meshes]


@pytest.mark.parametrize("method", METHODS)
def test_the_core_reads_the_range_and_the_thickness_from_the_struct(method):
    meshes = _native_meshes(sheets_passing())
    pairs = np.array([[0, 1]], dtype=np.int32)
    options = _native.CheckOptions(method=method, t_begin=0.0, t_end=4.0, discrete_substeps=8)
    touching = _native.find_contacts(meshes, pairs, options, None)["time"]
    assert touching.size and abs(touching.min() - MEETING_TIME) <= 1.0 / options.discrete_substeps
    options.thickness = 0.25
    early = _native.find_contacts(meshes, pairs, options, None)["time"]
    expected = MEETING_TIME - options.thickness / CLOSING_SPEED
    assert abs(early.min() - expected) <= (1.0 / options.discrete_substeps if method == "discrete" else TIME_SLACK)
    options.thickness, options.t_end = 0.0, 1.0   # before they meet (a sample time: brute force tests whole steps)
    assert _native.find_contacts(meshes, pairs, options, None)["time"].size == 0


def test_find_contacts_hands_its_keywords_to_the_core_in_one_struct(monkeypatch):
    handed = []
    real = _native.find_contacts

    def recording(meshes, pairs, options, progress):
        handed.append(options)
        return real(meshes, pairs, options, progress)

    monkeypatch.setattr(collision._native, "find_contacts", recording)
    result = find_contacts(list(sheets_passing()), [(0, 1)], method="swept", time_range=(0.5, 3.5), tolerance=1e-5,
                           thickness=0.25, max_iterations=5000, discrete_substeps=2, threads=2)
    assert len(handed) == 1 and isinstance(handed[0], _native.CheckOptions)
    options = handed[0]
    assert (options.method, options.t_begin, options.t_end, options.tolerance, options.thickness,
            options.max_iterations, options.discrete_substeps, options.threads) == (
        "swept", 0.5, 3.5, 1e-5, 0.25, 5000, 2, 2)
    assert abs(result.time.min() - (MEETING_TIME - 0.25 / CLOSING_SPEED)) <= TIME_SLACK
