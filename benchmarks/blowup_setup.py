"""The blown-up vertex both blow-up benchmarks share: its arguments, where it sits, its moved samples.

A simulation blow-up is one vertex of the shot's first deforming mesh thrown to y = H at one sample;
benchmarks/blowup.py measures what it costs the whole check, benchmarks/blowup_ccd.py what it costs
each narrow-phase query.
"""

from __future__ import annotations

import argparse
import dataclasses

import numpy as np

#: Heights (scene units, y) the vertex is thrown to, unless --heights says otherwise.
DEFAULT_HEIGHTS = [1e3, 1e5, 1e7, 1e9]


def add_blowup_arguments(parser: argparse.ArgumentParser, default_shot: str) -> None:
    """SHOT, --vertex, --time and --heights."""
    parser.add_argument("shot", nargs="?", default=default_shot)
    parser.add_argument("--vertex", type=int, default=None, help="vertex to blow up (default: the middle one)")
    parser.add_argument("--time", type=float, default=None, help="sample to blow it up at (default: middle sample)")
    parser.add_argument("--heights", type=float, nargs="+", default=list(DEFAULT_HEIGHTS))


@dataclasses.dataclass(frozen=True)
class BlowupTarget:
    """Vertex `vertex` of mesh `mesh_index` (the shot's first deforming mesh) at sample index `sample`."""

    mesh_index: int
    mesh: object
    vertex: int
    sample: int

    def blown_points(self, height: float) -> np.ndarray:
        """The mesh's points (samples, vertices, 3) with the vertex at y = `height` at the sample."""
        points = self.mesh.points.copy()
        points[self.sample, self.vertex, 1] = height
        return points


def blowup_target(meshes, args: argparse.Namespace) -> BlowupTarget:
    """The vertex given by --vertex (default: the middle one) at the sample nearest --time (default: the middle)."""
    mesh_index = next(i for i, mesh in enumerate(meshes) if mesh.kind == "deforming")
    mesh = meshes[mesh_index]
    vertex = mesh.vertex_count // 2 if args.vertex is None else args.vertex
    sample = (mesh.sample_count // 2 if args.time is None
              else int(np.argmin(np.abs(mesh.times - args.time))))
    return BlowupTarget(mesh_index, mesh, vertex, sample)
