"""Every shot the tests build, in one place: USD stages written with pxr into tmp_path, and animated
meshes as plain numpy arrays for the core (no USD). Test folders import it as ``builders`` (tests/ is on
sys.path through tests/conftest.py)."""

import hashlib
from dataclasses import dataclass
from pathlib import Path

import numpy as np
import shutil

from pxr import Gf, Sdf, Usd, UsdGeom, UsdSkel, Vt

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


def rotation(axis, angle):
    """3x3 rotation by ``angle`` (radians) about the unit vector ``axis`` (Rodrigues' formula)."""
    k = np.array([[0, -axis[2], axis[1]], [axis[2], 0, -axis[0]], [-axis[1], axis[0], 0]])
    return np.eye(3) + np.sin(angle) * k + (1 - np.cos(angle)) * (k @ k)


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


# ------------------------------------------------ UsdSkel characters, PointInstancers, layers (reading tests)
def grid(columns, rows, size_x, size_z, center=(0.0, 0.0, 0.0)):
    """(points float64[(c+1)(r+1), 3], faceVertexCounts, faceVertexIndices): quads in the XZ plane."""
    xs = np.linspace(-size_x / 2, size_x / 2, columns + 1)
    zs = np.linspace(-size_z / 2, size_z / 2, rows + 1)
    x, z = np.meshgrid(xs, zs)
    points = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1) + np.asarray(center, float)
    counts, indices = [], []
    for j in range(rows):
        for i in range(columns):
            a = j * (columns + 1) + i
            counts.append(4)
            indices += [a, a + 1, a + columns + 2, a + columns + 1]
    return points, counts, indices


def box(size=1.0):
    """(points float64[8, 3], counts, indices): a closed cube of edge ``size`` centred at the origin."""
    h = size / 2.0
    points = np.array([[x, y, z] for x in (-h, h) for y in (-h, h) for z in (-h, h)], float)
    faces = [[0, 1, 3, 2], [4, 6, 7, 5], [0, 4, 5, 1], [2, 3, 7, 6], [0, 2, 6, 4], [1, 5, 7, 3]]
    return points, [4] * 6, [i for face in faces for i in face]


def define_mesh(stage, path, points, counts, indices, samples=None):
    """A mesh with default ``points`` or with ``samples`` {time: points}."""
    mesh = UsdGeom.Mesh.Define(stage, path)
    mesh.CreateFaceVertexCountsAttr(Vt.IntArray([int(c) for c in counts]))
    mesh.CreateFaceVertexIndicesAttr(Vt.IntArray([int(i) for i in indices]))
    attribute = mesh.CreatePointsAttr()
    if samples:
        for time, value in samples.items():
            attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(value, np.float32)), float(time))
    else:
        attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(points, np.float32)))
    return mesh


def stretching_sheet(stage, path, size=6.0, columns=6, times=(1.0, 24.0), stretch=1.05):
    """A deforming cloth sheet in the plane y = 0: it stretches in X and Z (stays planar) between ``times``."""
    points, counts, indices = grid(columns, columns, size, size)
    return define_mesh(stage, path, None, counts, indices,
                       samples={times[0]: points, times[1]: points * [stretch, 1.0, stretch]})


# --------------------------------------------------------------------------------------------- UsdSkel

ARM_JOINTS = ["shoulder", "shoulder/elbow", "shoulder/elbow/wrist"]
ARM_LENGTH = 3.0


def _quat(axis, degrees):
    return Gf.Quatf(Gf.Rotation(Gf.Vec3d(*axis), degrees).GetQuat())


