"""A near miss smaller than the root finder's rounding-error bound is not a contact (docs/contracts.md, Contacts).

The contract: a pair is reported only when its raw-sample trajectories come within the thickness. The
root finder bounds the rounding of its corner values by a fixed multiple of the largest coordinate of the
query, so a gap below that bound (5e-18 beside coordinates of 0.006) could never exclude a box, and the
pair was reported at the first instant of the step. On the Newton shirt cache three arm/shirt face pairs
were reported at t = 0 this way while their edges stay 5.3e-18 apart (Tight-Inclusion at 1e-9 and an exact
evaluation agree: no touch). A gap of exactly zero, or one the motion closes, is still a contact.

Times are fractions of one step (CCD queries) or time codes (shots with samples at 0 and 1).
"""

import numpy as np
import pytest

from usdksl import ccd
from usdksl.checking.collision import find_contacts

from builders import animated

#: A gap far below the root finder's float error bound for these coordinates (64 u x 0.006 = 4e-17).
SUB_ROUNDING_GAP = 5e-18
#: How far the upper primitive rises over the step (scene units); sets the float error bound.
RISE = 0.006
#: Default CCD tolerance (fraction of a step).
TOLERANCE = 1e-6
#: A thickness that is a binary fraction, so thickness + one ulp is exactly representable above it.
THICKNESS = 0.25

#: The edge-edge query of /World/Body/LeftArm/Mesh edge (176, 144) and /World/Shirt edge (64, 0) over time
#: codes 0..1 of benchmarks/caches/newton_shirt_s0.25_f150.usdc (world space, as the loader reads them):
#: the arm edge lies 5.5e-18 above the shirt edge at t = 0 and rises away from it.
SHIRT_ARM_EDGE_EDGE = [
    [0.18993654925215045, 5.51091050576101e-18, 1.410710713784994],
    [0.19285313592359266, 5.323130994134429e-18, 1.422090256326055],
    [0.1899999976158142, 0.0, 1.4053846597671509],
    [0.1899999976158142, 0.0, 1.4199999570846558],
    [0.1911549097679461, 0.006129851906602015, 1.41075168464633],
    [0.19408260117028958, 0.005677172853237909, 1.422119365631612],
    [0.18518798053264618, 0.0028730779886245728, 1.4059982299804688],
    [0.19125930964946747, 0.004338438156992197, 1.4199999570846558],
]


def crossing_edges(gap, rise=RISE):
    """Edge A (along x, tilted in z) lies `gap` above edge B (along z) where they cross at the origin
    (in the xz projection) and rises by `rise` over the step; B stays."""
    a0, a1 = np.array([-0.5, gap, 0.1]), np.array([0.5, gap, -0.1])
    b0, b1 = np.array([0.0, 0.0, -0.5]), np.array([0.0, 0.0, 0.5])
    up = np.array([0.0, rise, 0.0])
    return np.array([[a0, a1, b0, b1, a0 + up, a1 + up, b0, b1]])


def vertex_over_face(gap, rise=RISE):
    """A vertex `gap` above the inside of a face in the plane y = 0, rising by `rise` over the step."""
    p = np.array([0.1, gap, 0.1])
    face = [np.array([-1.0, 0.0, -1.0]), np.array([1.0, 0.0, -1.0]), np.array([0.0, 0.0, 1.0])]
    return np.array([[p, *face, p + [0.0, rise, 0.0], *face]])


@pytest.mark.parametrize("query", [crossing_edges, vertex_over_face], ids=["edge-edge", "vertex-face"])
def test_a_gap_below_the_rounding_bound_is_not_a_contact(query):
    detailed = ccd.edge_edge_detailed if query is crossing_edges else ccd.vertex_face_detailed
    answer = detailed(query(SUB_ROUNDING_GAP), tolerance=TOLERANCE)
    assert not answer.hit[0]
    assert not answer.undecided[0]


@pytest.mark.parametrize("query", [crossing_edges, vertex_over_face], ids=["edge-edge", "vertex-face"])
def test_a_zero_gap_is_a_contact_at_the_start(query):
    detailed = ccd.edge_edge_detailed if query is crossing_edges else ccd.vertex_face_detailed
    answer = detailed(query(0.0), tolerance=TOLERANCE)
    assert answer.hit[0] and answer.toi[0] == 0.0


@pytest.mark.parametrize("query", [crossing_edges, vertex_over_face], ids=["edge-edge", "vertex-face"])
def test_a_sub_rounding_gap_that_closes_is_a_contact(query):
    """Moving down instead of up, the primitives meet after SUB_ROUNDING_GAP / RISE of the step."""
    detailed = ccd.edge_edge_detailed if query is crossing_edges else ccd.vertex_face_detailed
    answer = detailed(query(SUB_ROUNDING_GAP, rise=-RISE), tolerance=TOLERANCE)
    assert answer.hit[0]
    assert answer.toi[0] <= SUB_ROUNDING_GAP / RISE


def test_the_newton_shirt_arm_query_is_not_a_contact():
    answer = ccd.edge_edge_detailed(np.array([SHIRT_ARM_EDGE_EDGE]), tolerance=TOLERANCE * 1e-3)
    assert not answer.hit[0]


@pytest.mark.parametrize("query", [crossing_edges, vertex_over_face], ids=["edge-edge", "vertex-face"])
def test_one_ulp_beyond_the_thickness_is_not_a_contact(query):
    above = np.nextafter(THICKNESS, 1.0)
    detailed = ccd.edge_edge_detailed if query is crossing_edges else ccd.vertex_face_detailed
    assert not detailed(query(above), tolerance=TOLERANCE, thickness=THICKNESS).hit[0]
    at = detailed(query(THICKNESS), tolerance=TOLERANCE, thickness=THICKNESS)
    assert at.hit[0] and at.toi[0] == 0.0


def crossing_triangles(gap):
    """Two triangles that come closest where edge A crosses over edge B (see crossing_edges): A's third
    corner is above, B's below, so no other feature comes near. A rises, B stays."""
    edges = crossing_edges(gap)[0]
    top = np.array([edges[0], edges[1], [0.0, gap + 0.5, 0.5]])
    bottom = np.array([edges[2], edges[3], [0.5, -0.5, 0.0]])
    rising = animated([0.0, 1.0], [top, top + [0.0, RISE, 0.0]], [[0, 1, 2]])
    still = animated([0.0, 1.0], [bottom, bottom], [[0, 1, 2]])
    return [rising, still]


@pytest.mark.parametrize("method", ["ksl", "swept", "brute"])
def test_check_does_not_report_a_sub_rounding_near_miss(method):
    assert len(find_contacts(crossing_triangles(SUB_ROUNDING_GAP), [(0, 1)], method=method)) == 0
    touching = find_contacts(crossing_triangles(0.0), [(0, 1)], method=method)
    assert len(touching) == 1 and float(touching.time[0]) == 0.0
