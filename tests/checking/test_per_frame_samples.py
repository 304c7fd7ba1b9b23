"""samples/generate.py's per-frame scene (flutter) writes what it says: a sample at every frame, vertices on
curves (no three consecutive samples collinear, so flightplan merging has nothing to drop), and a cloth
that rests on a collider for many frames; and the core finds its contacts at every density, as brute force
and as ipctk's Tight-Inclusion CCD (tests/reference, no code shared with the core) find them."""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest
from pxr import Usd, UsdGeom

from usdksl.ccd_defaults import DEFAULT_TOLERANCE
from usdksl.checking.collision import find_contacts
from usdksl.reading.loader import load_shot
from usdksl.reading.scope import plan_shot

REPO_ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(REPO_ROOT / "samples"))
import generate  # noqa: E402

FRAMES = 24
FACES = 120
#: Smallest distance (scene units) of a middle sample from the chord of its two neighbours that the test
#: accepts: far above the core's merge tolerance (FLIGHTPLAN_COLLINEAR_TOLERANCE = 2^-22 times the largest
#: coordinate, ~3e-7 here), so no sample can merge away. The generator's circling keeps it near 8e-4.
MIN_CHORD_DEVIATION = 1e-4


@pytest.fixture(scope="module")
def flutter(tmp_path_factory):
    out = tmp_path_factory.mktemp("flutter") / "flutter.usdc"
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), "flutter", "--faces", str(FACES),
                    "--frames", str(FRAMES), "--out", str(out)], check=True, capture_output=True)
    return out


def chord_deviation(points: np.ndarray) -> np.ndarray:
    """float[K - 2, N]: distance of sample k+1 from the segment between samples k and k+2."""
    a, b, c = points[:-2], points[1:-1], points[2:]
    chord = c - a
    length = np.linalg.norm(chord, axis=-1, keepdims=True)
    direction = chord / np.where(length > 0, length, 1.0)
    offset = b - a
    return np.linalg.norm(offset - np.sum(offset * direction, axis=-1, keepdims=True) * direction, axis=-1)


def test_every_frame_is_a_sample(flutter):
    stage = Usd.Stage.Open(str(flutter))
    expected = [float(t) for t in range(1, FRAMES + 1)]
    cloth = UsdGeom.Mesh(stage.GetPrimAtPath("/World/Cloth"))
    assert cloth.GetPointsAttr().GetTimeSamples() == expected
    pendulum = UsdGeom.Xformable(stage.GetPrimAtPath("/World/Pendulum"))
    for op in pendulum.GetOrderedXformOps():
        assert op.GetAttr().GetTimeSamples() == expected
    shot = load_shot(str(flutter))
    assert shot.times.tolist() == expected


def test_vertices_move_on_curves(flutter):
    shot = load_shot(str(flutter))
    moving = {mesh.path: mesh for mesh in shot.meshes if mesh.kind != "static"}
    assert set(moving) == {"/World/Cloth", "/World/Pendulum/Ball"}
    for mesh in moving.values():
        deviation = chord_deviation(np.asarray(mesh.points, np.float64))
        # every vertex, at every inner sample: merging two segments would move it by at least this much
        assert deviation.min() > MIN_CHORD_DEVIATION, mesh.path


def test_cloth_rests_on_the_table_for_most_of_the_shot(flutter):
    shot = load_shot(str(flutter))
    cloth = next(m for m in shot.meshes if m.path == "/World/Cloth")
    top = next(m for m in shot.meshes if m.path == "/World/Table/Top")
    table_top = top.points[0, :, 1].max()
    half_x, half_z = top.points[0, :, 0].max(), top.points[0, :, 2].max()
    points = np.asarray(cloth.points, np.float64)
    over_table = (np.abs(points[0, :, 0]) < half_x - 0.02) & (np.abs(points[0, :, 2]) < half_z - 0.02)
    assert over_table.sum() > 10
    gap = points[:, over_table, 1] - table_top
    resting = np.all(np.abs(gap - generate.FLUTTER_REST_GAP) < 1e-5, axis=1)
    assert resting.sum() >= FRAMES // 2
    assert resting[-1] and not resting[0]
    # resting is at a gap: it never touches the top, but the falling cloth started above it
    assert gap.min() > 0.0