def skinned_arm(path, bend_degrees=((1.0, 0.0), (6.0, 40.0), (12.0, 95.0)), bulge_weights=((1.0, 0.0), (9.0, 1.0)),
                root_motion=((1.0, (0.0, 0.0, 0.0)), (12.0, (0.4, 0.0, 0.0))), with_sheet=True,
                rigid_bound_prop=False):
    """A skinned arm under a moving SkelRoot that bends down through a cloth sheet.

    Three joints along +X at y = 1.2 (shoulder, elbow at x = 1, wrist at x = 2); the arm is a strip of quads
    from x = 0 to 3, each vertex weighted between two joints (blended weights); the elbow bends about Z by
    the keys ``bend_degrees`` ((time, degrees), ...), sampled at every frame between the first and last key,
    bringing the forearm down through the sheet at y = 0;
    a blend shape ``bulge`` pushes the forearm's tip down, with weights animated by ``bulge_weights``; the
    SkelRoot translates by ``root_motion`` (samples at times that are also joint samples). ``with_sheet``
    adds a deforming sheet /World/Sheet at y = 0 under the forearm; ``rigid_bound_prop`` adds a small box
    bound to the wrist with constant (rigid) influences, above the arm. Returns {"arm": path, "sheet": path, ...}.
    """
    stage = new_stage(path)
    root = UsdSkel.Root.Define(stage, "/World/Character")
    translate = UsdGeom.Xformable(root).AddTranslateOp()
    for time, offset in root_motion:
        translate.Set(Gf.Vec3d(*offset), time)

    skeleton = UsdSkel.Skeleton.Define(stage, "/World/Character/Skel")
    skeleton.CreateJointsAttr(ARM_JOINTS)
    world_binds = [Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(x, 1.2, 0.0)) for x in (0.0, 1.0, 2.0)]
    skeleton.CreateBindTransformsAttr(Vt.Matrix4dArray(world_binds))
    rest = [Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(0.0, 1.2, 0.0))] + \
           [Gf.Matrix4d(1).SetTranslate(Gf.Vec3d(1.0, 0.0, 0.0))] * 2
    skeleton.CreateRestTransformsAttr(Vt.Matrix4dArray(rest))

    animation = UsdSkel.Animation.Define(stage, "/World/Character/Anim")
    animation.CreateJointsAttr(ARM_JOINTS)
    animation.CreateTranslationsAttr(Vt.Vec3fArray([(0.0, 1.2, 0.0), (1.0, 0.0, 0.0), (1.0, 0.0, 0.0)]))
    animation.CreateScalesAttr(Vt.Vec3hArray([(1, 1, 1)] * 3))
    rotations = animation.CreateRotationsAttr()
    key_times, key_degrees = np.array(bend_degrees, float).T
    for time in np.arange(key_times[0], key_times[-1] + 0.5):     # one sample per frame, as animators export
        degrees = float(np.interp(time, key_times, key_degrees))
        rotations.Set(Vt.QuatfArray([_quat((0, 0, 1), -0.25 * degrees), _quat((0, 0, 1), -degrees),
                                     _quat((0, 0, 1), -0.5 * degrees)]), float(time))
    animation.CreateBlendShapesAttr(["bulge"])
    weights = animation.CreateBlendShapeWeightsAttr()
    for time, weight in bulge_weights:
        weights.Set(Vt.FloatArray([weight]), time)
    UsdSkel.BindingAPI.Apply(skeleton.GetPrim()).CreateAnimationSourceRel().SetTargets([animation.GetPath()])

    columns = 12
    xs = np.linspace(0.0, ARM_LENGTH, columns + 1)
    points = np.array([[x, 1.2, z] for x in xs for z in (-0.15, 0.15)], float)
    counts = [4] * columns
    indices = [i for c in range(columns) for i in (2 * c, 2 * c + 2, 2 * c + 3, 2 * c + 1)]
    arm = define_mesh(stage, "/World/Character/Arm", points, counts, indices)
    binding = UsdSkel.BindingAPI.Apply(arm.GetPrim())
    binding.CreateSkeletonRel().SetTargets([skeleton.GetPath()])
    # each vertex blends the two joints around it: weight of the farther joint grows along the bone
    x = points[:, 0]
    lower = np.clip(np.floor(x), 0, 1).astype(int)                 # 0: shoulder..elbow, 1: elbow..wrist
    fraction = np.clip(x - lower, 0.0, 1.0) * np.where(x > 2.0, 1.0, 0.8)
    joint_indices = np.stack([lower, lower + 1], axis=1).ravel()
    joint_weights = np.stack([1.0 - fraction, fraction], axis=1).ravel()
    binding.CreateJointIndicesPrimvar(False, 2).Set(Vt.IntArray([int(i) for i in joint_indices]))
    binding.CreateJointWeightsPrimvar(False, 2).Set(Vt.FloatArray([float(w) for w in joint_weights]))
    binding.CreateGeomBindTransformAttr(Gf.Matrix4d(1))
    tip = np.flatnonzero(x >= 2.5)
    bulge = UsdSkel.BlendShape.Define(stage, "/World/Character/Arm/bulge")
    bulge.CreateOffsetsAttr(Vt.Vec3fArray([(0.0, -0.4, 0.0)] * tip.size))
    bulge.CreatePointIndicesAttr(Vt.IntArray([int(i) for i in tip]))
    binding.CreateBlendShapesAttr(["bulge"])
    binding.CreateBlendShapeTargetsRel().SetTargets([bulge.GetPath()])
    result = {"arm": "/World/Character/Arm", "skeleton": "/World/Character/Skel"}

    if rigid_bound_prop:
        prop_points, prop_counts, prop_indices = box(0.3)
        prop = define_mesh(stage, "/World/Character/Bracelet", prop_points + [2.2, 1.6, 0.0], prop_counts,
                           prop_indices)
        prop_binding = UsdSkel.BindingAPI.Apply(prop.GetPrim())
        prop_binding.CreateSkeletonRel().SetTargets([skeleton.GetPath()])
        prop_binding.CreateJointIndicesPrimvar(True, 1).Set(Vt.IntArray([2]))
        prop_binding.CreateJointWeightsPrimvar(True, 1).Set(Vt.FloatArray([1.0]))
        result["prop"] = "/World/Character/Bracelet"
    if with_sheet:
        stretching_sheet(stage, "/World/Sheet", size=8.0, columns=8, times=(1.0, 12.0))
        result["sheet"] = "/World/Sheet"
    stage.GetRootLayer().Save()
    return result


