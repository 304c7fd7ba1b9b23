"""closed_meshes: a mesh is closed when every edge is used by exactly two triangles, once each way."""

import numpy as np

from regions.scenes import Mesh, box, boxes, icosphere, sheet, sphere
from usdksl.regions.closed import closed_meshes, triangles_are_closed


def _still(points, triangles) -> Mesh:
    triangles = np.asarray(triangles, dtype=np.int32)
    return Mesh(np.zeros(1), np.asarray(points, float)[None], triangles, np.arange(len(triangles), dtype=np.int32))


TETRAHEDRON = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]]


def test_boxes_spheres_and_tetrahedra_are_closed_sheets_are_not():
    meshes = [box(0.5, lambda t: (0, 0, 0), [0.0]), sphere(1.0, 2, lambda t: (0, 0, 0), [0.0]),
              _still(np.eye(4, 3), TETRAHEDRON), sheet(3, 3, (0, 0, 0), (1, 0, 0), (0, 1, 0)),
              boxes(0.5, lambda t: [(0, 0, 0), (3, 0, 0)], [0.0])]
    assert closed_meshes(meshes).tolist() == [True, True, True, False, True]


def test_either_winding_is_closed_but_a_mix_is_not():
    inward = np.asarray(TETRAHEDRON)[:, ::-1]
    assert triangles_are_closed(inward)
    mixed = np.array(TETRAHEDRON)
    mixed[0] = mixed[0][::-1]   # one triangle against the others: its edges run the same way as its neighbours'
    assert not triangles_are_closed(mixed)


def test_a_hole_a_fin_and_a_repeated_corner_are_not_closed():
    _, triangles = icosphere(1)
    assert triangles_are_closed(triangles)
    assert not triangles_are_closed(triangles[1:]), "one triangle missing: a hole"
    fin = np.concatenate([TETRAHEDRON, [[0, 1, 4], [1, 0, 5]]])  # edge 0-1 now used by four triangles
    assert not triangles_are_closed(fin)
    assert not triangles_are_closed(np.concatenate([TETRAHEDRON, [[0, 0, 1]]]))
    assert not triangles_are_closed(np.zeros((0, 3), np.int32)), "no surface, no inside"


def test_two_triangles_back_to_back_are_closed_and_enclose_nothing():
    # every edge twice, once each way: closed by the rule, with zero volume (its depth is always 0)
    assert triangles_are_closed([[0, 1, 2], [0, 2, 1]])
