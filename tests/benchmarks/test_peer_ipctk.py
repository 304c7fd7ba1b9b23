"""benchmarks/peer_ipctk.py computes usdksl's answer: on tiny shots whose first contacts are known in closed
form, its face pairs and times equal the closed form and usdksl's (this guards the mapping of ipctk's
vertex-face and edge-edge candidates to authored face pairs), and its comparison report counts what it says."""

import os
import subprocess
import sys

import numpy as np
import pytest
from pxr import Usd, UsdGeom, Vt

ipctk = pytest.importorskip("ipctk", reason="ipctk (IPC Toolkit) is a benchmark-only dependency")

import usdksl  # noqa: E402
from usdksl.reading.scope import ScopeOptions, plan_shot  # noqa: E402

import peer_ipctk  # noqa: E402  (benchmarks/ is on sys.path via conftest.py)

#: Agreement between peer, usdksl and the closed form, in time codes (both CCDs stop far below this).
TIME_AGREEMENT = 1e-5


def write_shot(path, meshes):
    """meshes: {prim path: (counts, indices, {time: points} or points)}; 24 time codes per second."""
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24)
    UsdGeom.Xform.Define(stage, "/World")
    for prim_path, (counts, indices, points) in meshes.items():
        mesh = UsdGeom.Mesh.Define(stage, prim_path)
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray([int(c) for c in counts]))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in indices]))
        attribute = mesh.CreatePointsAttr()
        if isinstance(points, dict):
            for time, value in points.items():
                attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, np.float32)), time)
        else:
            attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, np.float32)))
    stage.GetRootLayer().Save()
    return str(path)


def ground_quad(half=1.0):
    points = np.array([[-half, 0, -half], [half, 0, -half], [half, 0, half], [-half, 0, half]], float)
    return [4], [0, 1, 2, 3], points


def pyramid(apex):
    """An apex pointing down (-Y) with four triangular sides and a quad base 0.3 above it."""
    ax, ay, az = apex
    base = [[ax - 0.2, ay + 0.3, az - 0.2], [ax + 0.2, ay + 0.3, az - 0.2], [ax + 0.2, ay + 0.3, az + 0.2],
            [ax - 0.2, ay + 0.3, az + 0.2]]
    points = np.array([[ax, ay, az]] + base, float)
    counts = [3, 3, 3, 3, 4]
    indices = [0, 2, 1, 0, 3, 2, 0, 4, 3, 0, 1, 4, 1, 2, 3, 4]
    return counts, indices, points


def both_answers(shot_path):
    shot = usdksl.load_shot(shot_path)
    plan = plan_shot(shot, ScopeOptions())
    faces = usdksl.find_contacts(shot.meshes, plan.pairs, method="ksl").face_contacts(shot.meshes)
    paths = np.asarray([m.path for m in shot.meshes], dtype=object)
    usdksl_keys = peer_ipctk.pair_keys(paths[faces.mesh_a].astype(str), faces.face_a,
                                       paths[faces.mesh_b].astype(str), faces.face_b)
    peer = peer_ipctk.all_first_contacts(peer_ipctk.combine(shot.meshes, plan.pairs, plan.moving))
    return dict(zip(usdksl_keys.tolist(), faces.time.tolist())), dict(zip(peer.keys().tolist(), peer.time.tolist()))


def expected(pairs, time):
    keys = peer_ipctk.pair_keys([a for a, _, _, _ in pairs], [fa for _, fa, _, _ in pairs],
                                [b for _, _, b, _ in pairs], [fb for _, _, _, fb in pairs])
    return {key: time for key in keys.tolist()}


def assert_same(found, wanted):
    assert set(found) == set(wanted)
    for key, time in wanted.items():
        assert found[key] == pytest.approx(time, abs=TIME_AGREEMENT), key


@pytest.fixture
def apex_shot(tmp_path):
    """The apex falls from 0.6 to -0.15 between time codes 1 and 2: it touches the ground at 1 + 0.6/0.75 = 1.8;
    the four sides around it touch the ground face then; the base stays above the ground."""
    counts, indices, start = pyramid((0.1, 0.6, 0.2))
    _, _, end = pyramid((0.1, -0.15, 0.2))
    return write_shot(tmp_path / "apex.usda", {"/World/Ground": ground_quad(),
                                               "/World/Pyramid": (counts, indices, {1.0: start, 2.0: end})})


def test_vertex_face_closed_form(apex_shot):
    found_usdksl, found_peer = both_answers(apex_shot)
    wanted = expected([("/World/Ground", 0, "/World/Pyramid", side) for side in range(4)], 1.8)
    assert_same(found_peer, wanted)
    assert_same(found_usdksl, wanted)


