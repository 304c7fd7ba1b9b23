"""A production-like cloth shot at any size, and ``usdksl check`` measured on it end to end.

    python benchmarks/production_shot.py generate --triangles 1000000 --frames 480 --out shot.usdc
    python benchmarks/production_shot.py measure --triangles 150000 --frames 240 480 --threads 2 --chunks 4 \\
        --markdown benchmarks/results/production_shot.md [--keep DIR]

What a studio checks: one garment (an open tube, a dress, about 2/3 of the triangles) on a deforming
character body (a closed capsule, about 1/3), a sample at every frame from frame 1001 at 24 fps, in
centimetres (metersPerUnit 0.01), Y up. The body breathes, twists and sways on a curved path (sines of
different periods, so no vertex moves on a straight line between samples); the garment follows it a few
frames late and :data:`GARMENT_GAP` off its surface, and its hem hangs below the body and swings. The first
half of the shot has no contact. In the second half the body bulges locally through the garment (a
penetration of the closed body) and the hem is pinched flat until its front and back walls pass through
each other (self contact of the garment); both are local, so the face pairs in contact grow with the
resolution (thousands to tens of thousands at 1M triangles), not with the square of it.

``generate`` streams: it computes one frame's points at a time and saves the crate file every
:data:`FLUSH_BYTES` of samples (a ``.usdc`` layer saved to the file it was saved to before appends the new
samples and lets go of them), so its memory does not grow with the frames (1M triangles x 480 frames are
about 2.9 GB of float32 points).

``measure`` generates each shot (into a temporary folder unless ``--keep``) and runs ``usdksl check SHOT
--out DIR [--threads T]`` on it in a process of its own, measured from outside by benchmarks/harness.py.
Printed per shot: triangles, frames, wall and CPU seconds, peak resident memory, bytes of it per triangle
and per triangle-frame, the exit code and the summary line; then the peak memory of the longest shot over
the shortest's (:data:`PEAK_RATIO_TARGET` when the frames double). ``--chunks N`` also checks the longest
shot as N farm chunks (``--time-range A B`` cut at whole frames, each reaching the next one's first frame),
joins them with ``usdksl merge`` and compares the merged contacts.csv with the whole run's byte for byte.
The machine is shared and has 2 cores: compare the ratios of one run, not seconds across runs.
"""

from __future__ import annotations

import argparse
import filecmp
import math
import os
import shutil
import sys
import tempfile
import time as wallclock
from dataclasses import dataclass
from typing import Dict, List, Optional, Sequence, Tuple

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
REPO = os.path.dirname(HERE)
sys.path.insert(0, os.path.join(REPO, "samples"))
from generate import capsule_faces, tube  # noqa: E402
from shotwriter import define_mesh, new_stage, smoothstep  # noqa: E402

from harness import MIB, Build, byte_compile_usdksl, load_average, run  # noqa: E402

# --------------------------------------------------------------------------- the shot's frame

#: First frame (time code) of the shot, as studios number them.
START_FRAME = 1001
#: Scene units are centimetres.
METERS_PER_UNIT = 0.01
#: Triangles (all meshes) and frames when not given.
DEFAULT_TRIANGLES = 150_000
DEFAULT_FRAMES = 240
DEFAULT_SEED = 7
#: Share of the triangles in the body; the garment has the rest.
BODY_SHARE = 1.0 / 3.0
BODY_PATH = "/World/Character/Body"
GARMENT_PATH = "/World/Character/Dress"
#: Bytes of points set on the stage between two saves of the crate file (bounds the writer's memory).
FLUSH_BYTES = 64 * MIB

# --------------------------------------------------------------------------- the body (cm, frames)

