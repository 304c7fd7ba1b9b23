"""Every shot the tests build, in one place: USD stages written with pxr into tmp_path, and animated
meshes as plain numpy arrays for the core (no USD). Test folders import it as ``builders`` (tests/ is on
sys.path through tests/conftest.py)."""

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from pxr import Usd, UsdGeom, Vt

# --------------------------------------------------------------------------- topologies

# One authored quad face in the XZ plane at height 0.
QUAD_POINTS = np.array([[0, 0, 0], [1, 0, 0], [1, 0, 1], [0, 0, 1]], dtype=np.float64)
QUAD_COUNTS = [4]
QUAD_INDICES = [0, 1, 2, 3]

# Two quads sharing an edge (faces 0 and 1).
STRIP_POINTS = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [2, 0, 1], [1, 0, 1], [0, 0, 1]], dtype=np.float64)
STRIP_COUNTS = [4, 4]
STRIP_INDICES = [0, 1, 4, 5, 1, 2, 3, 4]


def quad_grid(columns=2, rows=2, size=1.0):
    """A flat sheet of columns x rows quads in the XZ plane at y = 0: (points[N, 3], counts, indices).

    Vertex j * (columns + 1) + i sits at x cell i, z cell j; face f covers x cell f % columns and z cell
    f // columns."""
    x, z = np.meshgrid(np.linspace(0, size, columns + 1), np.linspace(0, size, rows + 1))
    points = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1)
    ids = np.arange((rows + 1) * (columns + 1)).reshape(rows + 1, columns + 1)
    quads = np.stack([ids[:-1, :-1], ids[:-1, 1:], ids[1:, 1:], ids[1:, :-1]], axis=-1).reshape(-1, 4)
    return points, [4] * len(quads), quads.ravel().tolist()


def grid_sheet(size, count, z=0.0, origin=(0.0, 0.0)):
    """A flat square sheet of count x count quads in the plane z (the XY plane shifted by ``origin``):
    (points[N, 3], counts, indices), numbered as :func:`quad_grid` with y in place of z."""
    points, counts, indices = quad_grid(count, count, size)
    points = points[:, [0, 2, 1]] + [origin[0], origin[1], float(z)]
    return points, np.asarray(counts), np.asarray(indices)


# --------------------------------------------------------------------------- USD stages

def new_stage(path, tcps=24.0, fps=None, start=1.0, end=24.0, up="Y", meters=1.0, default_prim="World"):
    """A stage with its metadata set and a /World Xform (the default prim unless ``default_prim`` is
    empty)."""
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(tcps)
    if fps is not None:
        stage.SetFramesPerSecond(fps)
    stage.SetStartTimeCode(start)
    stage.SetEndTimeCode(end)
    UsdGeom.SetStageUpAxis(stage, up)
    UsdGeom.SetStageMetersPerUnit(stage, meters)
    world = UsdGeom.Xform.Define(stage, "/World")
    if default_prim:
        stage.SetDefaultPrim(world.GetPrim())
    return stage


def bare_stage(path):
    """A stage with nothing but timeCodesPerSecond 24 (the loader tests author everything else)."""
    stage = Usd.Stage.CreateNew(str(path))
    stage.SetTimeCodesPerSecond(24)
    return stage


def write_mesh(stage, path, counts, indices, points=None, samples=None, holes=None, topology_samples=None):
    """A mesh with static ``points`` and/or ``samples`` {time: points}; ``topology_samples``
    {time: (counts, indices)} animates the topology."""
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([int(c) for c in counts]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in indices]))
    if holes is not None:
        mesh.CreateHoleIndicesAttr(Vt.IntArray([int(h) for h in holes]))
    attribute = mesh.CreatePointsAttr()
    if points is not None:
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, dtype=np.float32)))
    for time, value in (samples or {}).items():
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, dtype=np.float32)), time)
    for time, (t_counts, t_indices) in (topology_samples or {}).items():
        mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray([int(c) for c in t_counts]), time)
        mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray([int(i) for i in t_indices]), time)
    return mesh


def add_mesh(stage, path, points, counts=QUAD_COUNTS, indices=QUAD_INDICES, samples=None):
    """A quad (or the given topology): ``samples`` {time: points} for an animated mesh, otherwise
    ``points`` is the default value."""
    return write_mesh(stage, path, counts, indices, points=None if samples else points, samples=samples)


def falling_quad_samples(offset=(0.0, 0.0, 0.0), start_height=1.0, end_height=-1.0, times=(1.0, 24.0)):
    """A quad moving straight down through y = 0 between the two times."""
    base = QUAD_POINTS + np.asarray(offset)
    return {times[0]: base + [0, start_height, 0], times[1]: base + [0, end_height, 0]}


