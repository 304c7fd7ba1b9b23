"""Generate larger benchmark shots (not committed) into samples/generated/.

    python samples/generate.py tablecloth --faces 16000 --keyframes 11 --samples-per-keyframe 10
    python samples/generate.py swirl      --faces 8000
    python samples/generate.py character  --triangles 60000
    python samples/generate.py flutter    --faces 800 --frames 48

Motion is defined at K keyframes; between two keyframes, S samples are written that
interpolate the keyframes linearly (keyframe k sits at time code 1 + k*S, samples at every
integer time code), so the motion is piecewise linear in the keyframes and densely
resampled, which is what the paper's Fig. 10 varies. Files are .usdc written via pxr from
numpy arrays; the scenes are deterministic for a given --seed.

- tablecloth: a cloth falls onto a table (a top and four legs, static) and hangs over its
              edges with seeded wrinkles. --faces 2000..16000.
- swirl:      a square cloth gathers and twists into a swirl that folds over itself (heavy
              self contact). --faces 4000..33000.
- character:  a walking figure of capsules (torso, head, arms, legs; rigid, driven by
              animated xformOps on parent Xforms) wearing a deforming tube shirt that the
              swinging arms brush. --triangles 35000..90000 (all meshes together).

One scene is written the way simulator caches look instead (``PerFrameShot``): a sample at
every frame (time codes 1..--frames) of motion evaluated in closed form, so vertices move on
curves and no three consecutive samples of a moving vertex are collinear; --keyframes and
--samples-per-keyframe do not apply to it.

- flutter:    a cloth falls on a parabola onto a table, then rests on its top (a gap of
              FLUTTER_REST_GAP) for most of the shot while every vertex circles in place and
              the overhang flutters against the table's sides; a pendulum ball swings on an
              arc through the hanging cloth. --faces 100..20000, small enough for unit tests.
"""

from __future__ import annotations

import argparse
import math
import os
import sys
import time as wallclock
from typing import Callable, List, Optional

import numpy as np
from pxr import Gf, Usd, UsdGeom, Vt

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from shotwriter import box, define_mesh, grid, smoothstep  # noqa: E402

HERE = os.path.dirname(os.path.abspath(__file__))
GENERATED = os.path.join(HERE, "generated")
TIME_CODES_PER_SECOND = 24.0


# --------------------------------------------------------------------------- writing