#: Radius and half length of the capsule's cylinder (cm); its centre's height (cm).
BODY_RADIUS = 15.0
BODY_HALF_LENGTH = 50.0
BODY_CENTRE_Y = 100.0
#: Breathing: relative change of the radius, and its period (frames).
BREATH = 0.03
BREATH_PERIOD = 72.0
#: Sway of the whole character on a Lissajous curve: amplitudes (cm) and periods (frames) in X and Z.
SWAY = (5.0, 3.0)
SWAY_PERIOD = (96.0, 61.0)
#: Vertical bob (cm, frames).
BOB = 1.5
BOB_PERIOD = 37.0
#: Sideways bend (cm at the body's ends, growing with the square of the height from its centre; frames).
LEAN = 2.5
LEAN_PERIOD = 83.0
#: Twist about the body's axis (degrees, frames).
TWIST_DEGREES = 6.0
TWIST_PERIOD = 71.0

# --------------------------------------------------------------------------- the garment (cm, frames)

#: Distance between the body's surface and the garment at rest (cm). The garment's lag moves it at most
#: about 1.8 cm towards the body (sway, bend and breathing over GARMENT_LAG frames, plus WRINKLE), so the
#: first half of the shot keeps at least 1 cm of clearance.
GARMENT_GAP = 3.0
#: The garment's top edge and its hem (cm): it is longer than the body, whose lowest point is at 35 cm.
GARMENT_TOP_Y = 140.0
GARMENT_HEM_Y = 10.0
#: The skirt widens by this much (cm) from the body's lower end down to the hem.
GARMENT_FLARE = 4.0
#: Frames the garment's motion trails the body's.
GARMENT_LAG = 2.0
#: Radial wrinkles: amplitude (cm), number of travelling waves, their periods (frames) and lengths (cm).
WRINKLE = 0.4
WRINKLE_WAVES = 3
WRINKLE_PERIOD = (30.0, 60.0)
WRINKLE_LENGTH = (20.0, 45.0)
#: The hem below the body swings on its own: amplitudes (cm, X and Z) and periods (frames).
HEM_SWING = (3.0, 2.0)
HEM_SWING_PERIOD = (45.0, 29.0)
#: Angular offset of the garment's vertex columns, as a share of one column: the front and back walls then
#: never mirror each other vertex for vertex, so their crossing is not degenerate.
COLUMN_OFFSET = 0.25

# --------------------------------------------------------------------------- contact in the second half

#: Share of the shot (0 first frame, 1 last) before which nothing touches.
CONTACT_START = 0.5
#: The bulge: peak height (cm; above GARMENT_GAP plus the lag's reach, so it pokes through), width (cm,
#: the Gaussian's 1/e radius along and around the body), height of its centre (cm), angle (radians, +Z is
#: the front), and the share of the shot over which it grows.
BULGE = 5.5
BULGE_WIDTH = 6.0
BULGE_Y = 95.0
BULGE_ANGLE = 0.5 * math.pi
BULGE_GROWTH = 0.35
#: The pinch of the hem: at its full strength the front and back walls have each moved PINCH_MAX times the
#: radius towards the other (past 1, they have crossed); it acts where |cos(angle)| is within about
#: PINCH_WIDTH (the front and back), and below PINCH_TOP_Y (cm) over PINCH_RAMP (cm), below the body.
PINCH_MAX = 1.3
PINCH_WIDTH = 0.4
PINCH_TOP_Y = 26.0
PINCH_RAMP = 10.0
#: Share of the shot after CONTACT_START where the pinch starts, and over which it grows.
PINCH_DELAY = 0.05
PINCH_GROWTH = 0.3

# --------------------------------------------------------------------------- measuring

#: Most peak memory of the longest shot over the shortest's when the frames double: the check's memory
#: should grow with the triangles, hardly with the frames.
PEAK_RATIO_TARGET = 1.2
#: Wall seconds a check may take before it is killed, when --budget is not given.
DEFAULT_BUDGET_S = 4 * 3600.0


# --------------------------------------------------------------------------- meshes

