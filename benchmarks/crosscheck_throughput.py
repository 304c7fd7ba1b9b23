"""Throughput of the Embree cross-check: face-frames per second on a generated sheet.

    python benchmarks/crosscheck_throughput.py [--faces 10000] [--frames 50]

A waving sheet of about ``--faces`` quads (two triangles each) over ``--frames`` samples, with a rigid
box falling through it, is cross-checked frame by frame (library call, no USD file). Prints the
face-frames per second of the whole cross-check, the share of time spent inside Embree casting rays and
the ratio against a reading-only pass over the same frames (interpolating and concatenating the points),
all measured in this one run (wall time, benchmarks/harness.py).
"""

import argparse

import numpy as np

import usdksl.crosscheck.embree_frames as embree_frames
from usdksl.contacts.table import ContactTable
from usdksl.crosscheck.shot import crosscheck_shot, points_at
from usdksl.reading.loader import MeshData, Shot

from harness import Stopwatch, call


def sheet_mesh(faces: int, frames: int) -> MeshData:
    side = int(round(np.sqrt(faces)))
    ticks = np.linspace(0.0, 1.0, side + 1)
    x, y = np.meshgrid(ticks, ticks)
    times = np.arange(frames, dtype=np.float64)
    wave = 0.05 * np.sin(2 * np.pi * (x.ravel()[None, :] * 2 + times[:, None] / frames))
    points = np.empty((frames, x.size, 3))
    points[:, :, 0], points[:, :, 1], points[:, :, 2] = x.ravel(), y.ravel(), wave
    ids = np.arange((side + 1) ** 2).reshape(side + 1, side + 1)
    a, b, c, d = ids[:-1, :-1].ravel(), ids[:-1, 1:].ravel(), ids[1:, 1:].ravel(), ids[1:, :-1].ravel()
    triangles = np.concatenate([np.stack([a, b, c], 1), np.stack([a, c, d], 1)]).astype(np.int32)
    face = np.concatenate([np.arange(len(a)), np.arange(len(a))]).astype(np.int32)
    return MeshData("/Sheet", times, np.ascontiguousarray(points), triangles, face, len(a), "deforming")


def box_mesh(frames: int) -> MeshData:
    corners = np.array([[x, y, z] for z in (0, 1) for y in (0, 1) for x in (0, 1)], float) * 0.3 + 0.35
    quads = np.array([[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]])
    triangles = np.concatenate([quads[:, [0, 1, 2]], quads[:, [0, 2, 3]]]).astype(np.int32)
    face = np.concatenate([np.arange(6), np.arange(6)]).astype(np.int32)
    times = np.arange(frames, dtype=np.float64)
    drop = np.linspace(0.8, -0.8, frames)
    points = corners[None, :, :] + np.stack([np.zeros(frames), np.zeros(frames), drop], 1)[:, None, :]
    return MeshData("/Box", times, np.ascontiguousarray(points), triangles, face, 6, "rigid")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--faces", type=int, default=10000)
    parser.add_argument("--frames", type=int, default=50)
    arguments = parser.parse_args()
    meshes = [sheet_mesh(arguments.faces, arguments.frames), box_mesh(arguments.frames)]
    shot = Shot("generated", meshes, meshes[0].times.copy(), {}, None)
    no_contacts = ContactTable.empty([mesh.path for mesh in meshes])

    with Stopwatch() as watch:
        watch.wrap(embree_frames, "_cast_all_hits", "casting")
        checked = call(crosscheck_shot, shot, contacts=no_contacts)
    result, seconds = checked.value, checked.wall_s
    cast_seconds = watch.seconds.get("casting", 0.0)

    def read_frames():
        for frame in shot.times:
            np.concatenate([points_at(mesh, float(frame)) for mesh in meshes]).astype(np.float32)

    reading = call(read_frames).wall_s

    face_frames = result.counters["face_frames"]
    triangles = sum(mesh.triangle_count for mesh in meshes)
    print(f"sheet {meshes[0].face_count} quads + box, {triangles} triangles, {len(result.frames)} frames")
    print(f"cross-check: {seconds:.3f} s, {face_frames / seconds:,.0f} face-frames/s, "
          f"{triangles * len(result.frames) / seconds:,.0f} triangle-frames/s")
    print(f"rays cast {result.counters['rays_cast']:,}, rounds {result.counters['cast_rounds']}, "
          f"Embree hits {result.counters['embree_hits']:,}, candidates {result.counters['candidates']:,}, "
          f"unconfirmed {result.counters['unconfirmed_candidates']:,}, truncated rays "
          f"{result.counters['rays_truncated']}")
    print(f"intersecting face pair-frames {len(result.time):,} ({result.face_pairs} distinct pairs)")
    print(f"share of time casting rays in Embree: {cast_seconds / seconds:.2f}")
    print(f"cross-check / reading the frames alone: {seconds / reading:.1f}x")


if __name__ == "__main__":
    main()
