"""Pictures of contact regions for the HTML report: what a person sees where two surfaces go through
each other.

One PNG per region, rendered off-screen by VTK (through PyVista: no display, no GPU; VTK's EGL or OSMesa
window with Mesa's software rasteriser where there is no X server) at the region's ``max_depth_time``, the
meshes' points interpolated linearly between their samples as the check moves them:

* only the neighbourhood of the region is drawn: the triangles of its two meshes that come within
  :data:`NEIGHBOURHOOD_BOX_SIZES` region sizes of its centre (a whole shot would hide the problem);
* the region's faces of side a are :data:`SIDE_A_COLOR`, those of side b :data:`SIDE_B_COLOR` (for a self
  region a face of both sides is side a's colour), with their edges where the faces are large enough on
  screen (:data:`MIN_EDGE_PIXELS`); the rest of each mesh is a neutral grey;
* the camera looks at the region's centre from the one of :data:`VIEW_DIRECTIONS` in which both sides'
  faces show most (each candidate is rendered flat and small, and the visible pixels of the rarer side
  counted; ties go to the earlier direction), at a distance that frames :data:`FRAME_BOX_SIZES` region
  sizes. The view rule depends on the geometry only, so the same shot gives the same picture.

The region's size is the largest extent of its box at ``max_depth_time`` (RegionTable.box_min/box_max),
never less than the largest of its faces there, so a grazing touch (an empty box) still shows whole faces.

PyVista and VTK are an optional dependency (``pip install 'usdksl[report]'``), imported only when pictures
are asked for.
"""

from __future__ import annotations

import io
from contextlib import contextmanager
from typing import Dict, Iterator, List, Sequence, Tuple

import numpy as np

from ..contacts.table import ContactTable
from ..errors import UsdkslUsageError
from ..reading.positions import points_at
from ..regions.table import RegionTable

#: The line a user sees when PyVista or VTK is missing.
INSTALL_HINT = "--report needs PyVista and VTK for its region pictures: pip install 'usdksl[report]'"
#: Picture size in pixels (width, height).
DEFAULT_SIZE = (640, 420)
#: Radius of the drawn neighbourhood around the region's centre, in region sizes.
NEIGHBOURHOOD_BOX_SIZES = 2.5
#: Radius around the region's centre that the camera's view height frames, in region sizes.
FRAME_BOX_SIZES = 0.75
#: Vertical view angle of the camera (degrees).
VIEW_ANGLE_DEGREES = 30.0
#: Edges are drawn on a side's region faces when its median face spans at least this many pixels at the
#: region's distance (finer meshes would turn into a mesh of dark lines).
MIN_EDGE_PIXELS = 8.0
#: Width in pixels of the flat renders that score each candidate view (their height keeps the picture's
#: aspect).
SCORE_WIDTH = 160
#: A pixel of a flat render counts for a side when no channel is further than this from the side's colour
#: (0-255 steps: rasteriser rounding, not shading, since the scoring render is unlit).
SCORE_COLOR_TOLERANCE = 8
#: Candidate view directions (from the region's centre towards the camera, world space), in the order that
#: breaks ties: the four three-quarter views from above (+y is USD's default up axis), then the four from
#: below. Three-quarter views show two sides of a box and never a sheet edge-on.
VIEW_DIRECTIONS = np.array([[1, 1, 1], [-1, 1, 1], [-1, 1, -1], [1, 1, -1],
                            [1, -1, 1], [-1, -1, 1], [-1, -1, -1], [1, -1, -1]], dtype=np.float64)
#: The camera's up vector: +y, USD's default up axis (no candidate view looks along it).
VIEW_UP = (0.0, 1.0, 0.0)
#: A stage whose upAxis is Z (simulators, Houdini setups) is viewed with Y and Z of the rule above swapped,
#: so "from above" stays above.
Z_UP_SWAP = [0, 2, 1]


def view_rule(up_axis: str = "Y") -> Tuple[np.ndarray, Tuple[float, float, float]]:
    """(candidate view directions, camera up) for a stage's upAxis ("Y" or "Z")."""
    if str(up_axis).upper() == "Z":
        return VIEW_DIRECTIONS[:, Z_UP_SWAP], tuple(float(value) for value in np.asarray(VIEW_UP)[Z_UP_SWAP])
    return VIEW_DIRECTIONS, VIEW_UP
