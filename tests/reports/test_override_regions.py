"""Regions in the override layer: per face the region of its first contact, per mesh (or PointInstancer) its
regions with their frames and depth, read back with pxr over the shot against the RegionTable."""

import math

import numpy as np
import pytest
from pxr import Gf, Sdf, Usd, UsdGeom, Vt

from usdksl.checking.collision import find_contacts
from usdksl.clock import StageClock
from usdksl.contacts.table import ContactTable
from usdksl.pipeline.loading import load_segments
from usdksl.reading.loader import find_mesh_sources, load_shot
from usdksl.reading.segments import topology_epochs
from usdksl.regions.table import INTERSECTION_LENGTH, PENETRATION, RegionTable
from usdksl.reports.override import (ATTR_INSTANCE_REGION, ATTR_REGION_DEPTH_MEASURE, ATTR_REGION_FIRST_FRAME,
                                     ATTR_REGION_LAST_FRAME, ATTR_REGION_MAX_DEPTH, ATTR_REGION_WITH, ATTR_REGIONS,
                                     NO_REGION_ID, PRIMVAR_REGION, face_regions, override_layer)

from builders import (STRIP_COUNTS, STRIP_INDICES, STRIP_POINTS, add_mesh, box, define_mesh, falling_instancer,
                      grid, new_stage, stretching_sheet)
from .test_reports import contacts

#: Region properties the layer authors (beside the primvar); with them removed it is the layer without regions.
REGION_PROPERTIES = (PRIMVAR_REGION, ATTR_REGIONS, ATTR_REGION_FIRST_FRAME, ATTR_REGION_LAST_FRAME,
                     ATTR_REGION_MAX_DEPTH, ATTR_REGION_DEPTH_MEASURE, ATTR_REGION_WITH, ATTR_INSTANCE_REGION)
#: The hand-made regions last this many time codes past their first contact.
REGION_LENGTH = 3.0


def hand_regions(table, labels, measures=None):
    """A RegionTable grouping the rows of ``table`` by ``labels`` (one per row), numbered by earliest row (the
    table's canonical order), as the region finder numbers them. Depths are made up: 0.1 per region id."""
    labels = np.asarray(labels)
    _, first_rows = np.unique(labels, return_index=True)
    earliest = np.sort(first_rows)
    region_of = {labels[row]: position for position, row in enumerate(earliest.tolist())}
    row_region = np.array([region_of[label] for label in labels.tolist()], dtype=np.int32)
    count = earliest.size
    first_time = np.array([table.time[row_region == k].min() for k in range(count)])
    center = np.array([[float(k), 0.0, 0.0] for k in range(count)]).reshape(count, 3)
    return RegionTable(
        paths=table.paths, mesh_a=table.mesh_a[earliest].astype(np.int32),
        mesh_b=table.mesh_b[earliest].astype(np.int32),
        first_time=first_time, last_time=first_time + REGION_LENGTH,
        face_pairs=np.bincount(row_region, minlength=count).astype(np.int64),
        depth_measure=np.array(measures if measures is not None else [PENETRATION] * count, dtype=object),
        max_depth=0.1 * (np.arange(count) + 1), max_depth_time=first_time, max_intersection_length=np.zeros(count),
        center=center, box_min=center - 0.5, box_max=center + 0.5, row_region=row_region)


def expected_face_regions(table, regions, mesh_index, face_count):
    """The oracle, row by row: each face's earliest row (first in table order among equal times) gives its region."""
    best = {}
    for row in range(table.count):
        for mesh, face in ((table.mesh_a[row], table.face_a[row]), (table.mesh_b[row], table.face_b[row])):
            if mesh == mesh_index and (face not in best or table.time[row] < table.time[best[face]]):
                best[int(face)] = row
    values = [NO_REGION_ID] * face_count
    for face, row in best.items():
        values[face] = int(regions.row_ids[row])
    return values


def write_layer(shot, table, regions, layer_path, segments=None, checked=None):
    built = override_layer(shot, range(len(shot.meshes)) if checked is None else checked, table, layer_path,
                           segments=segments, regions=regions)
    layer_path.write_text(built.layer.ExportToString())
    return Usd.Stage.Open(str(layer_path)), built


def region_primvar(stage, path, time=Usd.TimeCode.Default()):
    primvar = UsdGeom.PrimvarsAPI(stage.GetPrimAtPath(path)).GetPrimvar("usdksl:region")
    assert primvar and primvar.GetInterpolation() == UsdGeom.Tokens.uniform
    return [int(value) for value in primvar.Get(time)]


