"""Peak memory of the loader as a multiple of the point data it returns.

    python benchmarks/loader_memory.py [--triangles 12800] [--samples 150]

Writes a one-mesh .usdc cache (the `swirl` scene of samples/generate.py: an 80 x 80 quad
sheet = 12,800 triangles, one keyframe per sample) into a temporary folder, then loads it
in a fresh interpreter (benchmarks/harness.py) and reports, relative to the bytes of the final
float64 points array (K x N x 3 x 8):

- tracemalloc peak during load_shot (numpy and Python allocations),
- peak RSS during load_shot minus the RSS just before it (everything, USD's own buffers and the
  stage the Shot keeps open included).

Target: a small multiple (<= 3x). Ratios, not absolute numbers, are what to compare.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import tempfile

from harness import call_fresh, measuring

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET_MULTIPLE = 3.0


def measure(path: str) -> dict:
    """Runs in a fresh interpreter, with the imports done before the load is measured."""
    import tracemalloc

    import numpy as np  # noqa: F401
    from pxr import Usd, UsdGeom  # noqa: F401

    import usdksl

    with measuring() as measured:
        tracemalloc.start()
        shot = usdksl.load_shot(path)
        _, traced_peak = tracemalloc.get_traced_memory()
        tracemalloc.stop()
    points_bytes = sum(mesh.points.nbytes for mesh in shot.meshes)
    return {
        "meshes": len(shot.meshes),
        "triangles": sum(mesh.triangle_count for mesh in shot.meshes),
        "samples": int(shot.times.size),
        "vertices": sum(mesh.vertex_count for mesh in shot.meshes),
        "points_bytes": points_bytes,
        "file_bytes": os.path.getsize(path),
        "traced_peak_bytes": traced_peak,
        "rss_rise_bytes": measured.peak_rise_bytes,
        "load_seconds": measured.wall_s,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=12800)
    parser.add_argument("--samples", type=int, default=150)
    args = parser.parse_args(argv)

    sys.path.insert(0, os.path.join(REPO, "samples"))
    import generate

    side = int(round(math.sqrt(args.triangles / 2)))
    with tempfile.TemporaryDirectory(prefix="usdksl-loader-memory-") as folder:
        path = os.path.join(folder, "cache.usdc")
        generate.generate("swirl", side * side, keyframes=args.samples, samples_per_keyframe=1,
                          seed=11, out=path)
        measured = call_fresh(measure, path)
    if measured.error:
        raise RuntimeError(f"loading {path} failed: {measured.error}\n{measured.stderr}")
    result = measured.value
    mib = 2.0 ** 20
    points = result["points_bytes"]
    traced = result["traced_peak_bytes"] / points
    rss = result["rss_rise_bytes"] / points
    print(f"cache: {result['meshes']} mesh, {result['triangles']} triangles, {result['vertices']} "
          f"vertices, {result['samples']} samples, file {result['file_bytes'] / mib:.1f} MiB")
    print(f"final points array (float64): {points / mib:.1f} MiB; load {result['load_seconds']:.2f} s")
    print(f"tracemalloc peak during load: {result['traced_peak_bytes'] / mib:.1f} MiB = {traced:.2f}x points")
    print(f"peak RSS rise during load:    {result['rss_rise_bytes'] / mib:.1f} MiB = {rss:.2f}x points")
    verdict = "within" if max(traced, rss) <= TARGET_MULTIPLE else "ABOVE"
    print(f"{verdict} the {TARGET_MULTIPLE:g}x target")
    return 0


if __name__ == "__main__":
    sys.exit(main())