#: Anti-aliasing of the final picture (VTK's SSAA: FXAA is not available off-screen; the scoring renders
#: have none, so their colours stay exact).
ANTI_ALIASING = "ssaa"
#: Lighting of the final picture, fixed to the camera so every view is lit alike (from below as from above):
#: a light at the camera and a key light above and right of it (camera coordinates), their intensities, and
#: the share of ambient light, so faces turned away from both stay readable.
KEY_LIGHT_POSITION = (0.7, 1.0, 0.6)
HEAD_LIGHT_INTENSITY = 0.45
KEY_LIGHT_INTENSITY = 0.55
AMBIENT = 0.3
DIFFUSE = 0.7
#: Colours: the region's faces of side a and of side b, the rest of side a's and side b's mesh, the edges
#: drawn on the region's faces, the background.
SIDE_A_COLOR = "#e8590c"
SIDE_B_COLOR = "#1971c2"
NEUTRAL_A_COLOR = "#d6d0c8"
NEUTRAL_B_COLOR = "#b9bfc6"
EDGE_COLOR = "#3b3b3b"
BACKGROUND_COLOR = "#ffffff"
#: Flat colours of the scoring render: side a, side b, everything else (the rest of the meshes occludes).
SCORE_A_RGB = (255, 0, 0)
SCORE_B_RGB = (0, 0, 255)
SCORE_OTHER_RGB = (0, 0, 0)
#: Triangle classes: not in the region, a face of side a, a face of side b.
NEUTRAL, SIDE_A, SIDE_B = 0, 1, 2


def require_pyvista():
    """The pyvista module; UsdkslUsageError (exit 2, one line naming the extra) when it or VTK is missing."""
    try:
        import pyvista
        import vtkmodules.vtkCommonCore  # noqa: F401
    except ImportError:
        raise UsdkslUsageError(INSTALL_HINT) from None
    return pyvista


def triangle_classes(mesh, faces_a: np.ndarray, faces_b: np.ndarray, side_a: bool, side_b: bool) -> np.ndarray:
    """int8[M]: NEUTRAL, SIDE_A or SIDE_B per triangle of ``mesh``, which is the region's side a and/or side b
    (both for a self region; then a face of both sides is SIDE_A)."""
    faces = np.asarray(mesh.triangle_face)
    classes = np.full(faces.shape[0], NEUTRAL, np.int8)
    if side_b:
        classes[np.isin(faces, faces_b)] = SIDE_B
    if side_a:
        classes[np.isin(faces, faces_a)] = SIDE_A
    return classes


def near_triangles(points: np.ndarray, triangles: np.ndarray, centre: np.ndarray, radius: float) -> np.ndarray:
    """bool[M]: triangles whose bounding box comes within ``radius`` of ``centre`` (so a large face that
    passes by the centre is kept even when its corners are far)."""
    corners = points[triangles]                       # [M, 3, 3]
    nearest = np.clip(centre, corners.min(axis=1), corners.max(axis=1))
    return np.einsum("ij,ij->i", nearest - centre, nearest - centre) <= radius * radius


def triangle_extents(points: np.ndarray, triangles: np.ndarray) -> np.ndarray:
    """float64[M]: each triangle's largest extent along an axis."""
    corners = points[triangles]
    return (corners.max(axis=1) - corners.min(axis=1)).max(axis=1)


def largest_triangle_extent(points: np.ndarray, triangles: np.ndarray) -> float:
    """The largest extent along any axis of any of ``triangles`` (0 for none)."""
    return float(triangle_extents(points, triangles).max()) if triangles.shape[0] else 0.0


def region_frame(regions: RegionTable, row: int, region_points: Sequence[np.ndarray],
                 region_triangles: Sequence[np.ndarray]) -> Tuple[np.ndarray, float]:
    """(centre float64[3], size) of region row ``row``: its box at max_depth_time, never smaller than the
    largest of its faces there (``region_points``/``region_triangles``: each side's points at that time and
    its region triangles). Without a finite box the centre is that of the region's faces."""
    low, high = np.asarray(regions.box_min[row], float), np.asarray(regions.box_max[row], float)
    face_size = max((largest_triangle_extent(p, t) for p, t in zip(region_points, region_triangles)), default=0.0)
    if np.isfinite(low).all() and np.isfinite(high).all():
        centre = np.asarray(regions.center[row], float)
        if not np.isfinite(centre).all():
            centre = (low + high) / 2.0
        size = float((high - low).max())
    else:
        used = [p[np.unique(t)] for p, t in zip(region_points, region_triangles) if t.shape[0]]
        if not used:
            raise ValueError(f"region row {row} has neither a finite box nor faces to frame")
        stacked = np.concatenate(used)
        low, high = stacked.min(axis=0), stacked.max(axis=0)
        centre, size = (low + high) / 2.0, float((high - low).max())
    size = max(size, face_size)
    if not size > 0.0:
        size = 1.0      # a region of degenerate faces at one point: any scale shows it
    return centre, size


