"""Region pictures (usdksl.reports.pictures): rendered off-screen by VTK on a real scene, a box through a
sheet with its real contacts, at the region's deepest time; the region's faces in the two side colours, the
camera on the region."""

import io
import os
import subprocess
import sys
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest
from matplotlib.colors import rgb_to_hsv, to_rgb
from PIL import Image

from usdksl.checking.collision import find_contacts
from usdksl.errors import UsdkslUsageError
from usdksl.regions.table import INTERSECTION_LENGTH, RegionTable
from usdksl.reports.pictures import (INSTALL_HINT, NEIGHBOURHOOD_BOX_SIZES, SIDE_A, SIDE_A_COLOR, SIDE_B,
                                     SIDE_B_COLOR, best_view, near_triangles, points_at, region_frame,
                                     region_pictures, triangle_classes)

from browser.report_scene import BOXES, contacts, hand_regions, scene
from builders import folding_sheet

REPO_ROOT = Path(__file__).resolve().parents[2]
#: A pixel shows a side's colour when its hue is this close to the colour's (0-1 hue circle) and it is at
#: least this saturated: lighting scales a colour's value, not its hue or saturation, and the neutral greys
#: are below 0.1.
HUE_TOLERANCE = 0.04
MIN_SATURATION = 0.45
#: Share of the picture each side's colour covers at least in the scene's pictures.
MIN_SIDE_SHARE = 0.02
#: Distinct colours a picture of shaded faces has at least (one flat colour is a blank picture).
MIN_DISTINCT_COLORS = 50


@pytest.fixture(scope="module")
def shot():
    meshes = scene()
    table = contacts(meshes)
    regions = hand_regions(meshes, table)
    return meshes, table, regions


@pytest.fixture(scope="module")
def pictures(shot):
    meshes, table, regions = shot
    return region_pictures(meshes, table, regions, [0, 1])


def pixels(png: bytes) -> np.ndarray:
    image = Image.open(io.BytesIO(png))
    assert image.format == "PNG"
    return np.asarray(image.convert("RGB"))


def side_mask(image: np.ndarray, color: str) -> np.ndarray:
    """bool[H, W]: pixels of ``color``'s hue, however lit."""
    hsv = rgb_to_hsv(image / 255.0)
    hue = rgb_to_hsv(np.array(to_rgb(color)))[0]
    distance = np.abs(hsv[..., 0] - hue)
    return (np.minimum(distance, 1.0 - distance) <= HUE_TOLERANCE) & (hsv[..., 1] >= MIN_SATURATION)


def distinct_colors(image: np.ndarray) -> int:
    return int(np.unique(image.reshape(-1, 3), axis=0).shape[0])


def test_the_scene_has_real_contacts_in_two_regions(shot):
    meshes, table, regions = shot
    assert table.count > 0
    assert regions.count == 2 and np.bincount(regions.row_region).tolist() == regions.face_pairs.tolist()
    # both boxes are deepest at time 5, the big one half its edge deep, the small one half of its own
    assert regions.max_depth.tolist() == [0.5, 0.25] and regions.max_depth_time.tolist() == [5.0, 5.0]
    faces_a, faces_b = regions.faces(0, table)
    assert faces_a.size and faces_b.size


def test_points_move_linearly_between_samples_and_hold_outside(shot):
    meshes = shot[0]
    small = meshes[2]
    path, edge, xz, times, heights = BOXES[1]
    centre = lambda points: points.mean(axis=0)     # noqa: E731  (the cube's vertices are symmetric)
    # time 5 lies between the small box's samples at 4 (height 0.2) and 6 (-0.2): halfway, at the sheet
    assert centre(points_at(small, 5.0)) == pytest.approx([xz[0], 0.0, xz[1]], abs=1e-12)
    assert centre(points_at(small, 4.5))[1] == pytest.approx(0.1)
    assert np.array_equal(points_at(small, 4.0), small.points[1])
    assert np.array_equal(points_at(small, -3.0), small.points[0])
    assert np.array_equal(points_at(small, 99.0), small.points[-1])
    assert np.array_equal(points_at(meshes[1], 5.0), meshes[1].points[0])     # a static mesh


def test_the_region_frame_is_its_box_never_smaller_than_its_faces(shot):
    meshes, table, regions = shot
    empty = [np.zeros((0, 3))]
    centre, size = region_frame(regions, 0, [meshes[0].points[0]], [np.zeros((0, 3), np.int64)])
    assert centre.tolist() == pytest.approx([-1.4, 0.0, -0.9]) and size == pytest.approx(1.0)
    # a region whose box is flat in every direction (a point) is as large as its largest face
    point = replace(regions, box_min=regions.center.copy(), box_max=regions.center.copy())
    big_faces = np.array([[0, 1, 2]])
    corners = [np.array([[0.0, 0.0, 0.0], [0.3, 0.0, 0.0], [0.0, 0.2, 0.0]])]
    assert region_frame(point, 0, corners, [big_faces])[1] == pytest.approx(0.3)
    # without a finite box the region's faces give the centre and size
    unknown = replace(regions, box_min=np.full((2, 3), np.nan), box_max=np.full((2, 3), np.nan),
                      center=np.full((2, 3), np.nan))
    centre, size = region_frame(unknown, 0, corners, [big_faces])
    assert centre.tolist() == pytest.approx([0.15, 0.1, 0.0]) and size == pytest.approx(0.3)
    with pytest.raises(ValueError):
        region_frame(unknown, 0, empty, [np.zeros((0, 3), np.int64)])


