"""The shipped samples: the cross-check finds exactly the face pairs an exhaustive double-precision search
finds, frame by frame, and agrees with the continuous check run by the command itself."""

import subprocess
import sys

import numpy as np
import pytest

from brute_force import brute_force_pairs
from usdksl.contacts.table import ContactTable
from usdksl.crosscheck.shot import _pair_matrix, crosscheck_shot, points_at, scoped_mesh_pairs
from usdksl.crosscheck.embree_frames import FrameTopology
from usdksl.reading.loader import load_shot

NO_CONTACTS = ContactTable.empty(None)

# sample -> (frames checked against the (slow) oracle: the first, one before contact and those with
# intersections; meshes whose pairs intersect there)
SAMPLES = {
    "clean": ("1,12,24", set()),
    "fold": ("1,20,31:36", {("/World/Strip", "/World/Strip")}),
    "pass_through": (None, {("/World/Mover/Box", "/World/Wall")}),
    "drape": ("17,18,24", {("/World/Box", "/World/Cloth")}),
}


def oracle_rows(shot, frames, pairs):
    meshes = shot.meshes
    topology = FrameTopology.from_meshes([m.triangles for m in meshes], [m.triangle_face for m in meshes],
                                         [m.vertex_count for m in meshes])
    allowed = _pair_matrix(pairs, len(meshes))
    rows = set()
    for time in frames:
        vertices = np.concatenate([points_at(mesh, time) for mesh in meshes])
        for a, b in brute_force_pairs(topology, vertices, allowed):
            ends = []
            for triangle in (a, b):
                mesh = int(topology.triangle_mesh[triangle])
                ends.append((meshes[mesh].path, int(topology.triangle_face[triangle])))
            if ends[0] != ends[1]:
                first, second = sorted(ends)
                rows.add((float(time), *first, *second))
    return rows


@pytest.mark.parametrize("name", sorted(SAMPLES))
def test_sample_rows_equal_the_exhaustive_search(samples_dir, name):
    frames, expected_meshes = SAMPLES[name]
    shot = load_shot(samples_dir / f"{name}.usda")
    result = crosscheck_shot(shot, frames=frames, contacts=NO_CONTACTS)
    paths = result.prim_paths
    rows = {(t, paths[a], int(fa), paths[b], int(fb)) for t, a, fa, b, fb in
            zip(result.time.tolist(), result.mesh_a, result.face_a, result.mesh_b, result.face_b)}
    assert len(rows) == len(result.time)
    assert rows == oracle_rows(shot, result.frames.tolist(), scoped_mesh_pairs(shot))
    assert {(row[1], row[3]) for row in rows} == expected_meshes
    assert result.exit_code() == (3 if rows else 0)


@pytest.mark.parametrize("name,expected_exit", [("clean", 0), ("fold", 1), ("pass_through", 1), ("drape", 1)])
def test_command_agrees_with_the_continuous_check(samples_dir, tmp_path, name, expected_exit):
    """No --contacts: the command runs the continuous check itself (in a child process, so that a crash of
    the core fails this test instead of the session)."""
    command = [sys.executable, "-c", "from usdksl.cli.main import main; main()", "crosscheck",
               str(samples_dir / f"{name}.usda"), "--out", str(tmp_path)]
    # From a neutral folder: `python -c` puts the working directory first on sys.path, and the
    # source tree's usdksl/ (no native module) must not shadow the installed package.
    finished = subprocess.run(command, capture_output=True, text=True, timeout=600, cwd=tmp_path)
    assert finished.returncode == expected_exit, finished.stderr[-2000:]
    assert "consistent" in finished.stderr
    assert (tmp_path / f"{name}.crosscheck.csv").is_file()