def _hex_rgb(color: str) -> Tuple[int, int, int]:
    return tuple(int(color[i:i + 2], 16) for i in (1, 3, 5))


def count_color(image: np.ndarray, rgb: Tuple[int, int, int]) -> int:
    """Pixels of ``image`` (uint8[H, W, 3+]) within SCORE_COLOR_TOLERANCE of ``rgb``."""
    close = np.abs(image[..., :3].astype(np.int16) - np.asarray(rgb, np.int16)) <= SCORE_COLOR_TOLERANCE
    return int(close.all(axis=-1).sum())


def best_view(scores: np.ndarray) -> int:
    """Index of the best candidate view from ``scores`` int[V, 2] (visible pixels of side a, side b): the most
    pixels of the side that shows less, then the most of both, then the earliest."""
    scores = np.asarray(scores, dtype=np.int64)
    rarer, total = scores.min(axis=1), scores.sum(axis=1)
    return int(np.lexsort((np.arange(scores.shape[0]), -total, -rarer))[0])


@contextmanager
def _vtk_warnings_off() -> Iterator[None]:
    """VTK first tries an X server for its window and warns ("bad X server connection") before it falls back
    to an off-screen one: a report has no use for that line."""
    from vtkmodules.vtkCommonCore import vtkObject

    shown = vtkObject.GetGlobalWarningDisplay()
    vtkObject.GlobalWarningDisplayOff()
    try:
        yield
    finally:
        vtkObject.SetGlobalWarningDisplay(shown)


class _Part:
    """One drawn piece: the triangles of one class of one mesh, with its final and scoring looks."""

    def __init__(self, pyvista, points: np.ndarray, triangles: np.ndarray, color: str, score_rgb, edges: bool):
        used, local = np.unique(triangles, return_inverse=True)
        self.mesh = pyvista.PolyData.from_regular_faces(points[used], local.reshape(-1, 3))
        self.color, self.score_rgb, self.edges = color, score_rgb, edges
        self.actor = None

    def add(self, plotter) -> None:
        self.actor = plotter.add_mesh(self.mesh, color=self.color, show_edges=self.edges, edge_color=EDGE_COLOR,
                                      line_width=1.0, smooth_shading=False, ambient=AMBIENT, diffuse=DIFFUSE,
                                      specular=0.0, reset_camera=False)

    def scoring(self) -> None:
        prop = self.actor.prop
        prop.color, prop.lighting, prop.show_edges = tuple(c / 255.0 for c in self.score_rgb), False, False

    def final(self) -> None:
        prop = self.actor.prop
        prop.color, prop.lighting, prop.show_edges = self.color, True, self.edges


def region_parts(pyvista, meshes: Sequence, table: ContactTable, regions: RegionTable, row: int,
                 height: int) -> Tuple[List[_Part], np.ndarray, float]:
    """The drawn pieces of region row ``row`` at its max_depth_time in a picture ``height`` pixels high, and its
    frame (centre, size)."""
    time = float(regions.max_depth_time[row])
    a, b = int(regions.mesh_a[row]), int(regions.mesh_b[row])
    faces_a, faces_b = regions.faces(row, table)
    sides = [a] if a == b else [a, b]
    points = {index: points_at(meshes[index], time) for index in sides}
    classes = {index: triangle_classes(meshes[index], faces_a, faces_b, index == a, index == b) for index in sides}
    region_tris = [np.asarray(meshes[index].triangles)[classes[index] != NEUTRAL] for index in sides]
    centre, size = region_frame(regions, row, [points[index] for index in sides], region_tris)
    pixels_per_unit = height / (2.0 * FRAME_BOX_SIZES * size)
    parts = []
    for index in sides:
        triangles = np.asarray(meshes[index].triangles)
        near = near_triangles(points[index], triangles, centre, NEIGHBOURHOOD_BOX_SIZES * size)
        neutral = NEUTRAL_A_COLOR if index == a else NEUTRAL_B_COLOR
        for kind, color, score_rgb in ((NEUTRAL, neutral, SCORE_OTHER_RGB), (SIDE_A, SIDE_A_COLOR, SCORE_A_RGB),
                                       (SIDE_B, SIDE_B_COLOR, SCORE_B_RGB)):
            chosen = triangles[near & (classes[index] == kind)]
            if chosen.shape[0]:
                edges = (kind != NEUTRAL and
                         float(np.median(triangle_extents(points[index], chosen))) * pixels_per_unit >= MIN_EDGE_PIXELS)
                parts.append(_Part(pyvista, points[index], chosen, color, score_rgb, edges=edges))
    return parts, centre, size