class KeyframedShot:
    """Collects meshes whose motion is given at keyframes, then writes dense linear samples."""

    def __init__(self, keyframes: int, samples_per_keyframe: int):
        if keyframes < 2 or samples_per_keyframe < 1:
            raise ValueError("need at least 2 keyframes and 1 sample per keyframe")
        self.keyframes = keyframes
        self.samples_per_keyframe = samples_per_keyframe
        self.keyframe_u = np.linspace(0.0, 1.0, keyframes)   # normalised shot time of each key
        self._writers: List[Callable[[Usd.Stage], None]] = []

    @property
    def sample_times(self) -> np.ndarray:
        count = (self.keyframes - 1) * self.samples_per_keyframe + 1
        return 1.0 + np.arange(count, dtype=np.float64)

    def _blend(self, time: float):
        """(key index k, weight a) so a sample is (1 - a) * key[k] + a * key[k + 1]."""
        position = (time - 1.0) / self.samples_per_keyframe
        k = min(int(position), self.keyframes - 2)
        return k, position - k

    def static_mesh(self, path, counts, indices, points, color=None):
        self._writers.append(lambda stage: define_mesh(stage, path, counts, indices,
                                                       points=points, color=color))

    def deforming_mesh(self, path, counts, indices, shape: Callable[[float], np.ndarray],
                       color=None):
        """``shape(u)`` gives the points at normalised time u in [0, 1]; sampled at the keys."""
        keys = np.stack([shape(float(u)) for u in self.keyframe_u]).astype(np.float32)

        def write(stage):
            mesh = define_mesh(stage, path, counts, indices, points=None, samples={}, color=color)
            attribute = mesh.GetPointsAttr()
            frame = np.empty_like(keys[0])
            for time in self.sample_times:
                k, a = self._blend(time)
                np.multiply(keys[k], np.float32(1.0 - a), out=frame)
                frame += np.float32(a) * keys[k + 1]
                attribute.Set(Vt.Vec3fArray.FromNumpy(frame), float(time))
        self._writers.append(write)

    def animated_xform(self, path, translate: Callable[[float], tuple],
                       rotate_xyz: Optional[Callable[[float], tuple]] = None):
        """An Xform whose translate (and XYZ Euler rotation, degrees) are keyed then resampled."""
        t_keys = np.array([translate(float(u)) for u in self.keyframe_u], dtype=np.float64)
        r_keys = (np.array([rotate_xyz(float(u)) for u in self.keyframe_u], dtype=np.float64)
                  if rotate_xyz else None)

        def write(stage):
            xform = UsdGeom.Xform.Define(stage, path)
            translate_op = xform.AddTranslateOp()
            rotate_op = xform.AddRotateXYZOp() if r_keys is not None else None
            for time in self.sample_times:
                k, a = self._blend(time)
                translate_op.Set(Gf.Vec3d(*((1 - a) * t_keys[k] + a * t_keys[k + 1])), float(time))
                if rotate_op is not None:
                    rotate_op.Set(Gf.Vec3f(*((1 - a) * r_keys[k] + a * r_keys[k + 1])), float(time))
        self._writers.append(write)

    def save(self, path: str, note: str) -> None:
        if os.path.exists(path):
            os.remove(path)
        stage = Usd.Stage.CreateNew(path)
        stage.SetTimeCodesPerSecond(TIME_CODES_PER_SECOND)
        stage.SetFramesPerSecond(TIME_CODES_PER_SECOND)
        stage.SetStartTimeCode(float(self.sample_times[0]))
        stage.SetEndTimeCode(float(self.sample_times[-1]))
        UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.y)
        UsdGeom.SetStageMetersPerUnit(stage, 1.0)
        stage.SetDefaultPrim(UsdGeom.Xform.Define(stage, "/World").GetPrim())
        stage.GetRootLayer().documentation = note
        for write in self._writers:
            write(stage)
        stage.GetRootLayer().Save()


class PerFrameShot(KeyframedShot):
    """A shot sampled at every frame (time codes 1..frames) from closed-form motion, like a simulator
    cache: ``shape(time_code)`` and the xform callables are evaluated at each frame, not keyframed."""

    def __init__(self, frames: int):
        if frames < 3:
            raise ValueError("need at least 3 frames")
        self.frames = frames
        self._writers: List[Callable[[Usd.Stage], None]] = []

    @property
    def sample_times(self) -> np.ndarray:
        return 1.0 + np.arange(self.frames, dtype=np.float64)

    def deforming_mesh(self, path, counts, indices, shape: Callable[[float], np.ndarray], color=None):
        """``shape(t)`` gives the points at time code t; written at every frame."""
        def write(stage):
            mesh = define_mesh(stage, path, counts, indices, points=None, samples={}, color=color)
            attribute = mesh.GetPointsAttr()
            for time in self.sample_times:
                attribute.Set(Vt.Vec3fArray.FromNumpy(np.asarray(shape(float(time)), np.float32)), float(time))
        self._writers.append(write)

    def animated_xform(self, path, translate: Callable[[float], tuple],
                       rotate_xyz: Optional[Callable[[float], tuple]] = None):
        """An Xform whose translate (and XYZ Euler rotation, degrees) are given per time code."""
        def write(stage):
            xform = UsdGeom.Xform.Define(stage, path)
            translate_op = xform.AddTranslateOp()
            rotate_op = xform.AddRotateXYZOp() if rotate_xyz is not None else None
            for time in self.sample_times:
                translate_op.Set(Gf.Vec3d(*translate(float(time))), float(time))
                if rotate_op is not None:
                    rotate_op.Set(Gf.Vec3f(*rotate_xyz(float(time))), float(time))
        self._writers.append(write)