def baked_copy(source, target):
    """UsdSkel.BakeSkinning into a copy of ``source`` at ``target`` (the input is never opened for writing)."""
    shutil.copyfile(source, target)
    stage = Usd.Stage.Open(str(target))
    if not UsdSkel.BakeSkinning(stage.Traverse()):
        raise RuntimeError(f"UsdSkel.BakeSkinning failed on {target}")
    stage.GetRootLayer().Save()
    return target


def skinned_crowd(path):
    """Two instances of the skinned arm of :func:`skinned_arm`, the prototype of a PointInstancer, bend
    down through a deforming sheet at y = 0. The prototype ``/World/crowd/Prototypes/Character`` references
    the arm's SkelRoot from ``arm_asset.usda`` beside ``path`` (as a crowd asset is); instance 0 stands at
    (-1, 0, -2), instance 1 at (2.5, -0.1, 2) turned 180 degrees about Y. Unskinned, the arms would stay level
    at y >= 1.2 and never touch the sheet. Returns the instance mesh names."""
    asset = Path(path).parent / "arm_asset.usda"
    skinned_arm(asset, with_sheet=False)
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Sheet", size=8.0, columns=8, times=(1.0, 12.0))
    instancer = UsdGeom.PointInstancer.Define(stage, "/World/crowd")
    UsdGeom.Xform.Define(stage, "/World/crowd/Prototypes")
    prototype = stage.DefinePrim("/World/crowd/Prototypes/Character")
    prototype.GetReferences().AddReference(asset.name, "/World/Character")
    instancer.CreatePrototypesRel().SetTargets([prototype.GetPath()])
    instancer.CreateProtoIndicesAttr(Vt.IntArray([0, 0]))
    instancer.CreatePositionsAttr(Vt.Vec3fArray([(-1.0, 0.0, -2.0), (2.5, -0.1, 2.0)]))
    instancer.CreateOrientationsAttr(Vt.QuathArray([Gf.Quath(1.0), Gf.Quath(_quat((0, 1, 0), 180.0))]))
    stage.GetRootLayer().Save()
    return ["/World/crowd[0]/Character/Arm", "/World/crowd[1]/Character/Arm"]