def region_arrays(stage, path):
    prim = stage.GetPrimAtPath(path)
    return {name: prim.GetAttribute(name).Get() for name in
            (ATTR_REGIONS, ATTR_REGION_FIRST_FRAME, ATTR_REGION_LAST_FRAME, ATTR_REGION_MAX_DEPTH,
             ATTR_REGION_DEPTH_MEASURE, ATTR_REGION_WITH)}


def two_boxes_through_a_sheet(path):
    """A deforming sheet at y = 0 and two boxes falling through it at opposite corners, box B later; 48 time
    codes a second played at 24 frames (frame = time / 2)."""
    stage = new_stage(path, tcps=48.0, fps=24.0, start=1.0, end=24.0)
    stretching_sheet(stage, "/World/Sheet", size=6.0, columns=6, times=(1.0, 24.0))
    points, counts, indices = box(1.0)
    for name, (x, z), (top, bottom) in (("BoxA", (-1.5, -1.5), (1.5, -2.0)), ("BoxB", (1.5, 1.5), (4.0, -1.0))):
        define_mesh(stage, f"/World/{name}", None, counts, indices,
                    samples={1.0: points + [x, top, z], 24.0: points + [x, bottom, z]})
    stage.GetRootLayer().Save()
    return path


@pytest.fixture
def boxes(tmp_path):
    shot = load_shot(str(two_boxes_through_a_sheet(tmp_path / "boxes.usda")))
    paths = [mesh.path for mesh in shot.meshes]
    sheet = paths.index("/World/Sheet")
    pairs = [(sheet, paths.index("/World/BoxA")), (sheet, paths.index("/World/BoxB"))]
    table = find_contacts(shot.meshes, pairs).face_contacts(shot.meshes)
    # one region per box: the side that is not the sheet
    labels = np.where(table.mesh_a == sheet, table.mesh_b, table.mesh_a)
    return shot, table, hand_regions(table, labels, measures=[PENETRATION, INTERSECTION_LENGTH])


def test_faces_carry_the_region_of_their_first_contact(boxes, tmp_path):
    shot, table, regions = boxes
    assert table.count and regions.count == 2
    stage, _ = write_layer(shot, table, regions, tmp_path / "boxes.usdksl.usda")
    for index, mesh in enumerate(shot.meshes):
        values = region_primvar(stage, mesh.path)
        assert values == expected_face_regions(table, regions, index, mesh.face_count), mesh.path
    sheet = region_primvar(stage, "/World/Sheet")
    # both problems show on the sheet, each on its own faces, and faces in none are 0
    assert {1, 2} <= set(sheet) and NO_REGION_ID in sheet
    box_a = [mesh.path for mesh in shot.meshes].index("/World/BoxA")
    region_a = int(regions.ids[(regions.mesh_a == box_a) | (regions.mesh_b == box_a)][0])
    assert set(region_primvar(stage, "/World/BoxA")) <= {region_a, NO_REGION_ID}
    assert region_a in region_primvar(stage, "/World/BoxA")


def test_each_mesh_lists_its_regions_with_frames_and_depth(boxes, tmp_path):
    shot, table, regions = boxes
    stage, _ = write_layer(shot, table, regions, tmp_path / "boxes.usdksl.usda")
    clock = StageClock(time_codes_per_second=48.0, frames_per_second=24.0)
    paths = [mesh.path for mesh in shot.meshes]
    sheet = region_arrays(stage, "/World/Sheet")
    assert list(sheet[ATTR_REGIONS]) == [1, 2]
    assert list(sheet[ATTR_REGION_FIRST_FRAME]) == (regions.first_time / 2.0).tolist()
    assert list(sheet[ATTR_REGION_LAST_FRAME]) == clock.frames(regions.last_time).tolist()
    assert list(sheet[ATTR_REGION_MAX_DEPTH]) == pytest.approx([0.1, 0.2], abs=0)
    assert list(sheet[ATTR_REGION_DEPTH_MEASURE]) == [PENETRATION, INTERSECTION_LENGTH]
    others = [paths[b] if paths[a] == "/World/Sheet" else paths[a] for a, b in zip(regions.mesh_a, regions.mesh_b)]
    assert list(sheet[ATTR_REGION_WITH]) == others
    assert sorted(others) == ["/World/BoxA", "/World/BoxB"]
    for region, box_path in zip(regions.ids.tolist(), others):
        arrays = region_arrays(stage, box_path)
        assert list(arrays[ATTR_REGIONS]) == [region]
        assert list(arrays[ATTR_REGION_WITH]) == ["/World/Sheet"]
        assert list(arrays[ATTR_REGION_FIRST_FRAME]) == [regions.first_time[region - 1] / 2.0]


