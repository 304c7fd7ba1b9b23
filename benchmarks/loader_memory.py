"""Peak memory of the loader as a multiple of the point data it returns.

    python benchmarks/loader_memory.py [--triangles 12800] [--samples 150]

Writes a one-mesh .usdc cache (the `swirl` scene of samples/generate.py: an 80 x 80 quad
sheet = 12,800 triangles, one keyframe per sample) into a temporary folder, then loads it
in a fresh interpreter and reports, relative to the bytes of the final float64 points
array (K x N x 3 x 8):

- tracemalloc peak during load_shot (numpy and Python allocations),
- peak RSS after load_shot (ru_maxrss) minus the RSS just before it (everything, USD's own
  buffers and the stage the Shot keeps open included).

Target: a small multiple (<= 3x). Ratios, not absolute numbers, are what to compare.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import resource
import subprocess
import sys
import tempfile
import time

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
TARGET_MULTIPLE = 3.0


def _max_rss_bytes() -> int:
    # Linux reports kilobytes, macOS bytes
    scale = 1 if sys.platform == "darwin" else 1024
    return resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * scale


def _current_rss_bytes() -> int:
    """Resident set size now (Linux /proc); falls back to the peak so far elsewhere."""
    try:
        with open("/proc/self/status") as status:
            for line in status:
                if line.startswith("VmRSS:"):
                    return int(line.split()[1]) * 1024
    except OSError:
        pass
    return _max_rss_bytes()


def measure(path: str) -> dict:
    """Runs in a fresh interpreter so ru_maxrss starts from the imports only."""
    import tracemalloc

    import numpy as np  # noqa: F401
    from pxr import Usd, UsdGeom  # noqa: F401

    from usdksl.reading.loader import load_shot

    rss_before = _current_rss_bytes()
    tracemalloc.start()
    started = time.perf_counter()
    shot = load_shot(path)
    seconds = time.perf_counter() - started
    _, traced_peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    rss_after = _max_rss_bytes()
    points_bytes = sum(mesh.points.nbytes for mesh in shot.meshes)
    return {
        "meshes": len(shot.meshes),
        "triangles": sum(mesh.triangle_count for mesh in shot.meshes),
        "samples": int(shot.times.size),
        "vertices": sum(mesh.vertex_count for mesh in shot.meshes),
        "points_bytes": points_bytes,
        "file_bytes": os.path.getsize(path),
        "traced_peak_bytes": traced_peak,
        "rss_rise_bytes": rss_after - rss_before,
        "load_seconds": seconds,
    }


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--triangles", type=int, default=12800)
    parser.add_argument("--samples", type=int, default=150)
    parser.add_argument("--measure", help=argparse.SUPPRESS)
    args = parser.parse_args(argv)
    if args.measure:
        print(json.dumps(measure(args.measure)))
        return 0

    sys.path.insert(0, os.path.join(REPO, "samples"))
    import generate

    side = int(round(math.sqrt(args.triangles / 2)))
    with tempfile.TemporaryDirectory(prefix="usdksl-loader-memory-") as folder:
        path = os.path.join(folder, "cache.usdc")
        generate.generate("swirl", side * side, keyframes=args.samples, samples_per_keyframe=1,
                          seed=11, out=path)
        output = subprocess.run([sys.executable, os.path.abspath(__file__), "--measure", path],
                                check=True, capture_output=True, text=True).stdout
    result = json.loads(output.strip().splitlines()[-1])
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