def closed_capsule(radius: float, half_length: float, segments: int, rings: int):
    """A closed capsule along +Y with ``rings`` latitude rings spaced evenly along its profile (hemisphere,
    cylinder, hemisphere; samples/generate.py's capsule has a single row on its cylinder, too coarse for a
    local bulge): quads between rings, triangle fans at the poles, outward facing. Returns (points,
    counts, indices, angle of each vertex around the axis, radius of its ring)."""
    cap = 0.5 * math.pi * radius
    profile = 2 * cap + 2 * half_length
    s = profile * np.arange(1, rings + 1) / (rings + 1)        # arc length from the top pole
    top, bottom = s < cap, s > cap + 2 * half_length
    theta_top, theta_bottom = s / radius, (profile - s) / radius
    heights = np.where(top, half_length + radius * np.cos(theta_top),
                       np.where(bottom, -half_length - radius * np.cos(theta_bottom), cap + half_length - s))
    radii = np.where(top, radius * np.sin(theta_top), np.where(bottom, radius * np.sin(theta_bottom), radius))
    phi = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    angle = np.concatenate([np.tile(phi, rings), [0.0, 0.0]])
    ring_radius = np.concatenate([np.repeat(radii, segments), [0.0, 0.0]])
    height = np.concatenate([np.repeat(heights, segments), [half_length + radius, -half_length - radius]])
    points = np.stack([ring_radius * np.cos(angle), height, ring_radius * np.sin(angle)], axis=1)
    counts, indices = capsule_faces(segments, rings)
    return points, counts, indices, angle, ring_radius


def triangle_count(counts: np.ndarray) -> int:
    """Triangles of a polygon mesh as the check fans it."""
    return int(np.sum(np.asarray(counts, dtype=np.int64) - 2))


def _wrapped(angle: np.ndarray) -> np.ndarray:
    """An angle difference brought into [-pi, pi)."""
    return (angle + math.pi) % (2 * math.pi) - math.pi


def _wave(amplitude: float, period: float, phase: float, time: float) -> float:
    return amplitude * math.sin(2 * math.pi * time / period + phase)


# --------------------------------------------------------------------------- the shot

@dataclass
class ShotSize:
    """What ``write_shot`` wrote."""

    path: str
    triangles: int
    body_triangles: int
    garment_triangles: int
    vertices: int
    frames: int
    file_bytes: int
    seconds: float


