"""The scene the report tests draw: a sheet and two boxes that pass down through it at two places, as
MeshData arrays (no USD), its real contacts from the continuous check, and a RegionTable built by hand from
the closed-form depth (one region per box).

The sheet is 6 x 6 units of 24 x 24 quads in the XZ plane at y = 0, static. Each box is a closed cube of
4 x 4 quads a side moving straight down (y); while its centre is at height c the sheet crosses it over its
whole footprint, so its penetration depth is ``edge / 2 - |c|`` (0 outside) and the intersection curve is
the footprint's outline, ``4 * edge`` long.
"""

from typing import List

import numpy as np

from usdksl.checking.collision import find_contacts
from usdksl.contacts.table import ContactTable
from usdksl.reading.meshes import MeshData
from usdksl.regions.table import PENETRATION, RegionTable

SHEET = "/World/Sheet"
BIG_BOX = "/World/Box"
SMALL_BOX = "/World/SmallBox"
SHEET_SIZE, SHEET_QUADS = 6.0, 24
#: The boxes: path, edge, (x, z) of the centre, sample times, centre heights at those times.
BOXES = ((BIG_BOX, 1.0, (-1.4, -0.9), (1.0, 3.0, 5.0, 7.0), (1.0, 0.5, 0.0, -1.2)),
         (SMALL_BOX, 0.5, (1.8, 1.8), (1.0, 4.0, 6.0), (0.6, 0.2, -0.2)))
#: The checked span (time codes).
SPAN = (1.0, 7.0)


def quads_to_mesh(path, times, points, quads, kind) -> MeshData:
    """MeshData of quads (int[F, 4]) split into two triangles each; face f is quad f."""
    quads = np.asarray(quads, dtype=np.int32)
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]])
    faces = np.concatenate([np.arange(len(quads)), np.arange(len(quads))]).astype(np.int32)
    order = np.argsort(faces, kind="stable")
    return MeshData(path=path, times=np.asarray(times, dtype=np.float64),
                    points=np.ascontiguousarray(points, dtype=np.float64), triangles=triangles[order],
                    triangle_face=faces[order], face_count=len(quads), kind=kind)


def grid_quads(columns, rows, offset=0):
    ids = np.arange((rows + 1) * (columns + 1)).reshape(rows + 1, columns + 1) + offset
    return np.stack([ids[:-1, :-1], ids[1:, :-1], ids[1:, 1:], ids[:-1, 1:]], axis=-1).reshape(-1, 4)


def sheet() -> MeshData:
    x, z = np.meshgrid(np.linspace(-SHEET_SIZE / 2, SHEET_SIZE / 2, SHEET_QUADS + 1),
                       np.linspace(-SHEET_SIZE / 2, SHEET_SIZE / 2, SHEET_QUADS + 1))
    points = np.stack([x.ravel(), np.zeros(x.size), z.ravel()], axis=1)
    return quads_to_mesh(SHEET, [SPAN[0]], points[None], grid_quads(SHEET_QUADS, SHEET_QUADS), "static")


def cube(edge, quads_per_side=4):
    """(points[N, 3], quads[F, 4]): a closed cube of ``edge`` centred at the origin, its corners shared."""
    u, v = np.meshgrid(np.linspace(-0.5, 0.5, quads_per_side + 1), np.linspace(-0.5, 0.5, quads_per_side + 1))
    u, v = u.ravel(), v.ravel()
    half = np.full(u.size, 0.5)
    sides = [np.stack(axes, axis=1) for axes in
             ((half, u, v), (-half, v, u), (u, half, v), (v, -half, u), (u, v, half), (v, u, -half))]
    points = np.concatenate(sides) * edge
    quads = np.concatenate([grid_quads(quads_per_side, quads_per_side, k * u.size) for k in range(6)])
    welded, inverse = np.unique(np.round(points, 9), axis=0, return_inverse=True)
    return welded, inverse.reshape(-1)[quads]


def box(path, edge, xz, times, heights) -> MeshData:
    points, quads = cube(edge)
    centres = np.array([[xz[0], height, xz[1]] for height in heights])
    return quads_to_mesh(path, times, points[None] + centres[:, None], quads, "rigid")


def scene() -> List[MeshData]:
    """[big box, sheet, small box]."""
    return [box(*BOXES[0]), sheet(), box(*BOXES[1])]


def contacts(meshes) -> ContactTable:
    """The real first contacts of each box with the sheet."""
    return find_contacts(meshes, [(0, 1), (1, 2)]).face_contacts(meshes)


def _centre_height(spec, times):
    return np.interp(times, spec[3], spec[4])


def hand_regions(meshes, table: ContactTable) -> RegionTable:
    """One region per box holding all its contact rows, depth and boxes from the closed form at the shot's
    samples; regions numbered by earliest contact."""
    samples = np.unique(np.concatenate([m.times for m in meshes]))
    samples = samples[(samples >= SPAN[0]) & (samples <= SPAN[1])]
    specs = [BOXES[0], BOXES[1]]
    row_box = np.where((table.mesh_a == 2) | (table.mesh_b == 2), 1, 0)      # 0: the big box, 1: the small one
    first = np.array([table.time[row_box == k].min() for k in range(2)])
    order = np.argsort(first, kind="stable")          # region row r holds box order[r]
    rank = np.argsort(order)
    columns = {name: [] for name in ("mesh_a", "mesh_b", "last", "depth", "depth_time", "length", "low", "high")}
    for k in order:
        _, edge, xz, _, _ = specs[k]
        rows = row_box == k
        heights = _centre_height(specs[k], samples)
        depth = np.maximum(edge / 2 - np.abs(heights), 0.0)
        deepest = int(np.argmax(depth))
        crossing = np.abs(heights) <= edge / 2
        columns["mesh_a"].append(int(table.mesh_a[rows][0]))
        columns["mesh_b"].append(int(table.mesh_b[rows][0]))
        columns["last"].append(float(samples[crossing].max()))
        columns["depth"].append(float(depth[deepest]))
        columns["depth_time"].append(float(samples[deepest]))
        columns["length"].append(4.0 * edge)
        columns["low"].append([xz[0] - edge / 2, 0.0, xz[1] - edge / 2])
        columns["high"].append([xz[0] + edge / 2, 0.0, xz[1] + edge / 2])
    low, high = np.array(columns["low"]), np.array(columns["high"])
    return RegionTable(
        paths=table.paths, mesh_a=np.array(columns["mesh_a"], np.int32), mesh_b=np.array(columns["mesh_b"], np.int32),
        first_time=first[order], last_time=np.array(columns["last"]),
        face_pairs=np.array([np.count_nonzero(row_box == k) for k in order], np.int64),
        depth_measure=np.array([PENETRATION, PENETRATION], dtype=object), max_depth=np.array(columns["depth"]),
        max_depth_time=np.array(columns["depth_time"]), max_intersection_length=np.array(columns["length"]),
        center=(low + high) / 2, box_min=low, box_max=high, row_region=rank[row_box].astype(np.int32))