def test_regions_only_add_their_own_properties(boxes, tmp_path):
    shot, table, regions = boxes
    layer_path = tmp_path / "boxes.usdksl.usda"
    without = override_layer(shot, range(len(shot.meshes)), table, layer_path)
    with_regions = override_layer(shot, range(len(shot.meshes)), table, layer_path, regions=regions)
    assert with_regions.array_elements > without.array_elements
    layer = with_regions.layer
    removed = []

    def strip(path):
        if path.IsPropertyPath() and path.name in REGION_PROPERTIES:
            removed.append(path)
    layer.Traverse("/", strip)
    for path in removed:
        layer.GetPrimAtPath(path.GetPrimPath()).RemoveProperty(layer.GetPropertyAtPath(path))
    assert {path.name for path in removed} == set(REGION_PROPERTIES) - {ATTR_INSTANCE_REGION}
    assert layer.ExportToString() == without.layer.ExportToString()


def test_a_clean_mesh_gets_no_region_properties(tmp_path):
    path = two_boxes_through_a_sheet(tmp_path / "boxes.usda")
    shot = load_shot(str(path))
    paths = [mesh.path for mesh in shot.meshes]
    sheet, box_a = paths.index("/World/Sheet"), paths.index("/World/BoxA")
    table = find_contacts(shot.meshes, [(sheet, box_a)]).face_contacts(shot.meshes)
    regions = hand_regions(table, np.zeros(table.count, int))
    stage, _ = write_layer(shot, table, regions, tmp_path / "one.usdksl.usda")
    clean = stage.GetPrimAtPath("/World/BoxB")
    assert clean.GetAttribute("usdksl:contactFaceCount").Get() == 0          # checked, and clean
    assert not clean.GetAttribute(ATTR_REGIONS) and not UsdGeom.PrimvarsAPI(clean).GetPrimvar("usdksl:region")
    assert list(stage.GetPrimAtPath("/World/Sheet").GetAttribute(ATTR_REGIONS).Get()) == [1]


def test_earliest_contact_wins_and_ties_go_to_the_first_row():
    # mesh 0 face 1 touches in region 2 at 16 and in region 1 at 14: region 1; face 0 touches at 17 in two
    # regions (rows in canonical order: (0,0)x(1,0) before (0,0)x(1,1)): the first row's region
    table = ContactTable.from_face_contacts(contacts([(16.0, 0, 1, 1, 0, 2), (14.0, 0, 1, 1, 1, 2),
                                                      (17.0, 0, 0, 1, 1, 2), (17.0, 0, 0, 1, 0, 2)]), ["/a", "/b"])
    row_ids = np.empty(table.count, np.int64)
    for row in range(table.count):
        key = (float(table.time[row]), int(table.face_a[row]), int(table.face_b[row]))
        row_ids[row] = {(16.0, 1, 0): 2, (14.0, 1, 1): 1, (17.0, 0, 1): 3, (17.0, 0, 0): 4}[key]
    assert face_regions(table, row_ids, 0, 3).tolist() == [4, 1, NO_REGION_ID]
    assert face_regions(table, row_ids, 1, 2).tolist() == [2, 1]      # face 0 of /b: 16 (region 2) before 17


def test_regions_of_another_table_are_refused(boxes, tmp_path):
    shot, table, regions = boxes
    regions.row_region = regions.row_region[:-1]
    with pytest.raises(ValueError, match="contact rows"):
        override_layer(shot, range(len(shot.meshes)), table, tmp_path / "x.usdksl.usda", regions=regions)


