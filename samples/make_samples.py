"""Write the small shots shipped in samples/ (deterministic: same bytes on every run).

    python samples/make_samples.py [--out DIR]

- drape.usda        a 20x20 cloth sheet falls onto a static box and drapes over it; near the
                    end a small dent in the middle of the sheet dips into the box top (inter).
- fold.usda         a 20x8 strip folds over onto itself and slightly past flat, so its tip
                    passes through the lower half near the end (self).
- pass_through.usda a box, moved rigidly by an animated translate on its parent Xform, passes
                    through a waving wall (inter; the box is rigid, the wall deforms).
- clean.usda        a waving sheet above a static box and a rigid box moving far away: no
                    contacts at all.

All shots: 24 time codes per second, Y up, metres, defaultPrim /World.
"""

from __future__ import annotations

import argparse
import math
import os
import sys

import numpy as np
from pxr import Gf, UsdGeom

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shotwriter import box, define_mesh, grid, layer_comment, new_stage, save, smoothstep  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))


def make_drape(path: str) -> None:
    first, last = 1.0, 24.0
    box_half = 0.5          # box spans [-0.5, 0.5]^3, so its top is at y = 0.5
    rest_gap = 0.005        # the sheet rests this far above the top
    hang_slope = 1.5        # how steeply the sheet hangs past the box edge
    edge_margin = 0.1       # one grid cell: the sheet leaves the top before it hangs down
    dent_depth, dent_radius = 0.02, 0.1
    start_height = 2.0

    stage = new_stage(path, first, last)
    layer_comment(stage, "usdksl sample: cloth draping over a box; contacts near the end")
    points, counts, indices = grid(20, 20, 2.0, 2.0)
    x, z = points[:, 0], points[:, 2]
    overhang = np.maximum(np.maximum(np.abs(x), np.abs(z)) - box_half - edge_margin, 0.0)
    rest = box_half + rest_gap - hang_slope * overhang
    rest -= dent_depth * np.exp(-(x * x + z * z) / (2 * dent_radius ** 2))
    settle_time = 20.0
    gravity = (start_height - rest.min()) / (settle_time - first) ** 2
    samples = {}
    for time in np.arange(first, last + 1):
        falling = start_height - gravity * (time - first) ** 2
        frame = points.copy()
        frame[:, 1] = np.maximum(rest, falling)
        samples[float(time)] = frame
    define_mesh(stage, "/World/Cloth", counts, indices, samples=samples, color=(0.8, 0.3, 0.3))
    box_points, box_counts, box_indices = box((0, 0, 0), (box_half,) * 3)
    define_mesh(stage, "/World/Box", box_counts, box_indices, points=box_points,
                color=(0.5, 0.5, 0.5))
    save(stage)


def fold_shape(columns_x: np.ndarray, angle: float, radius: float) -> np.ndarray:
    """(x, y) of a strip bent around a cylinder of ``radius`` at x = 0 by ``angle`` radians.

    Points with x <= 0 stay flat; x > 0 is arc length along the bend, then along its tangent.
    """
    s = np.maximum(columns_x, 0.0)
    arc = radius * angle
    on_arc = s < arc
    phi = np.where(on_arc, s / radius, angle)
    along = np.where(on_arc, 0.0, s - arc)
    x = radius * np.sin(phi) + along * np.cos(angle)
    y = radius * (1.0 - np.cos(phi)) + along * np.sin(angle)
    x = np.where(columns_x <= 0.0, columns_x, x)
    y = np.where(columns_x <= 0.0, 0.0, y)
    return np.stack([x, y], axis=1)