# --------------------------------------------------------------------------- shapes

def grid_for_faces(faces: int, aspect: float):
    """Columns and rows of a quad grid with about ``faces`` quads and columns/rows ~ aspect."""
    columns = max(2, int(round(math.sqrt(faces * aspect))))
    rows = max(2, int(round(faces / columns)))
    return columns, rows


def wrinkles(rng: np.random.Generator, x: np.ndarray, z: np.ndarray, waves: int = 6) -> np.ndarray:
    """A seeded sum of plane waves in [-1, 1]."""
    out = np.zeros_like(x)
    for _ in range(waves):
        angle = rng.uniform(0, 2 * math.pi)
        frequency = rng.uniform(6.0, 14.0)
        phase = rng.uniform(0, 2 * math.pi)
        out += np.sin(frequency * (math.cos(angle) * x + math.sin(angle) * z) + phase)
    return out / waves


def capsule(radius: float, half_length: float, segments: int, rings: int):
    """A closed capsule along +Y: quads everywhere, triangle fans at the two poles."""
    # latitude rings: hemisphere rings, then the cylinder part shares the equator rings
    theta = np.linspace(0.0, math.pi / 2, rings + 1)[1:]              # from the top pole down
    heights = np.concatenate([half_length + radius * np.cos(theta),
                              -half_length - radius * np.cos(theta[::-1])])
    radii = np.concatenate([radius * np.sin(theta), radius * np.sin(theta[::-1])])
    phi = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    ring_points = np.stack([np.outer(radii, np.cos(phi)).ravel(),
                            np.repeat(heights, segments),
                            np.outer(radii, np.sin(phi)).ravel()], axis=1)
    top = np.array([[0.0, half_length + radius, 0.0]])
    bottom = np.array([[0.0, -half_length - radius, 0.0]])
    points = np.concatenate([ring_points, top, bottom])
    counts, indices = capsule_faces(segments, heights.size)
    return points, counts, indices


def capsule_faces(segments: int, ring_count: int):
    """(counts, indices) int32 of a closed surface of ``ring_count`` rings of ``segments`` points (ring by
    ring from the top, then the top and the bottom pole): quads between rings, triangle fans at the poles,
    outward facing."""
    top_index, bottom_index = ring_count * segments, ring_count * segments + 1
    s = np.arange(segments)
    s_next = (s + 1) % segments
    top_fan = np.stack([np.full(segments, top_index), s_next, s], axis=1)
    r = np.arange(ring_count - 1)[:, None]
    quads = np.stack([r * segments + s, r * segments + s_next,
                      (r + 1) * segments + s_next, (r + 1) * segments + s], axis=2).reshape(-1, 4)
    last = (ring_count - 1) * segments
    bottom_fan = np.stack([np.full(segments, bottom_index), last + s, last + s_next], axis=1)
    counts = np.concatenate([np.full(segments, 3), np.full(len(quads), 4), np.full(segments, 3)])
    indices = np.concatenate([top_fan.ravel(), quads.ravel(), bottom_fan.ravel()])
    return counts.astype(np.int32), indices.astype(np.int32)


def capsule_triangles(segments: int, rings: int) -> int:
    return 2 * segments + 2 * segments * (2 * rings - 1)


def tube(radius: float, y0: float, y1: float, segments: int, rows: int):
    """An open cylinder along Y (quads)."""
    phi = np.linspace(0.0, 2 * math.pi, segments, endpoint=False)
    ys = np.linspace(y0, y1, rows + 1)
    points = np.stack([np.tile(radius * np.cos(phi), rows + 1), np.repeat(ys, segments),
                       np.tile(radius * np.sin(phi), rows + 1)], axis=1)
    s = np.arange(segments)
    r = np.arange(rows)[:, None]
    quads = np.stack([r * segments + s, (r + 1) * segments + s,
                      (r + 1) * segments + (s + 1) % segments, r * segments + (s + 1) % segments],
                     axis=2).reshape(-1, 4)
    return points, np.full(len(quads), 4, dtype=np.int32), quads.ravel().astype(np.int32)