def test_meshes_inside_instances_get_their_regions(tmp_path):
    path = tmp_path / "instanced.usda"
    stage = new_stage(path)
    points, counts, indices = grid(4, 4, 2.0, 2.0)
    define_mesh(stage, "/Prototypes/Prop/Geo", points, counts, indices)
    for name, x in (("A", 0.0), ("B", 5.0)):
        instance = UsdGeom.Xform.Define(stage, f"/World/{name}")
        instance.AddTranslateOp().Set(Gf.Vec3d(x, 0.0, 0.0))
        instance.GetPrim().GetReferences().AddInternalReference("/Prototypes/Prop")
        instance.GetPrim().SetInstanceable(True)
    stage.GetPrimAtPath("/Prototypes").SetSpecifier(Sdf.SpecifierClass)
    cube_points, cube_counts, cube_indices = box(0.4)
    define_mesh(stage, "/World/Falling", None, cube_counts, cube_indices,
                samples={1.0: cube_points + [0.5, 1.0, 0.5], 24.0: cube_points + [0.5, -1.0, 0.5]})
    stage.GetRootLayer().Save()
    shot = load_shot(str(path))
    paths = [mesh.path for mesh in shot.meshes]
    geo_a, geo_b, falling = paths.index("/World/A/Geo"), paths.index("/World/B/Geo"), paths.index("/World/Falling")
    table = find_contacts(shot.meshes, [(geo_a, falling), (geo_b, falling)]).face_contacts(shot.meshes)
    assert table.count and set(table.mesh_a.tolist()) | set(table.mesh_b.tolist()) == {geo_a, falling}
    regions = hand_regions(table, np.zeros(table.count, int))
    layered, _ = write_layer(shot, table, regions, tmp_path / "instanced.usdksl.usda")
    assert not layered.GetPrimAtPath("/World/A").IsInstance()           # de-instanced in the review layer only
    values = region_primvar(layered, "/World/A/Geo")
    assert values == expected_face_regions(table, regions, geo_a, shot.meshes[geo_a].face_count)
    assert 1 in values and NO_REGION_ID in values
    assert list(layered.GetPrimAtPath("/World/A/Geo").GetAttribute(ATTR_REGIONS).Get()) == [1]
    assert not layered.GetPrimAtPath("/World/B/Geo").GetAttribute(ATTR_REGIONS)     # instance B is clean
    assert Usd.Stage.Open(str(path)).GetPrimAtPath("/World/A").IsInstance()      # the input keeps its instancing


def test_point_instancer_instances_get_their_region_on_the_instancer(tmp_path):
    falling_instancer(tmp_path / "scatter.usda")
    shot = load_shot(str(tmp_path / "scatter.usda"))
    paths = [mesh.path for mesh in shot.meshes]
    sheet = paths.index("/World/Sheet")
    instances = [index for index, mesh in enumerate(shot.meshes) if mesh.instancer]
    table = find_contacts(shot.meshes, [(sheet, index) for index in instances]).face_contacts(shot.meshes)
    instance_of = {index: shot.meshes[index].instance_index for index in instances}
    # one region per instance (a crate's lid and body together): the side that is not the sheet
    labels = [instance_of[int(b if a == sheet else a)] for a, b in zip(table.mesh_a, table.mesh_b)]
    regions = hand_regions(table, labels)
    assert regions.count == 4
    stage, _ = write_layer(shot, table, regions, tmp_path / "scatter.usdksl.usda")
    instancer = stage.GetPrimAtPath("/World/scatter")
    per_instance = list(instancer.GetAttribute(ATTR_INSTANCE_REGION).Get())
    # oracle: the region of each instance's earliest row
    expected = [NO_REGION_ID] * 5
    earliest = [math.inf] * 5
    for row in range(table.count):
        other = int(table.mesh_b[row] if table.mesh_a[row] == sheet else table.mesh_a[row])
        if table.time[row] < earliest[instance_of[other]]:
            earliest[instance_of[other]] = float(table.time[row])
            expected[instance_of[other]] = int(regions.row_ids[row])
    assert per_instance == expected
    assert per_instance[2] == NO_REGION_ID and sorted(per_instance) == [0, 1, 2, 3, 4]   # instance 2 is invisible
    assert list(instancer.GetAttribute(ATTR_REGIONS).Get()) == [1, 2, 3, 4]
    assert list(instancer.GetAttribute(ATTR_REGION_WITH).Get()) == ["/World/Sheet"] * 4
    # nothing per face of an instance: the prototypes are shared
    for prototype in ("/World/scatter/Prototypes/box", "/World/scatter/Prototypes/crate/lid"):
        assert not UsdGeom.PrimvarsAPI(stage.GetPrimAtPath(prototype)).GetPrimvar("usdksl:region")
    # the sheet's faces name the instances' regions
    assert region_primvar(stage, "/World/Sheet") == expected_face_regions(table, regions, sheet,
                                                                          shot.meshes[sheet].face_count)
    with_names = list(stage.GetPrimAtPath("/World/Sheet").GetAttribute(ATTR_REGION_WITH).Get())
    assert all(name.startswith("/World/scatter[") for name in with_names)


TRIANGLE_COUNTS = [3, 3, 3, 3]
TRIANGLE_INDICES = [0, 1, 4, 0, 4, 5, 1, 2, 3, 1, 3, 4]   # the strip's two quads split in four triangles