def _aim(plotter, centre: np.ndarray, size: float, direction: np.ndarray, up=VIEW_UP) -> None:
    unit = direction / np.linalg.norm(direction)
    distance = FRAME_BOX_SIZES * size / np.sin(np.radians(VIEW_ANGLE_DEGREES) / 2.0)
    camera = plotter.camera
    camera.view_angle = VIEW_ANGLE_DEGREES
    camera.focal_point = tuple(centre)
    camera.position = tuple(centre + distance * unit)
    camera.up = up
    plotter.renderer.ResetCameraClippingRange()


def _render(plotter, size: Tuple[int, int]) -> np.ndarray:
    plotter.window_size = list(size)
    return np.asarray(plotter.screenshot(return_img=True))


def chosen_view(plotter, parts: Sequence[_Part], centre: np.ndarray, size: float,
                picture: Tuple[int, int], up_axis: str = "Y") -> np.ndarray:
    """The direction of the view rule (:func:`view_rule`) in which both sides show most in a ``picture``
    (width, height) of the region (see the module docstring)."""
    directions, up = view_rule(up_axis)
    for part in parts:
        part.scoring()
    score_size = (SCORE_WIDTH, max(1, round(SCORE_WIDTH * picture[1] / picture[0])))
    scores = []
    for direction in directions:
        _aim(plotter, centre, size, direction, up)
        image = _render(plotter, score_size)
        scores.append((count_color(image, SCORE_A_RGB), count_color(image, SCORE_B_RGB)))
    for part in parts:
        part.final()
    return directions[best_view(np.array(scores))]


def _png(image: np.ndarray) -> bytes:
    """PNG bytes of uint8[H, W, 3] (no metadata: the same pixels give the same bytes)."""
    from PIL import Image

    buffer = io.BytesIO()
    Image.fromarray(np.ascontiguousarray(image[..., :3])).save(buffer, format="PNG")
    return buffer.getvalue()


def region_pictures(meshes: Sequence, table: ContactTable, regions: RegionTable, region_rows: Sequence[int],
                    size: Tuple[int, int] = DEFAULT_SIZE, up_axis: str = "Y") -> Dict[int, bytes]:
    """{region row: PNG bytes} for each of ``region_rows`` (rows of ``regions``; its mesh indices index
    ``meshes``, the loader's MeshData or anything with times, points, triangles, triangle_face), viewed
    with the stage's ``up_axis`` up."""
    rows = [int(row) for row in region_rows]
    if not rows:
        return {}
    pyvista = require_pyvista()
    pictures: Dict[int, bytes] = {}
    with _vtk_warnings_off():
        plotter = pyvista.Plotter(off_screen=True, window_size=list(size), theme=pyvista.themes.Theme(),
                                  lighting="none")
        try:
            plotter.add_light(pyvista.Light(light_type="headlight", intensity=HEAD_LIGHT_INTENSITY))
            plotter.add_light(pyvista.Light(position=KEY_LIGHT_POSITION, light_type="camera light",
                                            intensity=KEY_LIGHT_INTENSITY))
            plotter.set_background(BACKGROUND_COLOR)
            for row in rows:
                parts, centre, extent = region_parts(pyvista, meshes, table, regions, row, size[1])
                for part in parts:
                    part.add(plotter)
                _aim(plotter, centre, extent, chosen_view(plotter, parts, centre, extent, size, up_axis),
                     view_rule(up_axis)[1])
                plotter.enable_anti_aliasing(ANTI_ALIASING)
                pictures[row] = _png(_render(plotter, size))
                plotter.disable_anti_aliasing()
                for part in parts:
                    plotter.remove_actor(part.actor, render=False)
        finally:
            plotter.close()
    return pictures


__all__ = ["DEFAULT_SIZE", "INSTALL_HINT", "SIDE_A_COLOR", "SIDE_B_COLOR", "best_view", "near_triangles",
           "points_at", "region_frame", "region_pictures", "require_pyvista", "triangle_classes"]
