"""region_depths against closed forms and an independent brute force: penetration into closed meshes at
every sample of a region, intersection lengths, boxes."""

import numpy as np
import pytest

from regions.scenes import Mesh, box, boxes, contacts, icosphere, longest_edge, sample_times, sheet, sphere
from usdksl.contacts.table import ContactTable
from usdksl.regions.closed import closed_meshes
from usdksl.regions.depth import DEPTH_RELATIVE_ACCURACY, region_depths
from usdksl.regions.grouping import group_regions

#: Rounding allowance of the closed forms (scene units).
ROUNDING = 1e-9


def measure(meshes, pairs, thickness=0.0):
    """(table, grouping, depth samples) of the check's contacts of ``pairs``."""
    table = contacts(meshes, pairs, thickness)
    times = sample_times(meshes)
    grouping = group_regions(meshes, table, times, thickness)
    return table, grouping, region_depths(meshes, table, grouping, times, closed_meshes(meshes))


def assert_depth(measured, expected, accuracy, faceting=0.0):
    """measured <= true <= measured + accuracy, the true depth known to within ``faceting``."""
    measured, expected = np.asarray(measured), np.asarray(expected)
    assert np.all(measured <= expected + faceting + ROUNDING), (measured, expected)
    assert np.all(expected - faceting <= measured + accuracy + ROUNDING), (measured, expected)


def box_depth(points, half):
    """Signed distance to the box [-half, half]^3 (positive inside), closed form."""
    q = np.abs(points) - half
    inside = np.all(q <= 0, axis=-1)
    return np.where(inside, -q.max(axis=-1), -np.linalg.norm(np.maximum(q, 0), axis=-1))


# ------------------------------------------------------------------ a box through a sheet

def flat_sheet(columns=10):
    return sheet(columns, columns, (-1.03, -0.98, 0.0), (2.0, 0, 0), (0, 2.0, 0))


def test_a_box_through_a_sheet_at_every_sample():
    """A box of half-size a = 0.5 rises through a sheet at a quarter unit per time code: with the sheet at
    height z of the box's centre the depth is min(a, a - |z|), the intersection the box's cross-section
    perimeter 8a, the box of it the square at the sheet's height."""
    a, times = 0.5, np.arange(9.0)
    meshes = [flat_sheet(), box(a, lambda t: (0, 0, -1 + 0.25 * t), times)]
    _, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 1
    assert depth.time.tolist() == [2.0, 3.0, 4.0, 5.0, 6.0], "from the first contact to the last sample in contact"
    assert np.all(depth.region == 0)
    z = 0.0 - (-1 + 0.25 * depth.time)      # the sheet's height in the box's frame
    expected = np.maximum(0.0, np.minimum(a, a - np.abs(z)))
    assert_depth(depth.penetration, expected, DEPTH_RELATIVE_ACCURACY * longest_edge(meshes[0]))
    assert depth.penetration[2] > 0.49
    # the walls cross the sheet along the perimeter; at times 2 and 6 the top and the bottom lie in the sheet
    # (an overlap of areas, which adds nothing) and the walls only touch it with their edges: half each
    np.testing.assert_allclose(depth.intersection_length, [4 * a, 8 * a, 8 * a, 8 * a, 4 * a], rtol=1e-12)
    np.testing.assert_allclose(depth.box_min, np.tile([-a, -a, 0.0], (5, 1)), atol=1e-12)
    np.testing.assert_allclose(depth.box_max, np.tile([a, a, 0.0], (5, 1)), atol=1e-12)