def through_the_floor_and_back(path):
    """/World/Changing goes down through a static floor (y = 0 at t = 3.5), its two quads become four triangles
    at t = 12 (a sample at 6, so 6..12 is not checked), and it comes back up through the floor at t = 18."""
    stage = new_stage(path)
    floor = np.array([[-1, 0, -1], [3, 0, -1], [3, 0, 2], [-1, 0, 2]], dtype=np.float64)
    add_mesh(stage, "/World/Floor", floor)
    heights = {1.0: 1.0, 6.0: -1.0, 12.0: -1.0, 24.0: 1.0}
    mesh = add_mesh(stage, "/World/Changing", None, STRIP_COUNTS, STRIP_INDICES,
                    samples={time: STRIP_POINTS + [0, height, 0] for time, height in heights.items()})
    mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray(STRIP_COUNTS), 1.0)
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray(STRIP_INDICES), 1.0)
    mesh.GetFaceVertexCountsAttr().Set(Vt.IntArray(TRIANGLE_COUNTS), 12.0)
    mesh.GetFaceVertexIndicesAttr().Set(Vt.IntArray(TRIANGLE_INDICES), 12.0)
    stage.GetRootLayer().Save()
    return path


def test_a_mesh_whose_topology_changes_gets_regions_per_segment(tmp_path):
    path = through_the_floor_and_back(tmp_path / "changing.usda")
    pieces, _ = load_segments(find_mesh_sources(str(path)), None, lambda *message: None)
    assert len(pieces) == 3
    tables = []
    for segment_range, segment in pieces:
        paths = [mesh.path for mesh in segment.meshes]
        changing, floor = paths.index("/World/Changing"), paths.index("/World/Floor")
        # the changing mesh is left out of the stretch between its two topologies
        pairs = [] if segment_range == (6.0, 12.0) else [(changing, floor)]
        tables.append(find_contacts(segment.meshes, pairs, time_range=segment_range).face_contacts(segment.meshes)
                      if pairs else ContactTable.empty(paths))
    assert tables[0].count == 2 and tables[2].count == 4
    table = ContactTable.concatenate(tables, topology_epochs([segment for _, segment in pieces]))
    # region 1: down through the floor (quads), region 2: back up (triangles)
    regions = hand_regions(table, (table.time > 12.0).astype(int))
    segments = [(segment_range, segment, segment_table) for (segment_range, segment), segment_table
                in zip(pieces, tables)]
    stage, _ = write_layer(pieces[0][1], table, regions, tmp_path / "changing.usdksl.usda", segments=segments)
    assert region_primvar(stage, "/World/Changing", 3.0) == [1, 1]          # the two quads, in region 1
    assert region_primvar(stage, "/World/Changing", 20.0) == [2, 2, 2, 2]    # the four triangles, in region 2
    # the floor keeps its one face: the region of its first contact
    assert region_primvar(stage, "/World/Floor") == [1]
    assert list(stage.GetPrimAtPath("/World/Floor").GetAttribute(ATTR_REGIONS).Get()) == [1, 2]
    assert list(stage.GetPrimAtPath("/World/Changing").GetAttribute(ATTR_REGION_WITH).Get()) == ["/World/Floor"] * 2


@pytest.mark.parametrize("sample", ["drape.usda", "pass_through.usda", "fold.usda"])
def test_the_regions_of_a_check_read_back_per_face(samples_dir, sample, tmp_path):
    from usdksl import check_shot
    from usdksl.pipeline.files import OutputTargets

    result = check_shot(str(samples_dir / sample), targets=OutputTargets(out_dir=tmp_path))
    regions = result.regions
    assert regions.count >= 1 and regions.row_region.shape[0] == result.table.count
    shot = load_shot(str(samples_dir / sample))
    assert [mesh.path for mesh in shot.meshes] == result.table.paths
    stage, _ = write_layer(shot, result.table, regions, tmp_path / "sample.usdksl.usda")
    touched = set(result.table.mesh_a.tolist()) | set(result.table.mesh_b.tolist())
    for index in sorted(touched):
        mesh = shot.meshes[index]
        values = region_primvar(stage, mesh.path)
        assert values == expected_face_regions(result.table, regions, index, mesh.face_count), mesh.path
        own = (regions.mesh_a == index) | (regions.mesh_b == index)
        arrays = region_arrays(stage, mesh.path)
        assert list(arrays[ATTR_REGIONS]) == regions.ids[own].tolist()
        assert list(arrays[ATTR_REGION_MAX_DEPTH]) == regions.max_depth[own].tolist()
        assert list(arrays[ATTR_REGION_FIRST_FRAME]) == result.clock.frames(regions.first_time[own]).tolist()
        assert list(arrays[ATTR_REGION_DEPTH_MEASURE]) == regions.depth_measure[own].tolist()
        assert set(values) - {NO_REGION_ID} <= set(regions.ids[own].tolist()) and set(values) != {NO_REGION_ID}