# --------------------------------------------------------------------------------------------- PointInstancer

INSTANCE_DROP = {"start": 1.0, "end": 11.0}


def falling_instancer(path, velocities=None, invisible=(2,), inactive=(), proto_index_change=None,
                      sheet=True):
    """Instances of two prototypes fall straight down through a deforming sheet at y = 0.

    Prototype 0 is the mesh ``box`` (edge 0.5, its own translate op); prototype 1 is the Xform ``crate``
    with two meshes below (``crate/lid`` and ``crate/body/geo``, each with its own transform). The
    prototypes are authored under ``/World/scatter/Prototypes`` straddling y = 0 where they are, so a
    loader that checked them on their own would report contacts at the first sample. Instances have
    orientations and scales; ``invisible`` ids are in invisibleIds at every sample. Instance i starts at
    height ``start_heights[i]`` at time 1 and ends at -2 at time 11. ``velocities``: None (not authored),
    "consistent" (the finite differences of the positions, per second) or "zero".
    Returns the expected first-contact time of each visible instance with the plane y = 0 (closed form).
    """
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Sheet", size=12.0, columns=6, times=(1.0, 11.0)) if sheet else None
    instancer = UsdGeom.PointInstancer.Define(stage, "/World/scatter")
    UsdGeom.Xform.Define(stage, "/World/scatter/Prototypes")
    box_points, counts, indices = box(0.5)
    proto_box = define_mesh(stage, "/World/scatter/Prototypes/box", box_points, counts, indices)
    UsdGeom.Xformable(proto_box).AddTranslateOp().Set(Gf.Vec3d(0.0, 0.1, 0.0))   # the prototype root's own xform
    crate = UsdGeom.Xform.Define(stage, "/World/scatter/Prototypes/crate")
    UsdGeom.Xformable(crate).AddRotateYOp().Set(30.0)
    lid = define_mesh(stage, "/World/scatter/Prototypes/crate/lid", box_points * [1.2, 0.2, 1.2], counts, indices)
    UsdGeom.Xformable(lid).AddTranslateOp().Set(Gf.Vec3d(0.0, 0.35, 0.0))
    body = UsdGeom.Xform.Define(stage, "/World/scatter/Prototypes/crate/body")
    UsdGeom.Xformable(body).AddScaleOp().Set(Gf.Vec3f(1.0, 1.2, 1.0))
    define_mesh(stage, "/World/scatter/Prototypes/crate/body/geo", box_points, counts, indices)
    instancer.CreatePrototypesRel().SetTargets([proto_box.GetPath(), crate.GetPath()])

    xz = np.array([[-3.0, -3.0], [0.0, -3.0], [3.0, -3.0], [-3.0, 2.0], [2.0, 2.0]])
    start_heights = np.array([3.0, 2.0, 2.5, 1.5, 4.0])
    proto_indices = [0, 1, 0, 1, 0]
    orientations = [Gf.Quath(Gf.Rotation(Gf.Vec3d(1, 0, 1), angle).GetQuat())
                    for angle in (0.0, 25.0, 40.0, 60.0, 15.0)]
    scales = [(1.0, 1.0, 1.0), (1.5, 0.8, 1.5), (1.0, 1.0, 1.0), (0.7, 1.3, 0.7), (2.0, 2.0, 2.0)]
    instancer.CreateProtoIndicesAttr(Vt.IntArray(proto_indices))
    if proto_index_change is not None:
        time, index, prototype = proto_index_change
        changed = list(proto_indices)
        changed[index] = prototype
        instancer.GetProtoIndicesAttr().Set(Vt.IntArray(proto_indices), INSTANCE_DROP["start"])
        instancer.GetProtoIndicesAttr().Set(Vt.IntArray(changed), time)
    instancer.CreateOrientationsAttr(Vt.QuathArray(orientations))
    instancer.CreateScalesAttr(Vt.Vec3fArray(scales))
    positions = instancer.CreatePositionsAttr()
    start, end = INSTANCE_DROP["start"], INSTANCE_DROP["end"]
    end_height = -2.0
    for time, heights in ((start, start_heights), (end, np.full(5, end_height))):
        positions.Set(Vt.Vec3fArray([(float(x), float(h), float(z)) for (x, z), h in zip(xz, heights)]), time)
    if velocities is not None:
        per_second = (end_height - start_heights) / (end - start) * stage.GetTimeCodesPerSecond()
        value = per_second if velocities == "consistent" else np.zeros(5)
        vectors = Vt.Vec3fArray([(0.0, float(v), 0.0) for v in value])
        for time in (start, end):
            instancer.CreateVelocitiesAttr().Set(vectors, time)
    if invisible:
        instancer.CreateInvisibleIdsAttr().Set(Vt.Int64Array(list(invisible)), start)
        instancer.GetInvisibleIdsAttr().Set(Vt.Int64Array(list(invisible)), end)
    for index in inactive:
        instancer.DeactivateId(index)
    stage.GetRootLayer().Save()

    # closed form: the lowest world point of instance i is height_i(t) + lowest offset of its prototype
    xforms = np.array(instancer.ComputeInstanceTransformsAtTime(
        Usd.TimeCode(start), Usd.TimeCode(start), UsdGeom.PointInstancer.IncludeProtoXform,
        UsdGeom.PointInstancer.IgnoreMask))
    lowest = {}
    for i, prototype in enumerate(proto_indices):
        if i in invisible or i in inactive:
            continue
        if prototype == 0:
            local = [box_points]
        else:
            local = [box_points * [1.2, 0.2, 1.2] + [0.0, 0.35, 0.0], box_points * [1.0, 1.2, 1.0]]
        offsets = min(float(((np.hstack([p, np.ones((8, 1))]) @ xforms[i])[:, 1] - start_heights[i]).min())
                      for p in local)
        lowest[i] = offsets
    expected = {}
    for i, offset in lowest.items():
        # height(t) = h0 + (end_height - h0) (t - start) / (end - start); contact when height + offset = 0
        h0 = start_heights[i]
        expected[i] = start + (-offset - h0) / (end_height - h0) * (end - start)
    return expected