# --------------------------------------------------------------------------- scenes

def scene_tablecloth(shot: KeyframedShot, faces: int, rng: np.random.Generator) -> str:
    top_half = np.array([0.6, 0.025, 0.4])
    top_center = np.array([0.0, 0.75, 0.0])
    table_top = top_center[1] + top_half[1]
    points, counts, indices = box(top_center, top_half)
    shot.static_mesh("/World/Table/Top", counts, indices, points, color=(0.45, 0.3, 0.2))
    for i, (sx, sz) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
        leg_points, leg_counts, leg_indices = box((sx * 0.55, 0.3625, sz * 0.35), (0.03, 0.3625, 0.03))
        shot.static_mesh(f"/World/Table/Leg{i}", leg_counts, leg_indices, leg_points,
                         color=(0.45, 0.3, 0.2))

    columns, rows = grid_for_faces(faces, 1.8 / 1.4)
    flat, cloth_counts, cloth_indices = grid(columns, rows, 1.8, 1.4)
    x, z = flat[:, 0], flat[:, 2]
    margin = 0.03
    overhang = np.maximum(np.maximum(np.abs(x) - top_half[0], np.abs(z) - top_half[2]) - margin, 0.0)
    pull = 0.35 * overhang      # hanging cloth moves in a little, keeping it a height field
    rest = np.stack([x - np.sign(x) * pull * (np.abs(x) - top_half[0] > margin),
                     table_top + 0.002 - 1.1 * overhang
                     + 0.04 * overhang / max(overhang.max(), 1e-9) * wrinkles(rng, x, z),
                     z - np.sign(z) * pull * (np.abs(z) - top_half[2] > margin)], axis=1)
    start_height = 1.6
    drop = start_height - rest[:, 1].min()

    def cloth(u: float) -> np.ndarray:
        settle = min(u / 0.8, 1.0)
        falling = start_height - drop * settle * settle
        out = flat.copy()
        blend = float(smoothstep(np.array(settle)))
        out[:, 0] = (1 - blend) * x + blend * rest[:, 0]
        out[:, 2] = (1 - blend) * z + blend * rest[:, 2]
        out[:, 1] = np.maximum(rest[:, 1], falling)
        return out

    shot.deforming_mesh("/World/Cloth", cloth_counts, cloth_indices, cloth, color=(0.8, 0.8, 0.9))
    return f"tablecloth: {len(cloth_counts)} cloth faces falling on a table"


def scene_swirl(shot: KeyframedShot, faces: int, rng: np.random.Generator) -> str:
    columns, rows = grid_for_faces(faces, 1.0)
    flat, counts, indices = grid(columns, rows, 2.0, 2.0)
    x, z = flat[:, 0], flat[:, 2]
    radius = np.hypot(x, z)
    angle = np.arctan2(z, x)
    r_max = radius.max()
    ripple_phase = rng.uniform(0, 2 * math.pi)

    def cloth(u: float) -> np.ndarray:
        gather = float(smoothstep(np.array(u)))
        folded = 0.35 + 0.2 * np.sin(5 * math.pi * radius / r_max + ripple_phase)
        r = (1 - 0.8 * gather) * radius + 0.8 * gather * folded
        twist = angle + 2.5 * math.pi * gather * (1 - radius / r_max) ** 2
        height = 1.0 - 0.4 * gather + 0.06 * gather * np.sin(6 * twist + 9 * radius)
        return np.stack([r * np.cos(twist), height, r * np.sin(twist)], axis=1)

    shot.deforming_mesh("/World/Cloth", counts, indices, cloth, color=(0.3, 0.6, 0.9))
    return f"swirl: {len(counts)} cloth faces twisting and folding over themselves"