def fifty_mesh_scene(path):
    """48 static quads, a falling cloth quad and a rigidly moving box under /World/Anim."""
    stage = new_stage(path)
    for k in range(48):
        add_mesh(stage, f"/World/Static/M{k:02d}", QUAD_POINTS + [3.0 * k, 0, 0])
    add_mesh(stage, "/World/Anim/Cloth", None, samples=falling_quad_samples())
    rigid = UsdGeom.Xform.Define(stage, "/World/Anim/Mover")
    op = rigid.AddTranslateOp()
    op.Set((0.0, 0.0, 0.0), 1.0)
    op.Set((5.0, 0.0, 0.0), 24.0)
    add_mesh(stage, "/World/Anim/Mover/Box", QUAD_POINTS + [0, 2.0, 0])
    stage.GetRootLayer().Save()


def write_shot(path, meshes, start=None, end=None):
    """A Z-up shot of ``meshes``: dicts with prim ``path``, ``counts``, ``indices`` and either ``points``
    (static) or ``samples`` {time: points}. The parent of each mesh is an Xform; start and end default to
    the sampled range. Returns the path as str."""
    stage = Usd.Stage.CreateNew(str(path))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    all_times = []
    for mesh in meshes:
        parent = mesh["path"].rsplit("/", 1)[0]
        if parent:
            UsdGeom.Xform.Define(stage, parent)
        samples = {float(time): points for time, points in mesh.get("samples", {}).items()}
        write_mesh(stage, mesh["path"], mesh["counts"], mesh["indices"],
                   points=None if samples else mesh["points"], samples=samples)
        all_times.extend(samples)
    if all_times:
        stage.SetStartTimeCode(start if start is not None else min(all_times))
        stage.SetEndTimeCode(end if end is not None else max(all_times))
    stage.GetRootLayer().Save()
    return str(path)


# --------------------------------------------------------------------------- files

def sha256(path) -> str:
    return hashlib.sha256(Path(path).read_bytes()).hexdigest()


def snapshot(directory) -> dict:
    """{relative path: sha256} of every file below directory (to prove nothing was written)."""
    directory = Path(directory)
    return {str(p.relative_to(directory)): sha256(p) for p in sorted(directory.rglob("*")) if p.is_file()}


# --------------------------------------------------------------------------- meshes for the core (no USD)

@dataclass
class Mesh:
    """What find_contacts reads of a mesh: times, points[K, N, 3], triangles, triangle -> face."""

    times: np.ndarray
    points: np.ndarray
    triangles: np.ndarray
    triangle_face: np.ndarray


def triangle_grid(nx, ny, size=1.0):
    """A flat (nx x ny quads) sheet in the XY plane, two triangles per quad: (vertices, triangles)."""
    xs, ys = np.meshgrid(np.linspace(0, size, nx + 1), np.linspace(0, size, ny + 1), indexing="ij")
    verts = np.stack([xs.ravel(), ys.ravel(), np.zeros(xs.size)], axis=1)
    idx = np.arange((nx + 1) * (ny + 1)).reshape(nx + 1, ny + 1)
    a, b, c, d = idx[:-1, :-1].ravel(), idx[1:, :-1].ravel(), idx[1:, 1:].ravel(), idx[:-1, 1:].ravel()
    tris = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    return verts, tris


def animated(times, frames, triangles, faces=None):
    """A Mesh from its sample times and points per sample; one face per triangle unless ``faces``."""
    times = np.asarray(times, dtype=np.float64)
    points = np.ascontiguousarray(np.asarray(frames, dtype=np.float64))
    triangles = np.asarray(triangles, dtype=np.int32)
    if faces is None:
        faces = np.arange(triangles.shape[0], dtype=np.int32)
    return Mesh(times, points, triangles, np.asarray(faces, dtype=np.int32))


def folding_sheet(n=6, samples=9):
    """A sheet folding about its middle line until the halves pass through each other."""
    verts, tris = triangle_grid(n, 2)
    frames = []
    for angle in np.linspace(0.0, 1.15 * np.pi, samples):
        p = verts.copy()
        right = p[:, 0] > 0.5
        dx = p[right, 0] - 0.5
        p[right, 0] = 0.5 + dx * np.cos(angle)
        p[right, 2] = dx * np.sin(angle) + 0.05 * dx * np.sin(angle / 2)  # slight offset so halves cross
        frames.append(p)
    return animated(np.arange(samples, dtype=float), frames, tris)


def sheets_passing(n=4, samples=5):
    """Two parallel sheets: the upper one moves down through the lower one."""
    verts, tris = triangle_grid(n, n)
    lower = animated(np.arange(samples, dtype=float), [verts] * samples, tris)
    upper_frames = [verts + [0.1, 0.07, 1.0 - 2.0 * k / (samples - 1)] for k in range(samples)]
    upper = animated(np.arange(samples, dtype=float), upper_frames, tris)
    return lower, upper


def tunnelling_triangle():
    """A small triangle crossing a plane entirely between two samples."""
    verts, tris = triangle_grid(2, 2, size=2.0)
    plane = animated([0.0, 1.0], [verts, verts], tris)
    small = np.array([[0.9, 0.9, 1.0], [1.0, 0.9, 1.0], [0.9, 1.0, 1.0]])
    bullet = animated([0.0, 1.0], [small, small - [0, 0, 2.0]], [[0, 1, 2]])
    return plane, bullet
