"""group_regions on real contacts (the check's own): rows join a region through a vertex they share while
their spans overlap; a region ends where its contacts end."""

import numpy as np
import pytest

from regions.scenes import BOX_BOTTOM, BOX_TOP, box, boxes, contacts, sample_times, sheet
from usdksl.contacts.table import ContactTable
from usdksl.regions.grouping import group_regions

#: A 10 x 10 sheet at z = 0 whose grid lines and diagonals miss the boxes' edges and corners.
SHEET_ORIGIN, SHEET_EDGE_U, SHEET_EDGE_V = (-1.03, -0.98, 0.0), (2.0, 0.0, 0.0), (0.0, 2.0, 0.0)


def flat_sheet():
    return sheet(10, 10, SHEET_ORIGIN, SHEET_EDGE_U, SHEET_EDGE_V)


def sheet_vertices(table, rows, sheet_mesh):
    """Set of sheet vertices (side a) the faces of ``rows`` use."""
    faces = np.unique(table.face_a[rows])
    return set(np.unique(sheet_mesh.triangles[np.isin(sheet_mesh.triangle_face, faces)]).tolist())


def keyframed(keys):
    """centre(t) interpolating the (time, x, y, z) keys linearly."""
    keys = np.asarray(keys, float)
    return lambda t: [np.interp(t, keys[:, 0], keys[:, axis]) for axis in (1, 2, 3)]


def test_a_box_through_a_sheet_is_one_region_and_each_row_spans_its_contact():
    # centre z = -1 + t / 4: the top reaches the sheet at time 2, the bottom leaves it at time 6
    times = np.arange(9.0)
    meshes = [flat_sheet(), box(0.5, lambda t: (0, 0, -1 + 0.25 * t), times)]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    assert grouping.region_count == 1
    assert np.all(grouping.row_region == 0)
    box_face = table.face_b
    # the top touches the sheet only at time 2 (then it is above), a wall from 2 to 6, the bottom only at 6
    assert np.all(grouping.row_last_sampled[box_face == BOX_TOP] == 2.0)
    walls = (box_face != BOX_TOP) & (box_face != BOX_BOTTOM)
    assert walls.any() and np.all(grouping.row_last_sampled[walls] == 6.0)
    assert np.all(grouping.row_last_sampled[box_face == BOX_BOTTOM] == 6.0)
    # spans: from the last sample at or before the row's time, at least one step, to its last sampled contact
    first = np.searchsorted(times, table.time, side="right") - 1
    assert np.array_equal(grouping.row_span[:, 0], first)
    assert np.array_equal(grouping.row_span[:, 1], np.maximum(first + 1, grouping.row_last_sampled.astype(int)))


@pytest.mark.parametrize("second_start, expected", [(10.0, 2), (0.0, 2)])
def test_two_boxes_at_different_places_are_two_regions(second_start, expected):
    # one mesh of two boxes poking through the sheet 1.2 apart, at different times or at once
    times = np.arange(21.0)

    def centres(t):
        return [(-0.6, 0.0, -0.5 + 0.125 * min(t, 8.0)),
                (0.6, 0.0, -0.5 + 0.125 * min(max(t - second_start, 0.0), 8.0))]

    meshes = [flat_sheet(), boxes(0.25, centres, times)]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    assert grouping.region_count == expected
    # each region holds the rows of one box (faces 0..5 the first, 6..11 the second)
    which_box = table.face_b // 6
    assert np.array_equal(grouping.row_region, which_box if table.face_b[0] < 6 else 1 - which_box)
    assert grouping.row_region[0] == 0, "numbered in the order of each region's first row"


def test_the_same_place_touched_again_after_its_contacts_end_is_a_new_region():
    # the box pokes up through the sheet, drops back, moves 0.3 to the side below it, pokes up again
    keys = [(0, 0, 0, -0.5), (4, 0, 0, -0.1), (8, 0, 0, -0.5), (12, 0.3, 0, -0.5), (16, 0.3, 0, -0.1),
            (20, 0.3, 0, -0.5)]
    times = np.arange(21.0)
    meshes = [flat_sheet(), box(0.25, keyframed(keys), times)]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    assert grouping.region_count == 2
    first, second = grouping.row_region == 0, grouping.row_region == 1
    assert table.time[first].max() < 8 < table.time[second].min()
    # connected on both meshes: the same box (its 8 vertices) and neighbouring sheet faces
    assert sheet_vertices(table, first, meshes[0]) & sheet_vertices(table, second, meshes[0])
    assert grouping.row_span[first, 1].max() < grouping.row_span[second, 0].min()


def _crossings(idle_after=None):
    """A box that crosses the sheet within every step (clear of it at every sample), up, then down, 0.1
    further along x each time; with ``idle_after`` (an even key: the box is below) it waits a whole step below
    the sheet at that key."""
    keys, t = [], 0.0
    for key in range(7):
        x, z = -0.3 + 0.1 * key, (0.5 if key % 2 else -0.5)
        keys.append((t, x, 0.0, z))
        if key == idle_after:
            t += 1.0
            keys.append((t, x, 0.0, z))
        t += 1.0
    keys = np.array(keys)
    return box(0.15, keyframed(keys), keys[:, 0])