def test_edge_edge_closed_form(tmp_path):
    """A static triangle with an edge on the X axis; a vertical triangle whose bottom edge (along Z, at x=0.3)
    falls from y=0.5 to y=-0.5 between time codes 3 and 5: the edges meet at y=0, time 4."""
    fixed = (np.array([[-1, 0, 0], [1, 0, 0], [0, -1, 0]], float))
    def blade(y):
        return np.array([[0.3, y, -1], [0.3, y, 1], [0.3, y + 1, 0]], float)
    shot = write_shot(tmp_path / "edges.usda", {"/World/Fixed": ([3], [0, 1, 2], fixed),
                                                "/World/Blade": ([3], [0, 1, 2], {3.0: blade(0.5), 5.0: blade(-0.5)})})
    found_usdksl, found_peer = both_answers(shot)
    wanted = expected([("/World/Blade", 0, "/World/Fixed", 0)], 4.0)
    assert_same(found_peer, wanted)
    assert_same(found_usdksl, wanted)


def test_self_contact_between_authored_quads(tmp_path):
    """One mesh of two quads; the upper one tilts so that its corner 4 leads and falls onto the lower one:
    corner 4 starts 0.5 above it and reaches it after 0.5 / 0.8 of the step (1 -> 2): time 1.625. Only the
    quad pair is reported (never a pair inside one quad)."""
    lower = [[-1, 0, -1], [1, 0, -1], [1, 0, 1], [-1, 0, 1]]
    def upper(drop):
        return [[-0.3, 0.5 - drop, -0.3], [0.3, 0.7 - drop, -0.3], [0.3, 0.9 - drop, 0.3], [-0.3, 0.7 - drop, 0.3]]
    counts, indices = [4, 4], [0, 1, 2, 3, 4, 5, 6, 7]
    shot = write_shot(tmp_path / "self.usda", {"/World/Sheet": (counts, indices, {
        1.0: np.array(lower + upper(0.0), float), 2.0: np.array(lower + upper(0.8), float)})})
    found_usdksl, found_peer = both_answers(shot)
    wanted = expected([("/World/Sheet", 0, "/World/Sheet", 1)], 1.625)
    assert_same(found_peer, wanted)
    assert_same(found_usdksl, wanted)


def test_already_intersecting_at_the_first_sample(tmp_path):
    """A vertical triangle pierces the ground (no vertex or edge of one touches the other) at the first sample
    and slides sideways: reported at the first sample, time 10."""
    def fin(x):
        return np.array([[x, -0.5, 0.0], [x + 0.4, 0.5, -0.2], [x + 0.4, 0.5, 0.2]], float)
    shot = write_shot(tmp_path / "pierce.usda", {"/World/Ground": ground_quad(),
                                                 "/World/Fin": ([3], [0, 1, 2], {10.0: fin(0.0), 12.0: fin(0.3)})})
    found_usdksl, found_peer = both_answers(shot)
    wanted = expected([("/World/Fin", 0, "/World/Ground", 0)], 10.0)
    assert_same(found_peer, wanted)
    assert_same(found_usdksl, wanted)


def test_comparison_report_counts_agreement_errors_and_mismatches(apex_shot, tmp_path):
    reference = peer_ipctk.all_first_contacts(peer_ipctk.load_combined(apex_shot), peer_ipctk.MODES["tight"])
    assert len(reference) == 4
    csv = tmp_path / "apex.contacts.csv"
    rows = ["time,prim_a,face_a,prim_b,face_b,kind"]
    rows += [f"1.8,/World/Ground,0,/World/Pyramid,{side},inter" for side in (0, 1)]
    rows += ["1.805,/World/Ground,0,/World/Pyramid,2,inter",          # 0.005 late
             "1.7,/World/Ground,0,/World/Pyramid,4,inter"]             # the base never touches
    csv.write_text("\n".join(rows) + "\n")
    report, _ = peer_ipctk.compare_csv_to_tight_reference(apex_shot, str(csv), reference=reference)
    assert report["reported_pairs"] == 4 and report["reference_pairs"] == 4
    assert report["common_pairs"] == 3 and report["within_agreement"] == 2
    assert report["largest_late_error"] == pytest.approx(0.005, abs=1e-6)
    assert report["largest_early_error"] < 1e-6
    assert report["reported_without_reference_touch"] == 1
    assert report["reference_pairs_missing_from_report"] == 1


def test_check_csv_agrees_with_the_tight_reference(apex_shot, tmp_path):
    executable = os.path.join(os.path.dirname(sys.executable), "usdksl")
    completed = subprocess.run([executable, "check", apex_shot, "--out", str(tmp_path)], capture_output=True,
                               text=True)
    assert completed.returncode == 1, completed.stderr
    report, _ = peer_ipctk.compare_csv_to_tight_reference(apex_shot, str(tmp_path / "apex.contacts.csv"))
    assert report["reported_pairs"] == report["within_agreement"] == 4
    assert report["reported_without_reference_touch"] == report["reference_pairs_missing_from_report"] == 0


def test_earliest_contact_sweep_finds_the_contact_interval(apex_shot):
    starts, times, counters = peer_ipctk.earliest_contact_sweep(peer_ipctk.load_combined(apex_shot))
    assert starts.tolist() == [0]
    assert times[0] == pytest.approx(1.8, abs=TIME_AGREEMENT)
    assert counters["intervals"] == 1