def test_the_neighbourhood_holds_what_is_near_the_region_only(shot):
    meshes, table, regions = shot
    radius = NEIGHBOURHOOD_BOX_SIZES * 1.0
    centre = regions.center[0]
    sheet = near_triangles(meshes[1].points[0], meshes[1].triangles, centre, radius)
    small_box = near_triangles(points_at(meshes[2], 5.0), meshes[2].triangles, centre, radius)
    assert not small_box.any()                       # the other box is about 4.4 units away
    assert 0 < sheet.sum() < sheet.size              # a patch of the sheet, not all of it
    # a large triangle whose corners are all far but which passes through the centre is kept
    big = np.array([[-10.0, 0.0, -10.0], [10.0, 0.0, -10.0], [0.0, 0.0, 10.0]]) + centre
    assert near_triangles(big, np.array([[0, 1, 2]]), centre, 0.1).tolist() == [True]


def test_faces_of_both_sides_of_a_self_region_take_side_a_first(shot):
    sheet = shot[0][1]
    classes = triangle_classes(sheet, np.array([3, 4]), np.array([4, 5]), True, True)
    by_face = {int(face): int(kind) for face, kind in zip(sheet.triangle_face, classes)}
    assert (by_face[3], by_face[4], by_face[5], by_face[6]) == (SIDE_A, SIDE_A, SIDE_B, 0)


def test_the_view_shows_the_rarer_side_most_then_both_then_the_earliest():
    assert best_view(np.array([[50, 0], [3, 3], [3, 4], [4, 3], [2, 9]])) == 2
    assert best_view(np.array([[1, 1], [1, 1]])) == 0


def test_each_picture_shows_both_sides_in_their_colours_and_is_not_blank(pictures):
    assert sorted(pictures) == [0, 1]
    for png in pictures.values():
        image = pixels(png)
        assert image.shape == (420, 640, 3)
        assert distinct_colors(image) >= MIN_DISTINCT_COLORS
        for color in (SIDE_A_COLOR, SIDE_B_COLOR):
            assert side_mask(image, color).mean() >= MIN_SIDE_SHARE, color


def test_the_camera_follows_the_region(pictures):
    first, second = pixels(pictures[0]), pixels(pictures[1])
    assert np.abs(first.astype(int) - second.astype(int)).mean() > 10     # another place, another picture
    height, width = first.shape[:2]
    for image in (first, second):
        rows, columns = np.nonzero(side_mask(image, SIDE_A_COLOR) | side_mask(image, SIDE_B_COLOR))
        # the region is framed in the middle of the picture
        assert abs(rows.mean() - height / 2) < 0.15 * height and abs(columns.mean() - width / 2) < 0.15 * width


def test_the_same_regions_give_the_same_bytes(shot, pictures):
    meshes, table, regions = shot
    assert region_pictures(meshes, table, regions, [1, 0]) == pictures


def test_no_rows_ask_for_nothing(shot, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyvista", None)     # pyvista is not even imported
    assert region_pictures(*shot, []) == {}


def test_without_pyvista_the_error_names_the_extra(shot, monkeypatch):
    monkeypatch.setitem(sys.modules, "pyvista", None)
    with pytest.raises(UsdkslUsageError) as raised:
        region_pictures(*shot, [0])
    assert str(raised.value) == INSTALL_HINT and "\n" not in INSTALL_HINT
    assert "pip install 'usdksl[report]'" in INSTALL_HINT


RENDER_WITHOUT_DISPLAY = """
import sys
sys.path.insert(0, {tests!r})
from browser.report_scene import contacts, hand_regions, scene
from usdksl.reports.pictures import region_pictures
meshes = scene()
table = contacts(meshes)
png = region_pictures(meshes, table, hand_regions(meshes, table), [0])[0]
sys.stdout.write(str(len(png)) + " " + png[:8].hex())
"""


def test_pictures_render_without_a_display_and_vtk_says_nothing():
    environment = {key: value for key, value in os.environ.items() if key not in ("DISPLAY", "WAYLAND_DISPLAY")}
    done = subprocess.run([sys.executable, "-c", RENDER_WITHOUT_DISPLAY.format(tests=str(REPO_ROOT / "tests"))],
                          env=environment, capture_output=True, text=True, cwd=REPO_ROOT)
    assert done.returncode == 0, done.stderr
    size, signature = done.stdout.split()
    assert int(size) > 1000 and signature == "89504e470d0a1a0a"      # a PNG
    assert done.stderr == ""                                          # no "bad X server connection"


def test_a_self_region_without_a_box_shows_its_two_sides_on_one_mesh():
    """A sheet folding through itself (one mesh): the region has no box (framed on its faces) and its depth is
    an intersection length."""
    sheet = folding_sheet(n=12, samples=9)
    table = find_contacts([sheet], [(0, 0)]).face_contacts([sheet])
    unknown = np.full((1, 3), np.nan)
    regions = RegionTable(paths=None, mesh_a=np.zeros(1, np.int32), mesh_b=np.zeros(1, np.int32),
                          first_time=table.time[:1], last_time=np.array([8.0]), face_pairs=np.array([table.count]),
                          depth_measure=np.array([INTERSECTION_LENGTH], object), max_depth=np.array([1.0]),
                          max_depth_time=np.array([7.5]), max_intersection_length=np.array([1.0]), center=unknown,
                          box_min=unknown, box_max=unknown, row_region=np.zeros(table.count, np.int32))
    faces_a, faces_b = regions.faces(0, table)
    assert np.setdiff1d(faces_b, faces_a).size > 0        # some faces are side b only
    image = pixels(region_pictures([sheet], table, regions, [0])[0])
    assert distinct_colors(image) >= MIN_DISTINCT_COLORS
    for color in (SIDE_A_COLOR, SIDE_B_COLOR):
        assert side_mask(image, color).mean() >= MIN_SIDE_SHARE, color