def scene_character(shot: KeyframedShot, triangles: int, rng: np.random.Generator) -> str:
    # split the triangle budget: shirt 60 %, six capsules 40 %
    shirt_triangles = int(0.6 * triangles)
    capsule_budget = (triangles - shirt_triangles) // 6
    segments = max(8, int(math.sqrt(capsule_budget / 4)) * 2)
    rings = max(2, int(round((capsule_budget / (2 * segments) + 1) / 2)))
    steps = rng.uniform(0.9, 1.1)

    shot.animated_xform("/World/Character",
                        translate=lambda u: (0.0, 0.0, 1.5 * u * steps),
                        rotate_xyz=lambda u: (0.0, 10.0 * math.sin(2 * math.pi * u), 0.0))
    torso_points, c_counts, c_indices = capsule(0.15, 0.22, segments, rings)
    shot.static_mesh("/World/Character/Torso", c_counts, c_indices,
                     torso_points + (0.0, 1.2, 0.0), color=(0.8, 0.6, 0.5))
    head_points, h_counts, h_indices = capsule(0.1, 0.02, segments, rings)
    shot.static_mesh("/World/Character/Head", h_counts, h_indices,
                     head_points + (0.0, 1.68, 0.0), color=(0.8, 0.6, 0.5))

    limb_points, l_counts, l_indices = capsule(0.05, 0.22, segments, rings)
    hanging = limb_points - (0.0, 0.27, 0.0)     # pivot at the top end
    swing = 2 * math.pi * 2.3                    # strides incommensurate with any key spacing
    for side, sign in (("Left", 1.0), ("Right", -1.0)):
        # arms swing forward/back and inward: at the inner extreme they brush the shirt
        shot.animated_xform(f"/World/Character/{side}Shoulder",
                            translate=lambda u, s=sign: (s * 0.24, 1.4, 0.0),
                            rotate_xyz=lambda u, s=sign: (35.0 * math.sin(swing * u),
                                                          0.0, s * (8.0 + 6.0 * math.cos(swing * u))))
        shot.static_mesh(f"/World/Character/{side}Shoulder/Arm", l_counts, l_indices, hanging,
                         color=(0.8, 0.6, 0.5))
        shot.animated_xform(f"/World/Character/{side}Hip",
                            translate=lambda u, s=sign: (s * 0.09, 0.95, 0.0),
                            rotate_xyz=lambda u, s=sign: (-30.0 * s * math.sin(swing * u), 0.0, 0.0))
        shot.static_mesh(f"/World/Character/{side}Hip/Leg", l_counts, l_indices,
                         hanging * (1.0, 1.8, 1.0), color=(0.3, 0.3, 0.5))

    shirt_segments = max(16, int(math.sqrt(shirt_triangles / 2 * 2.0)))
    shirt_rows = max(4, int(shirt_triangles / 2 / shirt_segments))
    shirt_flat, s_counts, s_indices = tube(0.19, 0.95, 1.45, shirt_segments, shirt_rows)
    phi = np.arctan2(shirt_flat[:, 2], shirt_flat[:, 0])
    height = (shirt_flat[:, 1] - 0.95) / 0.5
    wrinkle_phase = rng.uniform(0, 2 * math.pi, size=3)

    def shirt(u: float) -> np.ndarray:
        # the shirt sways with the stride and its hem flutters; radius stays above the torso's
        bulge = (0.012 * np.sin(7 * phi + wrinkle_phase[0] + swing * u)
                 + 0.02 * (1 - height) * np.sin(3 * phi + wrinkle_phase[1] + 2 * swing * u) + 0.01)
        r = 0.19 + bulge
        sway = 0.03 * math.sin(swing * u + wrinkle_phase[2]) * (1 - height)
        return np.stack([r * np.cos(phi), shirt_flat[:, 1], r * np.sin(phi) + sway], axis=1)

    shot.deforming_mesh("/World/Character/Shirt", s_counts, s_indices, shirt, color=(0.9, 0.2, 0.2))
    total = 6 * capsule_triangles(segments, rings) + 2 * len(s_counts)
    return f"character: {total} triangles (shirt {2 * len(s_counts)}, six capsules)"