class ProductionShot:
    """The body and the garment of one shot: topology and rest parameters, built once, and the points of
    each at any frame, computed in closed form (vectorised over vertices)."""

    def __init__(self, triangles: int = DEFAULT_TRIANGLES, frames: int = DEFAULT_FRAMES, seed: int = DEFAULT_SEED):
        if frames < 3:
            raise ValueError("need at least 3 frames")
        if triangles < 500:
            raise ValueError("need at least 500 triangles")
        self.frames = frames
        rng = np.random.default_rng(seed)
        self._phases = dict(zip(("sway_x", "sway_z", "bob", "lean", "twist", "breath", "hem_x", "hem_z"),
                                rng.uniform(0, 2 * math.pi, size=8)))
        self._build_body(int(round(triangles * BODY_SHARE)))
        self._build_garment(triangles - triangle_count(self.body_counts), rng)

    # ----------------------------------------------------------------- topology and rest parameters

    def _build_body(self, triangles: int) -> None:
        profile = math.pi * BODY_RADIUS + 2 * BODY_HALF_LENGTH
        aspect = profile / (2 * math.pi * BODY_RADIUS)                  # rings per segment, square quads
        segments = max(8, int(round(math.sqrt(triangles / (2 * aspect)))))
        rings = max(4, int(round(triangles / (2 * segments))))
        points, self.body_counts, self.body_indices, self._body_angle, self._body_ring = closed_capsule(
            BODY_RADIUS, BODY_HALF_LENGTH, segments, rings)
        self._body_y = points[:, 1] + BODY_CENTRE_Y
        along = (self._body_y - BULGE_Y) / BULGE_WIDTH
        around = _wrapped(self._body_angle - BULGE_ANGLE) * BODY_RADIUS / BULGE_WIDTH
        # the bulge pushes the surface outwards, in proportion to its ring's radius (nothing at the poles)
        self._bulge = np.exp(-along ** 2 - around ** 2) * self._body_ring / BODY_RADIUS
        self._body_bend = ((self._body_y - BODY_CENTRE_Y) / (BODY_HALF_LENGTH + BODY_RADIUS)) ** 2
        self._body_out = np.empty((len(points), 3), dtype=np.float32)

    def _build_garment(self, triangles: int, rng: np.random.Generator) -> None:
        rest_radius = BODY_RADIUS + GARMENT_GAP
        length = GARMENT_TOP_Y - GARMENT_HEM_Y
        quads = max(16, triangles // 2)
        segments = max(8, int(round(math.sqrt(quads * 2 * math.pi * (rest_radius + 0.5 * GARMENT_FLARE) / length))))
        rows = max(4, int(round(quads / segments)))
        points, self.garment_counts, self.garment_indices = tube(1.0, GARMENT_HEM_Y, GARMENT_TOP_Y, segments, rows)
        self.garment_counts = np.asarray(self.garment_counts, dtype=np.int32)
        angle = np.arctan2(points[:, 2], points[:, 0]) + COLUMN_OFFSET * 2 * math.pi / segments
        y = points[:, 1]
        body_bottom = BODY_CENTRE_Y - BODY_HALF_LENGTH - BODY_RADIUS
        flare_top = BODY_CENTRE_Y - BODY_HALF_LENGTH
        self._garment_y = y
        self._garment_radius = rest_radius + GARMENT_FLARE * smoothstep((flare_top - y) / (flare_top - GARMENT_HEM_Y))
        self._garment_cos, self._garment_sin = np.cos(angle), np.sin(angle)
        self._garment_bend = ((y - BODY_CENTRE_Y) / (BODY_HALF_LENGTH + BODY_RADIUS)) ** 2
        self._hang = np.clip((body_bottom - y) / (body_bottom - GARMENT_HEM_Y), 0.0, 1.0) ** 2
        # the pinch moves the front (sin > 0) and the back wall towards each other, in proportion to the radius
        pinched = (np.exp(-(self._garment_cos / PINCH_WIDTH) ** 2)
                   * smoothstep((PINCH_TOP_Y - y) / PINCH_RAMP))
        self._pinch = pinched * self._garment_radius * self._garment_sin
        # travelling wrinkles: whole waves around (the surface closes), seeded directions, lengths and phases
        around = rng.integers(3, 9, size=WRINKLE_WAVES)
        along = 2 * math.pi / rng.uniform(*WRINKLE_LENGTH, size=WRINKLE_WAVES)
        self._wrinkle_speed = 2 * math.pi / rng.uniform(*WRINKLE_PERIOD, size=WRINKLE_WAVES)
        self._wrinkle_phase = (around[:, None] * angle[None, :] + along[:, None] * y[None, :]
                               + rng.uniform(0, 2 * math.pi, size=(WRINKLE_WAVES, 1)))
        self._garment_out = np.empty((len(points), 3), dtype=np.float32)

    # ----------------------------------------------------------------- motion

    @property
    def times(self) -> np.ndarray:
        return START_FRAME + np.arange(self.frames, dtype=np.float64)

    @property
    def middle(self) -> float:
        """The time code half way through the shot: no contact at or before it."""
        return START_FRAME + 0.5 * (self.frames - 1)

    def _share(self, time: float) -> float:
        return (time - START_FRAME) / (self.frames - 1)

    def _character(self, tau: float) -> Dict[str, float]:
        """The motion shared by the body and (GARMENT_LAG frames later) the garment, at frame ``tau`` of the
        shot (0 at its first frame)."""
        p = self._phases
        return {"sway_x": _wave(SWAY[0], SWAY_PERIOD[0], p["sway_x"], tau),
                "sway_z": _wave(SWAY[1], SWAY_PERIOD[1], p["sway_z"], tau),
                "bob": _wave(BOB, BOB_PERIOD, p["bob"], tau),
                "lean": _wave(LEAN, LEAN_PERIOD, p["lean"], tau),
                "twist": math.radians(_wave(TWIST_DEGREES, TWIST_PERIOD, p["twist"], tau)),
                "breath": _wave(BREATH, BREATH_PERIOD, p["breath"], tau)}

    def bulge(self, time: float) -> float:
        """Height of the bulge at ``time`` (cm)."""
        return BULGE * float(smoothstep(np.array((self._share(time) - CONTACT_START) / BULGE_GROWTH)))

    def pinch(self, time: float) -> float:
        """Strength of the pinch at ``time`` (PINCH_MAX at its full)."""
        start = CONTACT_START + PINCH_DELAY
        return PINCH_MAX * float(smoothstep(np.array((self._share(time) - start) / PINCH_GROWTH)))

    def body_points(self, time: float) -> np.ndarray:
        """float32[V, 3] of the body at ``time``; the array is reused by the next call."""
        m = self._character(time - START_FRAME)
        radius = self._body_ring * (1.0 + m["breath"]) + self.bulge(time) * self._bulge
        angle = self._body_angle + m["twist"]
        out = self._body_out
        out[:, 0] = radius * np.cos(angle) + m["sway_x"] + m["lean"] * self._body_bend
        out[:, 1] = self._body_y + m["bob"]
        out[:, 2] = radius * np.sin(angle) + m["sway_z"]
        return out

    def garment_points(self, time: float) -> np.ndarray:
        """float32[V, 3] of the garment at ``time``; the array is reused by the next call."""
        tau = time - START_FRAME
        m = self._character(tau - GARMENT_LAG)
        wrinkle = np.sin(self._wrinkle_phase + self._wrinkle_speed[:, None] * tau).mean(axis=0) * WRINKLE
        radius = self._garment_radius + BODY_RADIUS * m["breath"] + wrinkle
        x = radius * self._garment_cos
        z = radius * self._garment_sin - self.pinch(time) * self._pinch
        cos_twist, sin_twist = math.cos(m["twist"]), math.sin(m["twist"])
        p = self._phases
        hem_x = _wave(HEM_SWING[0], HEM_SWING_PERIOD[0], p["hem_x"], tau)
        hem_z = _wave(HEM_SWING[1], HEM_SWING_PERIOD[1], p["hem_z"], tau)
        out = self._garment_out
        out[:, 0] = x * cos_twist - z * sin_twist + m["sway_x"] + m["lean"] * self._garment_bend + hem_x * self._hang
        out[:, 1] = self._garment_y + m["bob"]
        out[:, 2] = x * sin_twist + z * cos_twist + m["sway_z"] + hem_z * self._hang
        return out

    @property
    def mesh_triangles(self) -> Tuple[int, int]:
        """(body, garment) triangles."""
        return triangle_count(self.body_counts), triangle_count(self.garment_counts)

    @property
    def vertices(self) -> int:
        return len(self._body_out) + len(self._garment_out)


def _extent(points: np.ndarray):
    from pxr import Gf, Vt

    low, high = points.min(axis=0), points.max(axis=0)
    return Vt.Vec3fArray([Gf.Vec3f(*map(float, low)), Gf.Vec3f(*map(float, high))])


def write_shot(path: str, triangles: int = DEFAULT_TRIANGLES, frames: int = DEFAULT_FRAMES,
               seed: int = DEFAULT_SEED) -> ShotSize:
    """Writes the shot to ``path`` (a .usdc), one frame at a time, saving the layer every FLUSH_BYTES of
    samples so that its memory stays that of a few frames."""
    from pxr import UsdGeom, Vt

    started = wallclock.perf_counter()
    shot = ProductionShot(triangles, frames, seed)
    times = shot.times
    stage = new_stage(path, float(times[0]), float(times[-1]))
    UsdGeom.SetStageMetersPerUnit(stage, METERS_PER_UNIT)
    UsdGeom.Xform.Define(stage, "/World/Character")
    body_triangles, garment_triangles = shot.mesh_triangles
    layer = stage.GetRootLayer()
    layer.documentation = (f"usdksl production-like shot: a {garment_triangles}-triangle dress on a deforming "
                           f"{body_triangles}-triangle body, {frames} frames from {START_FRAME}; in the second half "
                           f"the body bulges through the dress and its hem is pinched through itself; seed {seed}")
    meshes = []
    for mesh_path, counts, indices, points, color in (
            (BODY_PATH, shot.body_counts, shot.body_indices, shot.body_points, (0.8, 0.6, 0.5)),
            (GARMENT_PATH, shot.garment_counts, shot.garment_indices, shot.garment_points, (0.3, 0.4, 0.8))):
        mesh = define_mesh(stage, mesh_path, counts, indices, color=color)
        meshes.append((mesh.GetPointsAttr(), mesh.CreateExtentAttr(), points))
    layer.Save()     # the crate file exists from here on: later saves append to it
    unsaved = 0
    for time in times:
        for points_attr, extent_attr, points_at in meshes:
            points = points_at(float(time))
            points_attr.Set(Vt.Vec3fArray.FromNumpy(points), float(time))
            extent_attr.Set(_extent(points), float(time))
            unsaved += points.nbytes
        if unsaved >= FLUSH_BYTES:
            layer.Save()
            unsaved = 0
    layer.Save()
    del stage, layer, meshes
    return ShotSize(path, body_triangles + garment_triangles, body_triangles, garment_triangles, shot.vertices,
                    frames, os.path.getsize(path), wallclock.perf_counter() - started)


# --------------------------------------------------------------------------- measuring the check

def chunk_ranges(first: int, last: int, chunks: int) -> List[Tuple[int, int]]:
    """``chunks`` time ranges cut at whole frames that cover [first, last], each ending on the next one's
    first frame (what ``usdksl merge`` joins exactly)."""
    if chunks < 1 or chunks > last - first:
        raise ValueError(f"cannot cut frames {first}..{last} into {chunks} chunks of at least one frame interval")
    cuts = np.round(np.linspace(first, last, chunks + 1)).astype(int)
    return [(int(a), int(b)) for a, b in zip(cuts[:-1], cuts[1:])]


def _threads(threads: Optional[int]) -> List[str]:
    return [] if threads is None else ["--threads", str(threads)]


def summary_line(stderr: str) -> str:
    """The check's last line on stderr (its summary)."""
    lines = [line for line in stderr.strip().splitlines() if line.strip()]
    return lines[-1] if lines else ""


def contact_rows(out_dir: str, stem: str) -> int:
    path = os.path.join(out_dir, stem + ".contacts.csv")
    if not os.path.exists(path):
        return 0
    with open(path) as stream:
        return sum(1 for _ in stream) - 1


def check_whole(usdksl: str, size: ShotSize, out_dir: str, threads: Optional[int], budget_s: float) -> Dict:
    """``usdksl check`` of one shot in a process of its own: its measurement and what it printed."""
    measured = run([usdksl, "check", size.path, "--out", out_dir, *_threads(threads)], timeout_s=budget_s)
    stem = os.path.splitext(os.path.basename(size.path))[0]
    return {"triangles": size.triangles, "frames": size.frames, "vertices": size.vertices,
            "file_mib": size.file_bytes / MIB, "generate_s": size.seconds, "wall_s": measured.wall_s,
            "cpu_s": measured.cpu_s, "peak_bytes": measured.peak_rss_bytes, "exit_code": measured.exit_code,
            "timed_out": measured.timed_out, "face_pairs": contact_rows(out_dir, stem),
            "summary": summary_line(measured.stderr)}


def check_in_chunks(usdksl: str, size: ShotSize, whole_dir: str, work: str, chunks: int,
                    threads: Optional[int], budget_s: float) -> Dict:
    """The shot checked as farm chunks, merged, and the merged contacts.csv held to the whole run's."""
    stem = os.path.splitext(os.path.basename(size.path))[0]
    parts = []
    for first, last in chunk_ranges(START_FRAME, START_FRAME + size.frames - 1, chunks):
        part_dir = os.path.join(work, f"chunk_{first}_{last}")
        measured = run([usdksl, "check", size.path, "--time-range", str(first), str(last), "--out", part_dir,
                        *_threads(threads)], timeout_s=budget_s)
        parts.append({"range": (first, last), "dir": part_dir, "wall_s": measured.wall_s, "cpu_s": measured.cpu_s,
                      "peak_bytes": measured.peak_rss_bytes, "exit_code": measured.exit_code,
                      "summary": summary_line(measured.stderr)})
    merged_dir = os.path.join(work, "merged")
    merged = run([usdksl, "merge", size.path, *[part["dir"] for part in parts], "--out", merged_dir],
                 timeout_s=budget_s)
    name = stem + ".contacts.csv"
    whole, joined = os.path.join(whole_dir, name), os.path.join(merged_dir, name)
    same = os.path.exists(whole) and os.path.exists(joined) and filecmp.cmp(whole, joined, shallow=False)
    return {"chunks": parts, "merge_wall_s": merged.wall_s, "merge_exit_code": merged.exit_code,
            "merge_summary": summary_line(merged.stderr), "same": same}


def render(rows: Sequence[Dict], chunked: Optional[Dict], threads: Optional[int], load: float) -> str:
    """The results as markdown: a table of the shots, the peak ratio and the chunks."""
    lines = [f"usdksl check on production-like shots (a dress on a deforming body, a sample at every frame), "
             f"threads={threads or 'all'}, load average {load:.2f} at the start",
             "",
             "| triangles | vertices | frames | file MiB | wall s | CPU s | peak MiB | peak B/triangle | "
             "peak B/triangle-frame | face pairs | exit |",
             "|---|---|---|---|---|---|---|---|---|---|---|"]
    for row in rows:
        lines.append(f"| {row['triangles']} | {row['vertices']} | {row['frames']} | {row['file_mib']:.1f} | "
                     f"{row['wall_s']:.1f} | {row['cpu_s']:.1f} | {row['peak_bytes'] / MIB:.0f} | "
                     f"{row['peak_bytes'] / row['triangles']:.0f} | "
                     f"{row['peak_bytes'] / (row['triangles'] * row['frames']):.1f} | {row['face_pairs']} | "
                     f"{row['exit_code']}{' (timed out)' if row['timed_out'] else ''} |")
    lines += [""] + [f"- {row['frames']} frames: `{row['summary']}`" for row in rows]
    shortest, longest = min(rows, key=lambda row: row["frames"]), max(rows, key=lambda row: row["frames"])
    if longest["frames"] > shortest["frames"]:
        ratio = longest["peak_bytes"] / shortest["peak_bytes"]
        lines += ["", f"Peak memory of the {longest['frames']}-frame shot over the {shortest['frames']}-frame shot's "
                  f"({longest['frames'] / shortest['frames']:g}x the frames): {ratio:.2f} (target: at most "
                  f"{PEAK_RATIO_TARGET:g} when the frames double; "
                  f"{'met' if ratio <= PEAK_RATIO_TARGET else 'NOT met'})"]
    if chunked is not None:
        lines += ["", f"The {longest['frames']}-frame shot as {len(chunked['chunks'])} farm chunks:", "",
                  "| time range | wall s | CPU s | peak MiB | exit |", "|---|---|---|---|---|"]
        lines += [f"| {part['range'][0]} {part['range'][1]} | {part['wall_s']:.1f} | {part['cpu_s']:.1f} | "
                  f"{part['peak_bytes'] / MIB:.0f} | {part['exit_code']} |" for part in chunked["chunks"]]
        lines += ["", f"usdksl merge: {chunked['merge_wall_s']:.1f} s, exit {chunked['merge_exit_code']}: "
                  f"`{chunked['merge_summary']}`", "", f"chunks merged == whole: {chunked['same']}"]
    return "\n".join(lines)


def measure(triangles: int, frames: Sequence[int], threads: Optional[int], chunks: Optional[int],
            keep: Optional[str], budget_s: float, seed: int = DEFAULT_SEED,
            echo=print) -> Tuple[List[Dict], Optional[Dict]]:
    """Generates a shot of ``triangles`` for each of ``frames`` and checks it; with ``chunks``, checks the
    longest also in chunks. Returns (a row per shot, the chunked run or None)."""
    usdksl = Build.current().usdksl
    work = keep or tempfile.mkdtemp(prefix="usdksl-production-")
    os.makedirs(work, exist_ok=True)
    rows, outs, sizes = [], {}, {}
    try:
        for count in sorted(set(frames)):
            path = os.path.join(work, f"production_{triangles}_f{count}.usdc")
            size = write_shot(path, triangles, count, seed)
            echo(f"generated {path}: {size.triangles} triangles (body {size.body_triangles}, dress "
                 f"{size.garment_triangles}), {size.vertices} vertices, {count} frames, "
                 f"{size.file_bytes / MIB:.1f} MiB in {size.seconds:.1f} s")
            outs[count], sizes[count] = os.path.join(work, f"check_f{count}"), size
            row = check_whole(usdksl, size, outs[count], threads, budget_s)
            rows.append(row)
            echo(f"  {row['triangles']} triangles x {row['frames']} frames: wall {row['wall_s']:.1f} s, CPU "
                 f"{row['cpu_s']:.1f} s, peak {row['peak_bytes'] / MIB:.0f} MiB "
                 f"({row['peak_bytes'] / row['triangles']:.0f} B/triangle, "
                 f"{row['peak_bytes'] / (row['triangles'] * row['frames']):.1f} B/triangle-frame), "
                 f"exit {row['exit_code']}{' (timed out)' if row['timed_out'] else ''}")
            echo(f"  {row['summary']}")
        chunked = None
        if chunks:
            longest = max(sizes)
            chunked = check_in_chunks(usdksl, sizes[longest], outs[longest], os.path.join(work, "chunks"), chunks,
                                      threads, budget_s)
            for part in chunked["chunks"]:
                echo(f"  chunk {part['range'][0]} {part['range'][1]}: wall {part['wall_s']:.1f} s, peak "
                     f"{part['peak_bytes'] / MIB:.0f} MiB, exit {part['exit_code']}")
            echo(f"  merge: exit {chunked['merge_exit_code']}: {chunked['merge_summary']}")
            echo(f"chunks merged == whole: {chunked['same']}")
    finally:
        if keep is None:
            shutil.rmtree(work, ignore_errors=True)
    return rows, chunked


# --------------------------------------------------------------------------- command line

def main(argv: Optional[List[str]] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    make = commands.add_parser("generate", help="write one shot (streaming)")
    make.add_argument("--triangles", type=int, default=DEFAULT_TRIANGLES, help="all triangles (body and dress)")
    make.add_argument("--frames", type=int, default=DEFAULT_FRAMES)
    make.add_argument("--seed", type=int, default=DEFAULT_SEED)
    make.add_argument("--out", required=True, help="the .usdc to write")
    check = commands.add_parser("measure", help="generate shots and measure usdksl check on each")
    check.add_argument("--triangles", type=int, default=DEFAULT_TRIANGLES)
    check.add_argument("--frames", type=int, nargs="+", default=[DEFAULT_FRAMES, 2 * DEFAULT_FRAMES])
    check.add_argument("--seed", type=int, default=DEFAULT_SEED)
    check.add_argument("--threads", type=int, default=None, help="threads of the check (default: its own)")
    check.add_argument("--chunks", type=int, default=None, help="also check the longest shot as N farm chunks")
    check.add_argument("--budget", type=float, default=DEFAULT_BUDGET_S, help="wall seconds per check")
    check.add_argument("--markdown", help="also write the results to this file")
    check.add_argument("--keep", help="generate into this folder and keep shots and outputs")
    args = parser.parse_args(argv)
    if args.command == "generate":
        size = write_shot(args.out, args.triangles, args.frames, args.seed)
        print(f"{size.path}: {size.triangles} triangles (body {size.body_triangles}, dress {size.garment_triangles}), "
              f"{size.vertices} vertices, {size.frames} frames from {START_FRAME}, "
              f"{size.file_bytes / MIB:.1f} MiB in {size.seconds:.1f} s")
        return 0
    byte_compile_usdksl()
    load = load_average()
    rows, chunked = measure(args.triangles, args.frames, args.threads, args.chunks, args.keep, args.budget, args.seed)
    table = render(rows, chunked, args.threads, load)
    print(table)
    if args.markdown:
        with open(args.markdown, "w") as stream:
            stream.write("# Production-like shot\n\nCommand: `python benchmarks/production_shot.py "
                         f"{' '.join(argv if argv is not None else sys.argv[1:])}`\n\n{table}\n")
    return 0 if chunked is None or chunked["same"] else 1


if __name__ == "__main__":
    sys.exit(main())