def test_two_boxes_in_one_mesh_are_two_regions_each_with_its_own_depth():
    times = np.arange(21.0)

    def centres(t):    # rise a quarter per time code, the second ten time codes later, 1.2 to the side
        return [(-0.6, 0, -0.75 + 0.125 * min(t, 12.0)), (0.6, 0, -0.75 + 0.125 * min(max(t - 8, 0.0), 12.0))]

    meshes = [flat_sheet(), boxes(0.25, centres, times)]
    table, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 2
    accuracy = DEPTH_RELATIVE_ACCURACY * longest_edge(meshes[0])
    for region, start in ((0, 0.0), (1, 8.0)):
        rows = grouping.row_region == region
        assert np.all(table.face_b[rows] // 6 == region)
        at = depth.region == region
        z = -(-0.75 + 0.125 * np.clip(depth.time[at] - start, 0, 12))
        assert_depth(depth.penetration[at], np.maximum(0, 0.25 - np.abs(z)), accuracy)
        crossing = np.abs(z) < 0.25
        assert crossing.sum() >= 3
        np.testing.assert_allclose(depth.intersection_length[at][crossing], 8 * 0.25, rtol=1e-12)
        centre_x = -0.6 if region == 0 else 0.6
        np.testing.assert_allclose(depth.box_min[at][crossing, 0], centre_x - 0.25, atol=1e-12)
        np.testing.assert_allclose(depth.box_max[at][crossing, 0], centre_x + 0.25, atol=1e-12)
    assert depth.time[depth.region == 0].max() < depth.time[depth.region == 1].min()


# ------------------------------------------------------------------ a sheet over a box edge

def test_a_sheet_over_a_box_edge_with_every_vertex_outside():
    """A coarse sheet in the plane x + z = c is pushed onto the box edge x = z = a: every sheet vertex stays
    outside the box, yet the sheet cuts off a wedge of it, h / 2 deep for c = 2a - h."""
    a = 0.5
    times = np.arange(7.0)
    c = 1.3 - 0.1 * times                        # c = 2a - h: h = 0 at time 3, h = 0.3 at time 6
    ridge = np.array([1.0, 0.0, 1.0]) / 2.0      # where the plane x + z = c meets the plane x = z, per unit c
    u_axis, v_axis = np.array([1.0, 0.0, -1.0]) / np.sqrt(2), np.array([0.0, 1.0, 0.0])
    # vertices at u = -1.5, -0.5, 0.5, 1.5 from the ridge: never on it
    cover = sheet(3, 3, -1.5 * u_axis - 1.5 * v_axis, 3.0 * u_axis, 3.0 * v_axis, times, lambda t: (1.3 - 0.1 * t) * ridge)
    table = box(a, lambda t: (0, 0, 0), [0.0])
    meshes = [cover, table]
    assert np.all(box_depth(cover.points, a) < -0.2), "every sheet vertex outside, at every sample"
    _, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 1
    h = np.maximum(0.0, 2 * a - np.interp(depth.time, times, c))
    assert np.all(depth.time >= 3.0)
    assert depth.penetration[-1] > 0.1
    assert_depth(depth.penetration, h / 2, DEPTH_RELATIVE_ACCURACY * longest_edge(cover))


# ------------------------------------------------------------------ a sphere through a plane

def test_a_sphere_through_a_plane_is_r_minus_d():
    r, levels = 1.0, 4
    times = np.arange(11.0)
    ball = sphere(r, levels, lambda t: (0.013, -0.021, -1.25 + 0.25 * t), times)
    plane = sheet(12, 12, (-1.53, -1.48, 0.0), (3.0, 0, 0), (0, 3.0, 0))
    meshes = [plane, ball]
    # the faceted sphere lies between its inscribed radius and r
    unit = ball.points[0] - ball.points[0].mean(axis=0)
    corners = unit[ball.triangles]
    normals = np.cross(corners[:, 1] - corners[:, 0], corners[:, 2] - corners[:, 0])
    inscribed = np.min(np.abs(np.einsum("ij,ij->i", normals, corners[:, 0])) / np.linalg.norm(normals, axis=1))
    faceting = r - inscribed
    assert faceting < 0.005
    _, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 1
    d = np.abs(-1.25 + 0.25 * depth.time)
    assert_depth(depth.penetration, np.maximum(0, r - d), DEPTH_RELATIVE_ACCURACY * longest_edge(plane), faceting)
    # the intersection is a circle of radius sqrt(r^2 - d^2), its polygon a little shorter
    circle = 2 * np.pi * np.sqrt(np.maximum(0, r * r - d * d))
    crossing = d < 0.9
    assert np.all(depth.intersection_length[crossing] <= circle[crossing] + ROUNDING)
    assert np.all(depth.intersection_length[crossing] >= 0.99 * 2 * np.pi * np.sqrt(inscribed ** 2 - d[crossing] ** 2))


# ------------------------------------------------------------------ both sides closed

@pytest.mark.parametrize("slab_first", [False, True])
def test_two_closed_meshes_take_the_deeper_direction(slab_first):
    """A thin slab (half-sizes 0.1, 0.75, 0.75) slides into a box (half-size 0.5) from +x: its face x_l =
    x - 0.1 goes 0.5 - x_l deep into the box, while the box goes at most 0.1 into the slab. Either mesh order."""
    times = np.arange(7.0)
    cube = box(0.5, lambda t: (0, 0, 0), [0.0])
    slab = box((0.1, 0.75, 0.75), lambda t: (0.75 - 0.1 * t, 0, 0), times)
    meshes = [slab, cube] if slab_first else [cube, slab]
    _, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 1
    x_l = 0.75 - 0.1 * depth.time - 0.1
    assert_depth(depth.penetration, np.clip(0.5 - x_l, 0, None), DEPTH_RELATIVE_ACCURACY * longest_edge(slab))
    assert depth.penetration.max() > 0.35


# ------------------------------------------------------------------ open meshes

def test_cloth_on_cloth_has_no_penetration_and_the_exact_intersection_length():
    """A vertical sheet 0.8 wide sinks through a horizontal one: where they cross, the intersection is a
    segment of the vertical sheet's width; neither is closed, so there is no penetration depth."""
    times = np.arange(9.0)
    flat = sheet(6, 6, (-0.53, -0.48, 0.0), (1.0, 0, 0), (0, 1.0, 0))
    wall = sheet(3, 4, (0.07, -0.4, 0.0), (0, 0.8, 0), (0, 0, 0.6), times, lambda t: (0, 0, 0.2 - 0.1 * t))
    meshes = [flat, wall]
    _, grouping, depth = measure(meshes, [(0, 1)])
    assert grouping.region_count == 1
    assert np.all(np.isnan(depth.penetration))
    bottom = 0.2 - 0.1 * depth.time
    crossing = (bottom < 0) & (bottom + 0.6 > 0)
    assert crossing.sum() >= 4
    np.testing.assert_allclose(depth.intersection_length[crossing], 0.8, rtol=1e-12)
    np.testing.assert_allclose(depth.box_min[crossing], np.tile([0.07, -0.4, 0.0], (crossing.sum(), 1)), atol=1e-12)
    np.testing.assert_allclose(depth.box_max[crossing], np.tile([0.07, 0.4, 0.0], (crossing.sum(), 1)), atol=1e-12)
    gone = bottom > 0
    assert np.all(depth.intersection_length[gone] == 0) and np.all(np.isnan(depth.box_min[gone]))


def test_a_self_region_has_no_penetration_even_of_a_closed_mesh():
    """One closed mesh of two boxes, a thinner one (half-sizes 0.25, 0.15, 0.15) sliding into the other
    (half-size 0.25) along x: a self region, so no penetration depth, though the mesh is closed. While the thin
    box straddles x = 0.25, the big box's face there crosses its four walls: a square of side 0.3."""
    times = np.arange(6.0)
    big = box(0.25, lambda t: (0, 0, 0), times)
    thin = box((0.25, 0.15, 0.15), lambda t: (0.6 - 0.1 * t, 0, 0), times)
    pair = Mesh(times, np.concatenate([big.points, thin.points], axis=1),
                np.concatenate([big.triangles, thin.triangles + 8]), np.concatenate([big.triangle_face, thin.triangle_face + 6]))
    table = contacts([pair], [(0, 0)])
    grouping = group_regions([pair], table, sample_times([pair]), 0.0)
    assert closed_meshes([pair])[0]
    depth = region_depths([pair], table, grouping, sample_times([pair]), closed_meshes([pair]))
    assert grouping.region_count == 1 and depth.count > 0
    assert np.all(np.isnan(depth.penetration))
    straddling = depth.time >= 2
    assert straddling.sum() == 4
    np.testing.assert_allclose(depth.intersection_length[straddling], 4 * 0.3, rtol=1e-12)


def test_faces_of_one_mesh_sharing_an_edge_add_no_length():
    # two quads folded 90 degrees along the edge x = 1 they share; a row naming the two
    strip = sheet(2, 1, (0, 0, 0), (2, 0, 0), (0, 1, 0))
    points = strip.points.copy()
    far = points[0, :, 0] > 1.5                  # the corners at x = 2 go up to z = 1 above the fold
    points[0, far, 0], points[0, far, 2] = 1.0, 1.0
    folded = Mesh(strip.times, points, strip.triangles, strip.triangle_face)
    table = ContactTable.from_rows(None, [0.0], [0], [0], [0], [1])
    grouping = group_regions([folded], table, np.zeros(1), 0.0)
    depth = region_depths([folded], table, grouping, np.zeros(1), np.zeros(1, bool))
    assert depth.intersection_length.tolist() == [0.0]
    assert np.all(np.isnan(depth.box_min))


# ------------------------------------------------------------------ an independent brute force

def _point_triangle_distance(points, a, b, c):
    """Distance from each point (float[P, 3]) to each triangle (float[T, 3] corners): float[P, T]
    (Ericson's Voronoi regions, vectorised; an implementation of its own, not the core's)."""
    p = points[:, None, :]
    ab, ac, ap = b - a, c - a, p - a
    d1, d2 = np.einsum("tk,ptk->pt", ab, ap), np.einsum("tk,ptk->pt", ac, ap)
    bp, cp = p - b, p - c
    d3, d4 = np.einsum("tk,ptk->pt", ab, bp), np.einsum("tk,ptk->pt", ac, bp)
    d5, d6 = np.einsum("tk,ptk->pt", ab, cp), np.einsum("tk,ptk->pt", ac, cp)
    va, vb, vc = d3 * d6 - d5 * d4, d5 * d2 - d1 * d6, d1 * d4 - d3 * d2
    with np.errstate(divide="ignore", invalid="ignore"):
        denom = va + vb + vc
        v, w = vb / denom, vc / denom
        closest = a + ab * v[..., None] + ac * w[..., None]
        e_ab = a + ab * np.clip(d1 / (d1 - d3), 0, 1)[..., None]
        e_ac = a + ac * np.clip(d2 / (d2 - d6), 0, 1)[..., None]
        e_bc = b + (c - b) * np.clip((d4 - d3) / ((d4 - d3) + (d5 - d6)), 0, 1)[..., None]
    region = [(d1 <= 0) & (d2 <= 0), (d3 >= 0) & (d4 <= d3), (d6 >= 0) & (d5 <= d6),
              (vc <= 0) & (d1 >= 0) & (d3 <= 0), (vb <= 0) & (d2 >= 0) & (d6 <= 0),
              (va <= 0) & ((d4 - d3) >= 0) & ((d5 - d6) >= 0)]
    choices = [np.broadcast_to(a, closest.shape), np.broadcast_to(b, closest.shape), np.broadcast_to(c, closest.shape),
               e_ab, e_ac, e_bc]
    for mask, choice in zip(region[::-1], choices[::-1]):
        closest = np.where(mask[..., None], choice, closest)
    return np.linalg.norm(p - closest, axis=-1)


def _winding_number(points, a, b, c):
    """Generalized winding number of the closed triangle soup around each point (about 1 inside, 0 outside)."""
    x, y, z = a[None] - points[:, None], b[None] - points[:, None], c[None] - points[:, None]
    lx, ly, lz = (np.linalg.norm(v, axis=-1) for v in (x, y, z))
    det = np.einsum("ptk,ptk->pt", x, np.cross(y, z))
    denom = (lx * ly * lz + np.einsum("ptk,ptk->pt", x, y) * lz + np.einsum("ptk,ptk->pt", y, z) * lx
             + np.einsum("ptk,ptk->pt", z, x) * ly)
    return (2 * np.arctan2(det, denom)).sum(axis=1) / (4 * np.pi)


def test_depth_into_a_deformed_closed_mesh_matches_a_brute_force():
    rng = np.random.default_rng(7)
    # a lumpy sphere: radius 1 times smooth bumps (still star-shaped, so closed and not self-intersecting)
    unit, _ = icosphere(2)
    bumps = rng.normal(size=(6, 3))
    bumps /= np.linalg.norm(bumps, axis=1, keepdims=True)
    radial = 1 + 0.25 * np.exp(-np.sum((unit[:, None] - bumps[None]) ** 2, axis=-1) / 0.3) @ rng.uniform(-1, 1, 6)
    lump = sphere(1.0, 2, lambda t: (0.0, 0.0, 0.0), [0.0], radial)
    # a coarse, tilted sheet sweeping in from afar to cut it 0.2 off the centre
    normal = np.array([0.3, -0.2, 1.0]) / np.linalg.norm([0.3, -0.2, 1.0])
    u_axis = np.cross(normal, [1.0, 0, 0])
    u_axis /= np.linalg.norm(u_axis)
    v_axis = np.cross(normal, u_axis)
    times = np.array([0.0, 1.0])
    cut = sheet(5, 5, -1.8 * u_axis - 1.8 * v_axis, 3.6 * u_axis, 3.6 * v_axis, times,
                lambda t: normal * (2.0 - 1.8 * t))
    meshes = [cut, lump]
    table, grouping, depth = measure(meshes, [(0, 1)])
    assert depth.time.tolist() == [1.0] and grouping.region_count == 1
    measured = depth.penetration[0]

    # brute force over the region's sheet faces at time 1: dense barycentric points
    triangles = cut.triangles[np.isin(cut.triangle_face, np.unique(table.face_a))]
    corners = cut.points[1][triangles]                      # [T, 3, 3]
    steps = 30
    i, j = np.meshgrid(np.arange(steps + 1), np.arange(steps + 1), indexing="ij")
    keep = i + j <= steps
    bary = np.stack([i[keep], j[keep], steps - i[keep] - j[keep]], axis=1) / steps
    points = np.einsum("bk,tkd->tbd", bary, corners).reshape(-1, 3)
    solid = lump.points[0][lump.triangles]
    a, b, c = solid[:, 0], solid[:, 1], solid[:, 2]
    depths = []
    for chunk in np.array_split(points, max(1, len(points) // 1500)):
        inside = _winding_number(chunk, a, b, c) > 0.5
        distance = _point_triangle_distance(chunk, a, b, c).min(axis=1)
        depths.append(np.where(inside, distance, 0.0))
    brute = np.concatenate(depths).max()
    edge = longest_edge(cut)
    spacing = edge / steps            # every point of a triangle lies within this of a sample point
    assert brute > 0.3
    assert brute <= measured + DEPTH_RELATIVE_ACCURACY * edge + ROUNDING
    assert measured <= brute + spacing
    # the sheet's vertices alone would not show it: the deepest point lies inside a face
    vertices = cut.points[1][np.unique(triangles)]
    at_vertices = np.where(_winding_number(vertices, a, b, c) > 0.5,
                           _point_triangle_distance(vertices, a, b, c).min(axis=1), 0.0).max()
    assert measured > at_vertices + 0.05


def test_the_answer_does_not_depend_on_the_threads():
    a, times = 0.5, np.arange(9.0)
    meshes = [flat_sheet(), box(a, lambda t: (0.1, 0.05, -1 + 0.25 * t), times)]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    one = region_depths(meshes, table, grouping, sample_times(meshes), closed_meshes(meshes), threads=1)
    two = region_depths(meshes, table, grouping, sample_times(meshes), closed_meshes(meshes), threads=2)
    for name in ("penetration", "intersection_length", "box_min", "box_max"):
        np.testing.assert_array_equal(getattr(one, name), getattr(two, name))