def make_fold(path: str) -> None:
    first, last = 1.0, 36.0
    bend_radius = 0.08
    overfold = 0.35         # radians past flat: the tip dips through the lower half
    stage = new_stage(path, first, last)
    layer_comment(stage, "usdksl sample: a strip folding onto itself; self contacts near the end")
    points, counts, indices = grid(20, 8, 2.0, 0.8)
    samples = {}
    for time in np.arange(first, last + 1):
        angle = (math.pi + overfold) * float(smoothstep((time - first) / (last - first)))
        frame = points.copy()
        frame[:, :2] = fold_shape(points[:, 0], angle, bend_radius)
        samples[float(time)] = frame
    define_mesh(stage, "/World/Strip", counts, indices, samples=samples, color=(0.2, 0.5, 0.8))
    save(stage)


def make_pass_through(path: str) -> None:
    first, last = 1.0, 24.0
    stage = new_stage(path, first, last)
    layer_comment(stage, "usdksl sample: a rigidly moving box passes through a waving wall")
    points, counts, indices = grid(8, 8, 1.6, 1.6)
    wall = points[:, [1, 0, 2]]   # the XZ grid turned into the YZ plane
    samples = {}
    for time in np.arange(first, last + 1):
        frame = wall.copy()
        frame[:, 0] = 0.05 * np.sin(2 * math.pi * frame[:, 1] / 1.6 + 0.3 * time)
        samples[float(time)] = frame
    define_mesh(stage, "/World/Wall", counts, indices, samples=samples, color=(0.6, 0.6, 0.2))

    mover = UsdGeom.Xform.Define(stage, "/World/Mover")
    translate = mover.AddTranslateOp()
    translate.Set(Gf.Vec3d(-1.5, 0.1, 0.0), first)
    translate.Set(Gf.Vec3d(1.5, 0.1, 0.0), last)
    box_points, box_counts, box_indices = box((0, 0, 0), (0.25, 0.25, 0.25))
    define_mesh(stage, "/World/Mover/Box", box_counts, box_indices, points=box_points,
                color=(0.2, 0.7, 0.3))
    save(stage)


def make_clean(path: str) -> None:
    first, last = 1.0, 24.0
    stage = new_stage(path, first, last)
    layer_comment(stage, "usdksl sample: moving meshes that never touch (exit code 0)")
    points, counts, indices = grid(10, 10, 1.0, 1.0)
    samples = {}
    for time in np.arange(first, last + 1):
        frame = points.copy()
        frame[:, 1] = 1.2 + 0.05 * np.sin(3.0 * frame[:, 0] + 0.25 * time)
        samples[float(time)] = frame
    define_mesh(stage, "/World/Sheet", counts, indices, samples=samples, color=(0.8, 0.5, 0.2))
    box_points, box_counts, box_indices = box((0, 0, 0), (0.5, 0.5, 0.5))
    define_mesh(stage, "/World/Box", box_counts, box_indices, points=box_points,
                color=(0.5, 0.5, 0.5))
    mover = UsdGeom.Xform.Define(stage, "/World/Mover")
    translate = mover.AddTranslateOp()
    translate.Set(Gf.Vec3d(3.0, 0.0, -1.0), first)
    translate.Set(Gf.Vec3d(3.0, 0.0, 1.0), last)
    rotate = mover.AddRotateYOp()
    for time in np.arange(first, last + 1, 4.0):
        rotate.Set(float(15.0 * (time - first)), float(time))
    small_points, small_counts, small_indices = box((0, 0, 0), (0.3, 0.3, 0.3))
    define_mesh(stage, "/World/Mover/Box", small_counts, small_indices, points=small_points,
                color=(0.2, 0.7, 0.3))
    save(stage)


SHOTS = {
    "drape.usda": make_drape,
    "fold.usda": make_fold,
    "pass_through.usda": make_pass_through,
    "clean.usda": make_clean,
}


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", default=HERE, help="folder to write the shots to (default: samples/)")
    args = parser.parse_args(argv)
    os.makedirs(args.out, exist_ok=True)
    for name, make in SHOTS.items():
        path = os.path.join(args.out, name)
        make(path)
        print(f"{path}: {os.path.getsize(path) / 1024:.0f} KiB")
    return 0


if __name__ == "__main__":
    sys.exit(main())