#: Gap between the resting cloth and the table top (scene units): the cloth never touches the top.
FLUTTER_REST_GAP = 0.004
#: Every cloth vertex circles in a horizontal plane with this radius (scene units) and period (frames).
#: The circle's speed (2 pi r / period) exceeds the largest horizontal speed of the rest of the motion
#: (FLUTTER_AMPLITUDE * 2 pi / FLUTTER_PERIOD), so the path curves at every sample: the middle of any
#: three consecutive samples lies off their chord, and no flightplan merge can drop a sample.
FLUTTER_CIRCLE = 0.004
FLUTTER_CIRCLE_PERIOD = 6.0
#: Horizontal flutter of the overhang into the table's sides (scene units, frames).
FLUTTER_AMPLITUDE = 0.02
FLUTTER_PERIOD = 40.0


def scene_flutter(shot: PerFrameShot, faces: int, rng: np.random.Generator) -> str:
    frames = shot.frames
    top_half = np.array([0.5, 0.025, 0.35])
    top_center = np.array([0.0, 0.5, 0.0])
    table_top = top_center[1] + top_half[1]
    points, counts, indices = box(top_center, top_half)
    shot.static_mesh("/World/Table/Top", counts, indices, points, color=(0.45, 0.3, 0.2))

    columns, rows = grid_for_faces(faces, 1.4 / 1.0)
    flat, cloth_counts, cloth_indices = grid(columns, rows, 1.4, 1.0)
    x, z = flat[:, 0], flat[:, 2]
    overhang = np.maximum(np.maximum(np.abs(x) - top_half[0], np.abs(z) - top_half[2]), 0.0)
    hanging = np.minimum(overhang / 0.05, 1.0)
    # hanging parts tuck in under the table edge, so their flutter swings into its sides
    tuck = 0.035 * hanging
    rest = np.stack([x - np.sign(x) * tuck * (np.abs(x) > top_half[0]),
                     table_top + FLUTTER_REST_GAP - 0.9 * overhang,
                     z - np.sign(z) * tuck * (np.abs(z) > top_half[2])], axis=1)
    along_x = np.abs(x) - top_half[0] > np.abs(z) - top_half[2]
    inward = np.stack([np.where(along_x, np.sign(x), 0.0), np.zeros_like(x),
                       np.where(along_x, 0.0, np.sign(z))], axis=1)
    start_height, landing = 1.1, 0.25 * frames        # falls on a parabola until the landing frame
    circle_phase = rng.uniform(0, 2 * math.pi, size=x.shape)
    flutter_phase = rng.uniform(0, 2 * math.pi, size=x.shape)

    def cloth(t: float) -> np.ndarray:
        u = min((t - 1.0) / landing, 1.0)
        out = rest.copy()
        drop = (start_height - table_top) * (1.0 - u * u)
        out[:, 1] = rest[:, 1] + drop * (1.0 - 0.9 * overhang / max(overhang.max(), 1e-9) * u)
        circling = 2 * math.pi * t / FLUTTER_CIRCLE_PERIOD + circle_phase
        out[:, 0] += FLUTTER_CIRCLE * np.cos(circling)
        out[:, 2] += FLUTTER_CIRCLE * np.sin(circling)
        flutter = FLUTTER_AMPLITUDE * hanging * np.sin(2 * math.pi * t / FLUTTER_PERIOD + flutter_phase)
        return out - flutter[:, None] * inward

    shot.deforming_mesh("/World/Cloth", cloth_counts, cloth_indices, cloth, color=(0.85, 0.85, 0.95))

    ball, ball_counts, ball_indices = capsule(0.06, 0.0, 12, 4)
    pivot = (0.0, 1.4, top_half[2] + 0.12)
    shot.animated_xform("/World/Pendulum", translate=lambda t: pivot,
                        rotate_xyz=lambda t: (0.0, 0.0, 55.0 * math.sin(2 * math.pi * t / 23.0)))
    shot.static_mesh("/World/Pendulum/Ball", ball_counts, ball_indices, ball - (0.0, 1.0, 0.0),
                     color=(0.2, 0.3, 0.8))
    return (f"flutter: {len(cloth_counts)} cloth faces falling onto a table and resting on it, sampled at "
            f"every one of {frames} frames on curved paths, a pendulum ball swinging through the overhang")