# --------------------------------------------------------------------------------------------- placeholders, scope, layers

EMPTY_KINDS = ("no points", "no faces", "only degenerate faces")


def shot_with_empty_mesh(path, empty_kind, contact=True):
    """A deforming sheet, a falling box that passes through it (``contact``) or stays above, and an empty
    placeholder mesh /World/Layout/Placeholder of ``empty_kind`` (one of EMPTY_KINDS)."""
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Sheet")
    points, counts, indices = box(0.5)
    end = -1.0 if contact else 0.5
    define_mesh(stage, "/World/Box", None, counts, indices,
                samples={1.0: points + [0.0, 1.0, 0.0], 24.0: points + [0.0, end, 0.0]})
    UsdGeom.Xform.Define(stage, "/World/Layout")
    placeholder = "/World/Layout/Placeholder"
    if empty_kind == "no points":
        define_mesh(stage, placeholder, np.zeros((0, 3)), [], [])
    elif empty_kind == "no faces":
        define_mesh(stage, placeholder, points, [], [])
    else:   # two-vertex "faces": nothing to triangulate
        define_mesh(stage, placeholder, points, [2, 2], [0, 1, 2, 3])
    stage.GetRootLayer().Save()
    return placeholder


def rigid_bodies_and_cloth(path):
    """Two rigid boxes (only their transforms animate) that collide with each other, a static floor box one
    of them reaches, and a deforming cloth that one box falls through. Returns the mesh paths."""
    stage = new_stage(path)
    stretching_sheet(stage, "/World/Cloth", size=3.0, columns=3)
    points, counts, indices = box(1.0)
    # BoxA falls through the cloth onto the floor; BoxB slides across at y = 1 and meets BoxA on its way down
    for name, start, end in (("BoxA", (0.0, 2.0, 0.0), (0.0, -1.5, 0.0)), ("BoxB", (3.0, 1.0, 0.0), (-3.0, 1.0, 0.0))):
        mover = UsdGeom.Xform.Define(stage, f"/World/{name}")
        translate = mover.AddTranslateOp()
        translate.Set(Gf.Vec3d(*start), 1.0)
        translate.Set(Gf.Vec3d(*end), 24.0)
        define_mesh(stage, f"/World/{name}/geo", points, counts, indices)
    define_mesh(stage, "/World/Floor", points * [8.0, 0.2, 8.0] + [0.0, -1.9, 0.0], counts, indices)
    stage.GetRootLayer().Save()
    return {"cloth": "/World/Cloth", "a": "/World/BoxA/geo", "b": "/World/BoxB/geo", "floor": "/World/Floor"}