@pytest.mark.parametrize("method", ["ksl", "swept"])
def test_contacts_with_table_and_pendulum_are_found(flutter, method):
    shot = load_shot(str(flutter))
    plan = plan_shot(shot)
    result = find_contacts(shot.meshes, plan.pairs, method=method)
    faces = result.face_contacts(shot.meshes)
    paths = [mesh.path for mesh in shot.meshes]
    touched = {(paths[a], paths[b]) for a, b in zip(faces.mesh_a.tolist(), faces.mesh_b.tolist())}
    cloth, top, ball = (paths.index(p) for p in ("/World/Cloth", "/World/Table/Top", "/World/Pendulum/Ball"))
    assert tuple(sorted((paths[cloth], paths[top]))) in {tuple(sorted(p)) for p in touched}
    assert tuple(sorted((paths[cloth], paths[ball]))) in {tuple(sorted(p)) for p in touched}
    assert result.counters["narrow_phase_tests"] > 0


def contact_columns(result):
    return [np.asarray(column).tolist() for column in
            (result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b, result.feature)]


@pytest.mark.parametrize("seed,faces,thickness", [(3, 96, 0.0), (11, 150, 0.004)])
def test_kinetic_lists_equal_brute_force_bit_for_bit_on_per_frame_curves(tmp_path, seed, faces, thickness):
    # Every frame is a breakpoint and vertices move on curves: the kinetic core's step boxes and
    # clearance certificates must not lose a pair or make one later, so its answer is brute force's,
    # bit for bit (and the same at two threads).
    out = generate.generate("flutter", faces, seed=seed, out=str(tmp_path / "flutter.usdc"), frames=FRAMES)
    shot = load_shot(out)
    plan = plan_shot(shot)
    brute = contact_columns(find_contacts(shot.meshes, plan.pairs, method="brute", thickness=thickness))
    assert len(brute[0]) > 0, "the shot must have contacts"
    for method, threads in (("ksl", 1), ("ksl", 2), ("swept", 1)):
        answer = contact_columns(find_contacts(shot.meshes, plan.pairs, method=method, thickness=thickness,
                                               threads=threads))
        assert answer == brute, (method, threads)


# Smaller cloths than above: the reference makes one Python call per primitive query.
@pytest.mark.parametrize("seed,faces,thickness", [(3, 40, 0.0), (11, 12, 0.004)])
def test_brute_force_and_the_kinetic_lists_agree_with_ipctk_on_per_frame_curves(tmp_path, seed, faces, thickness,
                                                                               ipctk_reference):
    out = generate.generate("flutter", faces, seed=seed, out=str(tmp_path / "flutter.usdc"), frames=FRAMES)
    shot = load_shot(out)
    plan = plan_shot(shot)
    reference = ipctk_reference.first_contacts(shot.meshes, plan.pairs, thickness=thickness)
    paths = [mesh.path for mesh in shot.meshes]
    touched = {(paths[key[0]], paths[key[2]]) for key in reference.must}
    assert {("/World/Table/Top", "/World/Cloth"), ("/World/Cloth", "/World/Pendulum/Ball")} <= touched
    for method in ("brute", "ksl"):
        result = find_contacts(shot.meshes, plan.pairs, method=method, thickness=thickness, threads=1)
        ipctk_reference.assert_agrees(reference, result, shot.meshes, DEFAULT_TOLERANCE, f"{method}: ")


@pytest.mark.parametrize("dash_frame", [7, 18, 29])
def test_a_mesh_resting_far_away_that_dashes_in_one_frame_is_not_missed(dash_frame, ipctk_reference):
    # The lists skip looking at boxes that cannot meet before their meshes have travelled their gap,
    # counted with each mesh's largest motion per frame: a sheet that rests 3 units away for many
    # frames and then crosses the other in a single frame must still be found, at brute force's time.
    sys.path.insert(0, str(REPO_ROOT / "tests"))
    from builders import animated, triangle_grid

    verts, tris = triangle_grid(4, 4)
    times = np.arange(0.0, 36.0)
    still = animated(times, [verts + [0.0, 0.0, 0.1 * np.sin(0.3 * t)] for t in times], tris)
    frames = [verts + [0.05, 0.03, 3.0 if t <= dash_frame else -0.5] for t in times]
    dasher = animated(times, frames, tris)
    meshes, pairs = [still, dasher], [(0, 0), (1, 1), (0, 1)]
    brute = contact_columns(find_contacts(meshes, pairs, method="brute"))
    assert brute[0] and min(brute[0]) > dash_frame
    assert contact_columns(find_contacts(meshes, pairs, method="ksl", threads=1)) == brute
    reference = ipctk_reference.first_contacts(meshes, pairs)
    assert min(reference.must.values()) > dash_frame
    ipctk_reference.assert_agrees(reference, find_contacts(meshes, pairs, method="brute"), meshes, DEFAULT_TOLERANCE)