SCENES = {
    "tablecloth": (scene_tablecloth, "--faces", 8000, (2000, 16000)),
    "swirl": (scene_swirl, "--faces", 8000, (4000, 33000)),
    "character": (scene_character, "--triangles", 60000, (35000, 90000)),
    "flutter": (scene_flutter, "--faces", 800, (100, 20000)),
}
#: Scenes written at every frame (PerFrameShot) rather than from keyframes.
PER_FRAME_SCENES = ("flutter",)


def generate(scene: str, size: Optional[int] = None, keyframes: int = 11,
             samples_per_keyframe: int = 10, seed: int = 7, out: Optional[str] = None,
             frames: int = 48) -> str:
    """Write one scene and return its path (also usable from benchmarks). ``frames`` applies to the
    per-frame scenes only, ``keyframes`` and ``samples_per_keyframe`` to the others."""
    build, flag, default, _ = SCENES[scene]
    size = default if size is None else size
    per_frame = scene in PER_FRAME_SCENES
    shot = PerFrameShot(frames) if per_frame else KeyframedShot(keyframes, samples_per_keyframe)
    note = build(shot, size, np.random.default_rng(seed))
    if out is None:
        os.makedirs(GENERATED, exist_ok=True)
        name = f"{scene}_{size}_f{frames}" if per_frame else f"{scene}_{size}_k{keyframes}_s{samples_per_keyframe}"
        out = os.path.join(GENERATED, name + ".usdc")
    sampling = (f"a sample at every one of {frames} frames" if per_frame else
                f"keyframes {keyframes}, samples per keyframe {samples_per_keyframe}")
    shot.save(out, f"usdksl generated benchmark shot; {note}; {sampling}, seed {seed}")
    return out


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", choices=sorted(SCENES))
    parser.add_argument("--faces", type=int, default=None, help="cloth faces (tablecloth, swirl)")
    parser.add_argument("--triangles", type=int, default=None, help="all triangles (character)")
    parser.add_argument("--keyframes", type=int, default=11)
    parser.add_argument("--samples-per-keyframe", type=int, default=10)
    parser.add_argument("--frames", type=int, default=48, help="frames of the per-frame scenes (flutter)")
    parser.add_argument("--seed", type=int, default=7)
    parser.add_argument("--out", default=None, help="output .usdc (default: samples/generated/...)")
    args = parser.parse_args(argv)
    _, flag, default, (low, high) = SCENES[args.scene]
    size = args.faces if flag == "--faces" else args.triangles
    other = args.triangles if flag == "--faces" else args.faces
    if other is not None:
        parser.error(f"{args.scene} takes {flag}, not the other size option")
    if size is not None and not low <= size <= high:
        print(f"note: {args.scene} is meant for {flag} {low}..{high}", file=sys.stderr)
    started = wallclock.perf_counter()
    path = generate(args.scene, size, args.keyframes, args.samples_per_keyframe, args.seed, args.out, args.frames)
    print(f"{path}: {os.path.getsize(path) / 2 ** 20:.1f} MiB in "
          f"{wallclock.perf_counter() - started:.1f} s")
    return 0


if __name__ == "__main__":
    sys.exit(main())