def wrapper_around_cache(directory, cache_rate=30.0, wrapper_rate=None, reference=False):
    """A cache layer at ``cache_rate`` time codes per second with a falling quad through a deforming sheet
    (samples at 10 and 20), and a wrapper layer that sublayers (or, with ``reference``, references) it and
    authors ``wrapper_rate`` (None: no rate at all, USD then assumes 24). Returns (wrapper path, cache path)."""
    directory = Path(directory)
    cache_path = directory / "cache.usda"
    cache = Usd.Stage.CreateNew(str(cache_path))
    cache.SetTimeCodesPerSecond(cache_rate)
    cache.SetFramesPerSecond(cache_rate)
    UsdGeom.Xform.Define(cache, "/World")
    stretching_sheet(cache, "/World/Sheet", times=(10.0, 20.0))
    points, counts, indices = box(0.5)
    define_mesh(cache, "/World/Box", None, counts, indices,
                samples={10.0: points + [0.0, 1.0, 0.0], 20.0: points + [0.0, -1.0, 0.0]})
    cache.GetRootLayer().Save()
    wrapper_path = directory / "shot.usda"
    wrapper = Sdf.Layer.CreateNew(str(wrapper_path))
    if wrapper_rate is not None:
        wrapper.timeCodesPerSecond = wrapper_rate
    if reference:
        stage = Usd.Stage.Open(wrapper)
        stage.DefinePrim("/World").GetReferences().AddReference("./cache.usda", "/World")
    else:
        wrapper.subLayerPaths.append("./cache.usda")
    wrapper.Save()
    return wrapper_path, cache_path


#: The time codes of :func:`resting_sheets` (a sample every frame) and when its sheets come to rest.
RESTING_SHEETS_TIMES = [float(t) for t in range(1, 25)]
RESTING_SHEETS_REST = 11.0


def resting_sheets(path, bad=None):
    """Two 3x3 sheets, each falling onto a floor of its own (y = (11 - t) / 10) and resting there from t = 11, a
    sample every frame 1..24; ``bad`` {time: 'empty' | 'block'} spoils samples of /World/Cloth only."""
    stage = new_stage(path, start=1.0, end=24.0)
    for name, x in (("Cloth", 0.0), ("Other", 10.0)):
        points, counts, indices = grid(3, 3, 2.0, 2.0, center=(x, 0.0, 0.0))
        floor, floor_counts, floor_indices = grid(1, 1, 4.0, 4.0, center=(x, 0.0, 0.0))
        define_mesh(stage, f"/World/{name}Floor", floor, floor_counts, floor_indices)
        samples = {t: points + [0.0, max(0.0, (RESTING_SHEETS_REST - t) / 10.0), 0.0] for t in RESTING_SHEETS_TIMES}
        mesh = define_mesh(stage, f"/World/{name}", None, counts, indices, samples=samples)
        if name == "Cloth":
            for time, kind in (bad or {}).items():
                mesh.GetPointsAttr().Set(Sdf.ValueBlock() if kind == "block" else Vt.Vec3fArray(), time)
    stage.GetRootLayer().Save()
    return str(path)