def test_crossings_in_consecutive_steps_over_neighbouring_faces_are_one_region():
    meshes = [flat_sheet(), _crossings()]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    # every contact is a graze: its own time is its last sampled contact, its span one step
    assert np.array_equal(grouping.row_last_sampled, table.time)
    assert np.all(grouping.row_span[:, 1] == grouping.row_span[:, 0] + 1)
    assert np.array_equal(np.unique(grouping.row_span[:, 0]), np.arange(6))
    assert grouping.region_count == 1


def test_a_step_without_contact_splits_the_crossings():
    meshes = [flat_sheet(), _crossings(idle_after=2)]
    table = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table, sample_times(meshes), 0.0)
    assert grouping.region_count == 2
    # the crossings in steps 0-1 and 1-2, then (after the idle step 2-3) those from step 3-4 on
    assert np.array_equal(grouping.row_region, (table.time > 3).astype(np.int32))


@pytest.mark.parametrize("fine_top, expected", [(False, 1), (True, 2)])
def test_one_large_face_joins_what_touches_it_at_once(fine_top, expected):
    """Two separate cloth patches drop through a table top at x = -0.6 and x = 0.6 at the same time. A top of
    one quad face joins them (every row shares its four vertices): one region. A finely tessellated top does
    not: two regions."""
    times = np.arange(4.0)   # down to z = -0.1: through the top, not down to the table's bottom
    patches = [sheet(2, 2, (x, -0.1, 0.0), (0.2, 0, 0), (0, 0.2, 0), times, lambda t: (0, 0, 0.2 - 0.1 * t))
               for x in (-0.7, 0.5)]
    cloth = type(patches[0])(times, np.concatenate([p.points for p in patches], axis=1),
                             np.concatenate([patches[0].triangles, patches[1].triangles + 9]),
                             np.concatenate([patches[0].triangle_face, patches[1].triangle_face + 4]))
    if fine_top:
        table = sheet(10, 10, (-1.03, -0.98, -0.0), (2.0, 0, 0), (0, 2.0, 0))
    else:
        table = box((1.0, 1.0, 0.1), lambda t: (0.0, 0.0, -0.1), [0.0])
    meshes = [table, cloth]
    table_contacts = contacts(meshes, [(0, 1)])
    grouping = group_regions(meshes, table_contacts, sample_times(meshes), 0.0)
    assert grouping.region_count == expected
    if not fine_top:
        assert np.all(table_contacts.face_a == BOX_TOP)


def test_a_self_region_joins_rows_through_any_side():
    # one mesh of two sheets that cross each other: every contact is a self contact of the mesh
    times = np.arange(5.0)
    flat = sheet(6, 6, (-0.53, -0.48, 0.0), (1.0, 0, 0), (0, 1.0, 0), times)
    wall = sheet(6, 2, (0.07, -0.4, 0.0), (0, 0.8, 0), (0, 0, 0.5), times, lambda t: (0, 0, 0.3 - 0.15 * t))
    both = type(flat)(times, np.concatenate([flat.points, wall.points], axis=1),
                      np.concatenate([flat.triangles, wall.triangles + flat.points.shape[1]]),
                      np.concatenate([flat.triangle_face, wall.triangle_face + 36]))
    table = contacts([both], [(0, 0)])
    assert np.all(table.face_a < 36) and np.all(table.face_b >= 36), "canonical: face_a < face_b"
    grouping = group_regions([both], table, sample_times([both]), 0.0)
    assert grouping.region_count == 1


def test_thickness_keeps_a_contact_going():
    # a sheet sinks past another at 0.1 per sample: in contact at one sample, or within 0.25 for five
    times = np.arange(11.0)
    low = sheet(2, 2, (0.01, 0.02, 0.0), (1, 0, 0), (0, 1, 0))
    high = sheet(2, 2, (0.0, 0.0, 0.0), (1, 0, 0), (0, 1, 0), times, lambda t: (0, 0, 0.5 - 0.1 * t))
    meshes = [low, high]
    table = contacts(meshes, [(0, 1)])
    plain = group_regions(meshes, table, sample_times(meshes), 0.0)
    assert np.all(plain.row_last_sampled[table.time == 5.0] == 5.0)
    thick_table = contacts(meshes, [(0, 1)], thickness=0.25)
    thick = group_regions(meshes, thick_table, sample_times(meshes), 0.25)
    # within 0.25 from time 2.5 (found at 2.5, first sample 3) through time 7.5: last sample 7
    assert np.all(thick.row_last_sampled[np.isclose(thick_table.time, 2.5)] == 7.0)


def test_the_answer_does_not_depend_on_the_threads():
    meshes = [flat_sheet(), _crossings()]
    table = contacts(meshes, [(0, 1)])
    one = group_regions(meshes, table, sample_times(meshes), 0.0, threads=1)
    two = group_regions(meshes, table, sample_times(meshes), 0.0, threads=2)
    assert np.array_equal(one.row_region, two.row_region)
    assert np.array_equal(one.row_span, two.row_span)


def test_rows_the_meshes_do_not_have_are_refused():
    meshes = [flat_sheet(), box(0.5, lambda t: (0, 0, 0), [0.0])]
    with pytest.raises(ValueError, match="face 6 of mesh 1"):
        group_regions(meshes, ContactTable.from_rows(None, [0.0], [0], [0], [1], [6]), np.zeros(1), 0.0)
    with pytest.raises(ValueError, match="sorted"):
        group_regions(meshes, ContactTable.from_rows(None, [0.0], [0], [0], [1], [1]), np.array([1.0, 0.0]), 0.0)
