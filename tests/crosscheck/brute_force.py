"""The cross-check tests' oracle: every intersecting triangle pair of a frame by brute force."""

import numpy as np

from usdksl.crosscheck.segment_crossing import segments_cross_triangles


def brute_force_pairs(topology, vertices, allowed=None):
    """Every (triangle, triangle) pair where an edge of one properly crosses the other, the edge sharing
    no vertex with the triangle: all edge x triangle combinations, no acceleration (chunked)."""
    triangles = topology.triangles
    owners_edges = triangles[:, [[0, 1], [1, 2], [2, 0]]].reshape(-1, 2)
    owner = np.repeat(np.arange(len(triangles)), 3)
    found = set()
    chunk = max(1, 400000 // max(len(triangles), 1))
    for begin in range(0, len(owners_edges), chunk):
        edge_index, other = np.meshgrid(np.arange(begin, min(begin + chunk, len(owners_edges))),
                                        np.arange(len(triangles)), indexing="ij")
        edge_index, other = edge_index.ravel(), other.ravel()
        edge = owners_edges[edge_index]
        shares = (triangles[other] == edge[:, :1]).any(axis=1) | (triangles[other] == edge[:, 1:]).any(axis=1)
        keep = ~shares
        if allowed is not None:
            keep &= allowed[topology.triangle_mesh[owner[edge_index]], topology.triangle_mesh[other]]
        edge, edge_index, other = edge[keep], edge_index[keep], other[keep]
        corners = vertices[triangles[other]]
        hit = segments_cross_triangles(vertices[edge[:, 0]], vertices[edge[:, 1]], corners[:, 0],
                                       corners[:, 1], corners[:, 2])
        first, second = owner[edge_index[hit]], other[hit]
        found |= set(zip(np.minimum(first, second).tolist(), np.maximum(first, second).tolist()))
    return found
