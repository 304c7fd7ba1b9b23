"""Record cloth caches with NVIDIA Newton on CPU, written as USD the way a simulator cache looks.

    python benchmarks/record_newton.py tablecloth             # ~12k triangles x 150 frames
    python benchmarks/record_newton.py tablecloth_press       # the same, the ball pressing through the cloth briefly
    python benchmarks/record_newton.py twist                  # ~4.8k triangles x 200 frames
    python benchmarks/record_newton.py cards                  # 52 poker cards (~3.6k triangles) x 120 frames
    python benchmarks/record_newton.py shirt                  # ~20k triangles x 150 frames
    python benchmarks/record_newton.py all --scale 0.1 --frames 20      # small versions for a quick run
    python benchmarks/record_newton.py twist --every-substep  # also a sample at each of its 10 substeps a frame

Each cache is simulated by Newton's VBD solver (`pip install newton warp-lang`; not a project
dependency) on procedurally built geometry (no downloaded assets), and written with pxr:

- every cloth piece is a Mesh of triangles whose ``points`` are sampled at every frame (time codes
  0..frames, 60 per second, Z up, metres);
- colliders are Meshes: static ones (Newton body -1, the ground) without samples; rigidly moving ones
  (kinematic Newton bodies) with their shape's local points and a time-sampled translate + orient on a
  parent Xform, the way DCCs write rigid caches.

With ``--every-substep`` one simulation writes two caches: ``<cache>_sub<N>.usdc`` with a sample after each of
the scene's N substeps (time codes frame + k/N, the sub-frame samples a simulator writes for motion blur;
the vertices move on the simulator's curves between frames, not on lines) and ``<cache>_sub<N>_frames.usdc``
with every Nth of them (the whole frames of that same run): the same motion sampled N times denser, for
``benchmarks/densify.py --dense``.

The Newton/Warp versions, the command line, the scene parameters and the simulation wall time go into
the layer's ``customLayerData`` (key ``newtonRecording``) and a sidecar ``<cache>.json``. Output goes to
benchmarks/caches/ (git-ignored). Simulation takes minutes per cache on CPU: run it in the background.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import sys
import time
from dataclasses import dataclass, field
from typing import Callable, Dict, List, Optional

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
import collider_meshes  # noqa: E402
from harness import Clock, call  # noqa: E402

CACHES = os.path.join(HERE, "caches")
FRAMES_PER_SECOND = 60
#: Key of the recording metadata in the layer's customLayerData.
METADATA_KEY = "newtonRecording"


# --------------------------------------------------------------------------- what a scene describes

@dataclass
class ClothPiece:
    """Particles [first, first + count) of the model, and their triangles (indices local to the piece)."""

    path: str
    first_particle: int
    particle_count: int
    triangles: np.ndarray


@dataclass
class Collider:
    """A collision shape written as a mesh; ``body`` -1 is static, otherwise its transform is sampled."""

    path: str
    body: int
    points: np.ndarray          # in the body frame (shape offset applied)
    counts: np.ndarray
    indices: np.ndarray


@dataclass
class Scene:
    builder: object
    cloths: List[ClothPiece]
    colliders: List[Collider]
    default_frames: int
    substeps: int
    iterations: int
    solver_options: Dict
    pipeline_options: Dict = field(default_factory=dict)
    contact_model: Dict = field(default_factory=dict)        # model.soft_contact_* values
    #: Called once per substep before collision and the solver step: (model, state_in, state_out, time_s).
    drive: Optional[Callable] = None
    #: Called once after finalize: (model) -> None (particle flags of pinned vertices, ...).
    setup: Optional[Callable] = None
    note: str = ""


def _cloth_from_builder(builder, path: str, first_particle: int, first_triangle: int) -> ClothPiece:
    count = len(builder.particle_q) - first_particle
    triangles = np.asarray(builder.tri_indices[first_triangle:], np.int64).reshape(-1, 3) - first_particle
    return ClothPiece(path, first_particle, count, triangles.astype(np.int32))


def _static_shape(builder, path, mesh, position=(0.0, 0.0, 0.0)):
    points, counts, indices = mesh
    return Collider(path, -1, points + np.asarray(position, np.float64), counts, indices)


def _grid_triangles(columns: int, rows: int) -> np.ndarray:
    """Triangles of a (columns + 1) x (rows + 1) vertex grid, x fastest: two per cell."""
    i, j = np.meshgrid(np.arange(columns), np.arange(rows), indexing="xy")
    v0 = (j * (columns + 1) + i).reshape(-1)
    first = np.stack([v0, v0 + columns + 2, v0 + 1], axis=1)
    second = np.stack([v0, v0 + columns + 1, v0 + columns + 2], axis=1)
    return np.stack([first, second], axis=1).reshape(-1, 3).astype(np.int32)


def _set_kinematic_particles(model, indices: np.ndarray) -> None:
    from newton import ParticleFlags

    flags = model.particle_flags.numpy()
    flags[indices] = flags[indices] & ~int(ParticleFlags.ACTIVE)
    import warp as wp
    model.particle_flags = wp.array(flags, dtype=model.particle_flags.dtype, device=model.particle_flags.device)


def _write_particles(state, indices: np.ndarray, positions: np.ndarray) -> None:
    view = state.particle_q.numpy()       # CPU arrays: a view on the simulator's memory
    view[indices] = positions
    velocity = state.particle_qd.numpy()
    velocity[indices] = 0.0


def _write_body(state, body: int, position, quaternion_xyzw) -> None:
    pose = state.body_q.numpy()
    pose[body, :3] = position
    pose[body, 3:] = quaternion_xyzw
    if state.body_qd is not None:
        state.body_qd.numpy()[body] = 0.0


def _quat_about_z(angle: float):
    return (0.0, 0.0, math.sin(angle / 2.0), math.cos(angle / 2.0))


def _quat_about_x(angle: float):
    return (math.sin(angle / 2.0), 0.0, 0.0, math.cos(angle / 2.0))


def _quat_multiply(a, b):
    ax, ay, az, aw = a
    bx, by, bz, bw = b
    return (aw * bx + ax * bw + ay * bz - az * by, aw * by - ax * bz + ay * bw + az * bx,
            aw * bz + ax * by - ay * bx + az * bw, aw * bw - ax * bx - ay * by - az * bz)


# --------------------------------------------------------------------------- scenes

#: tablecloth_press: how far below its resting height (metres) the ball presses into the cloth on the table,
#: and how long it stays down (seconds) before it rises again at RISE_SPEED (m/s).
PRESS_DEPTH = 0.02
PRESS_HOLD_S = 0.15
RISE_SPEED = 1.0


def scene_tablecloth_press(scale: float) -> Scene:
    """The tablecloth, but the ball presses the cloth against the table top, harder than the cloth's
    collision gap allows, and rises again: a brief pass-through beside the cloth's long rest on the table."""
    return scene_tablecloth(scale, press=True)


def scene_tablecloth(scale: float, press: bool = False) -> Scene:
    """A tablecloth falls onto a table, drapes and rests; a ball is dropped onto it late in the shot."""
    import newton
    import warp as wp

    builder = newton.ModelBuilder(gravity=(0.0, 0.0, -9.81))
    table_half = (0.6, 0.4, 0.025)
    table_center = (0.0, 0.0, 0.75)
    top = table_center[2] + table_half[2]
    colliders = []
    builder.add_shape_box(-1, xform=wp.transform(table_center, wp.quat_identity()), hx=table_half[0],
                          hy=table_half[1], hz=table_half[2])
    colliders.append(_static_shape(builder, "/World/Table/Top", collider_meshes.box(table_half), table_center))
    for index, (sx, sy) in enumerate([(-1, -1), (1, -1), (1, 1), (-1, 1)]):
        leg_center = (sx * 0.55, sy * 0.35, 0.3625)
        builder.add_shape_box(-1, xform=wp.transform(leg_center, wp.quat_identity()), hx=0.03, hy=0.03, hz=0.3625)
        colliders.append(_static_shape(builder, f"/World/Table/Leg{index}",
                                       collider_meshes.box((0.03, 0.03, 0.3625)), leg_center))
    builder.add_ground_plane()
    colliders.append(_static_shape(builder, "/World/Ground", collider_meshes.ground(2.0)))

    ball_radius = 0.12
    ball_hold = (0.15, 0.05, 1.6)
    ball = builder.add_body(xform=wp.transform(ball_hold, wp.quat_identity()), is_kinematic=True, label="ball")
    builder.add_shape_sphere(ball, radius=ball_radius)
    colliders.append(Collider("/World/Ball/Mesh", ball, *collider_meshes.sphere(ball_radius, 32, 16)))

    columns = max(4, int(round(88 * math.sqrt(scale))))
    rows = max(4, int(round(68 * math.sqrt(scale))))
    size_x, size_y = 1.8, 1.4
    first_particle, first_triangle = len(builder.particle_q), len(builder.tri_indices)
    builder.add_cloth_grid(pos=wp.vec3(-size_x / 2, -size_y / 2, top + 0.2), rot=wp.quat_identity(),
                           vel=wp.vec3(0.0, 0.0, 0.0), dim_x=columns, dim_y=rows, cell_x=size_x / columns,
                           cell_y=size_y / rows, mass=0.4 / ((columns + 1) * (rows + 1)), tri_ke=1.0e4,
                           tri_ka=1.0e4, tri_kd=1.0e-2, edge_ke=2.0e-2, edge_kd=1.0e-3,
                           particle_radius=0.006)
    cloth = _cloth_from_builder(builder, "/World/Cloth", first_particle, first_triangle)
    builder.color(include_bending=True)

    release_s, rest_z = 1.5, top + 0.012 + ball_radius
    if press:
        rest_z -= PRESS_DEPTH
    landed_s = release_s + math.sqrt(2.0 * (ball_hold[2] - rest_z) / 9.81)

    def drive(model, state_in, state_out, t):
        fall = max(t - release_s, 0.0)
        z = max(ball_hold[2] - 0.5 * 9.81 * fall * fall, rest_z)
        if press and t > landed_s + PRESS_HOLD_S:
            z = min(rest_z + RISE_SPEED * (t - landed_s - PRESS_HOLD_S), ball_hold[2])
        for state in (state_in, state_out):
            _write_body(state, ball, (ball_hold[0], ball_hold[1], z), (0.0, 0.0, 0.0, 1.0))

    return Scene(builder, [cloth], colliders, default_frames=150, substeps=5, iterations=5,
                 solver_options=dict(particle_enable_self_contact=True, particle_self_contact_margin=0.004,
                                     particle_self_contact_gap=0.002),
                 pipeline_options=dict(soft_contact_gap=0.02),
                 contact_model=dict(soft_contact_ke=1.0e4, soft_contact_kd=1.0e-2, soft_contact_mu=0.4),
                 drive=drive,
                 note=f"tablecloth: {len(cloth.triangles)} triangles fall onto a table and rest; "
                      f"a ball (kinematic) drops onto it at {release_s} s"
                      + (f", presses {PRESS_DEPTH} m below its resting height for {PRESS_HOLD_S} s and rises"
                         if press else ""))


def scene_twist(scale: float) -> Scene:
    """Newton's cloth_twist example on a procedural grid: the two ends of a sheet rotate in opposite
    directions until the sheet twists into a rope (heavy self contact, no gravity)."""
    import newton
    import warp as wp

    side = max(6, int(round(50 * math.sqrt(scale))))          # vertices per side (the example: 50)
    u = np.linspace(-0.75, 0.75, side)
    v = np.linspace(-0.5, 0.5, side)
    grid_y, grid_z = np.meshgrid(u, v, indexing="xy")
    vertices = np.stack([np.zeros(side * side), grid_y.reshape(-1), grid_z.reshape(-1)], axis=1)
    triangles = _grid_triangles(side - 1, side - 1)

    builder = newton.ModelBuilder(gravity=(0.0, 0.0, 0.0))
    first_particle, first_triangle = len(builder.particle_q), len(builder.tri_indices)
    builder.add_cloth_mesh(pos=wp.vec3(0.0, 0.0, 0.0), rot=wp.quat_identity(), scale=1.0,
                           vertices=[wp.vec3(*p) for p in vertices], indices=triangles.reshape(-1).tolist(),
                           vel=wp.vec3(0.0, 0.0, 0.0), density=0.2, tri_ke=1.0e3, tri_ka=1.0e3, tri_kd=2.0e-4,
                           edge_ke=1e-3, edge_kd=1e-2)
    cloth = _cloth_from_builder(builder, "/World/Cloth", first_particle, first_triangle)
    builder.color()

    columns = np.arange(side)
    pinned_plus = (columns * side + side - 1).astype(np.int64)     # y = +0.75, rotates about -Y
    pinned_minus = (columns * side).astype(np.int64)               # y = -0.75, rotates about +Y
    pinned = np.concatenate([pinned_plus, pinned_minus])
    rest = vertices[pinned]
    sign = np.concatenate([-np.ones(side), np.ones(side)])
    angular_velocity, end_s = math.pi / 3.0, 10.0

    def setup(model):
        model.soft_contact_ke, model.soft_contact_kd, model.soft_contact_mu = 1.0e3, 1.0e-1, 0.2
        _set_kinematic_particles(model, pinned)

    def drive(model, state_in, state_out, t):
        theta = sign * min(t, end_s) * angular_velocity          # rotation about +Y by sign * angle
        cos, sin = np.cos(theta), np.sin(theta)
        rotated = np.stack([cos * rest[:, 0] + sin * rest[:, 2], rest[:, 1], -sin * rest[:, 0] + cos * rest[:, 2]],
                           axis=1)
        for state in (state_in, state_out):
            _write_particles(state, pinned, rotated)

    return Scene(builder, [cloth], [], default_frames=200, substeps=10, iterations=4,
                 solver_options=dict(particle_enable_self_contact=True, particle_self_contact_margin=0.002,
                                     particle_self_contact_gap=0.0015, particle_vertex_contact_buffer_size=64,
                                     particle_edge_contact_buffer_size=128),
                 drive=drive, setup=setup,
                 note=f"twist: {len(cloth.triangles)} triangles; the sheet's ends rotate in opposite directions "
                      f"(Newton's cloth_twist on a procedural {side}x{side} grid)")


def scene_cards(scale: float) -> Scene:
    """Poker cards (stiff cloth) drop onto a cube; a kinematic sphere sweeps through the stack and knocks
    them off onto spheres, boxes and the ground (after Newton's cloth_poker_cards example)."""
    import newton
    import warp as wp

    builder = newton.ModelBuilder(gravity=(0.0, 0.0, -9.8))
    colliders = []
    cube_half, cube_center = 0.1, (0.0, 0.0, 0.1)
    builder.add_shape_box(-1, xform=wp.transform(cube_center, wp.quat_identity()), hx=cube_half, hy=cube_half,
                          hz=cube_half)
    colliders.append(_static_shape(builder, "/World/Cube", collider_meshes.box((cube_half,) * 3), cube_center))
    obstacles = [("sphere", (0.2, 0.05, 0.05), 0.05), ("sphere", (0.17, -0.12, 0.04), 0.04),
                 ("box", (0.24, -0.02, 0.03), 0.03), ("sphere", (-0.18, 0.1, 0.04), 0.04),
                 ("box", (0.14, 0.16, 0.025), 0.025)]
    for index, (kind, center, size) in enumerate(obstacles):
        if kind == "sphere":
            builder.add_shape_sphere(-1, xform=wp.transform(center, wp.quat_identity()), radius=size)
            mesh = collider_meshes.sphere(size, 20, 10)
        else:
            builder.add_shape_box(-1, xform=wp.transform(center, wp.quat_identity()), hx=size, hy=size, hz=size)
            mesh = collider_meshes.box((size,) * 3)
        colliders.append(_static_shape(builder, f"/World/Obstacles/{kind.title()}{index}", mesh, center))
    builder.add_ground_plane()
    colliders.append(_static_shape(builder, "/World/Ground", collider_meshes.ground(1.0)))

    sphere_radius, sphere_start, sphere_height, sphere_speed = 0.03, -0.35, 0.23, 0.5
    pusher = builder.add_body(xform=wp.transform((sphere_start, 0.0, sphere_height), wp.quat_identity()),
                              is_kinematic=True, label="pusher")
    builder.add_shape_sphere(pusher, radius=sphere_radius)
    colliders.append(Collider("/World/Pusher/Mesh", pusher, *collider_meshes.sphere(sphere_radius, 20, 10)))

    card_count = max(2, int(round(52 * scale)))
    width, height, cells_x, cells_y = 0.0635, 0.0889, 5, 7
    rng = np.random.default_rng(42)
    cloths = []
    for index in range(card_count):
        first_particle, first_triangle = len(builder.particle_q), len(builder.tri_indices)
        offset = rng.uniform(-0.02, 0.02, size=2)
        builder.add_cloth_grid(pos=wp.vec3(-width / 2 + offset[0], -height / 2 + offset[1], 0.25 + 0.004 * index),
                               rot=wp.quat_from_axis_angle(wp.vec3(0.0, 0.0, 1.0), float(rng.uniform(-0.3, 0.3))),
                               vel=wp.vec3(0.0, 0.0, 0.0), dim_x=cells_x, dim_y=cells_y, cell_x=width / cells_x,
                               cell_y=height / cells_y, mass=1.8e-3 / ((cells_x + 1) * (cells_y + 1)),
                               tri_ke=1.0e4, tri_ka=1.0e4, tri_kd=1.0, edge_ke=1.0e2, edge_kd=1.0,
                               particle_radius=0.003)
        cloths.append(_cloth_from_builder(builder, f"/World/Cards/Card{index:02d}", first_particle, first_triangle))
    builder.color(include_bending=True)

    def drive(model, state_in, state_out, t):
        x = sphere_start + sphere_speed * max(t - 0.5, 0.0)
        for state in (state_in, state_out):
            _write_body(state, pusher, (x, 0.0, sphere_height), (0.0, 0.0, 0.0, 1.0))

    triangles = sum(len(c.triangles) for c in cloths)
    return Scene(builder, cloths, colliders, default_frames=120, substeps=10, iterations=5,
                 solver_options=dict(particle_enable_self_contact=True, particle_self_contact_margin=0.001,
                                     particle_self_contact_gap=0.0005,
                                     particle_topological_contact_filter_threshold=2,
                                     rigid_body_particle_contact_buffer_size=1024),
                 pipeline_options=dict(broad_phase="nxn", soft_contact_gap=0.005),
                 contact_model=dict(soft_contact_ke=1.0e5, soft_contact_kd=1.0e2, soft_contact_mu=0.3),
                 drive=drive,
                 note=f"cards: {card_count} poker cards ({triangles} triangles) drop on a cube, a kinematic sphere "
                      f"knocks them onto spheres, boxes and the ground")


def scene_shirt(scale: float) -> Scene:
    """A tube shirt hangs from the shoulders of a capsule body that twists and sways; the swinging
    capsule arms brush it. The top ring of the shirt is pinned to the torso (kinematic vertices)."""
    import newton
    import warp as wp

    builder = newton.ModelBuilder(gravity=(0.0, 0.0, -9.81))
    torso_radius, torso_half, torso_z = 0.15, 0.2, 1.2
    arm_radius, arm_half = 0.045, 0.2
    shoulder_x, shoulder_z = 0.24, 1.45
    torso = builder.add_body(xform=wp.transform((0.0, 0.0, torso_z), wp.quat_identity()), is_kinematic=True,
                             label="torso")
    builder.add_shape_capsule(torso, radius=torso_radius, half_height=torso_half)
    head_offset = (0.0, 0.0, torso_half + torso_radius + 0.12)
    builder.add_shape_sphere(torso, xform=wp.transform(head_offset, wp.quat_identity()), radius=0.1)
    colliders = [Collider("/World/Body/Torso/Mesh", torso, *collider_meshes.capsule(torso_radius, torso_half, 48, 8)),
                 Collider("/World/Body/Torso/Head", torso,
                          *_offset(collider_meshes.sphere(0.1, 32, 16), head_offset))]
    arms = []
    for side, sign in (("Left", 1.0), ("Right", -1.0)):
        arm = builder.add_body(xform=wp.transform((sign * shoulder_x, 0.0, shoulder_z), wp.quat_identity()),
                               is_kinematic=True, label=f"arm_{side.lower()}")
        # the capsule hangs below the shoulder pivot
        hang = (0.0, 0.0, -(arm_half + arm_radius))
        builder.add_shape_capsule(arm, xform=wp.transform(hang, wp.quat_identity()), radius=arm_radius,
                                  half_height=arm_half)
        colliders.append(Collider(f"/World/Body/{side}Arm/Mesh", arm,
                                  *_offset(collider_meshes.capsule(arm_radius, arm_half, 32, 6), hang)))
        arms.append((arm, sign))

    segments = max(12, int(round(128 * math.sqrt(scale))))
    rows = max(4, int(round(78 * math.sqrt(scale))))
    shirt_radius, shirt_top, shirt_bottom = 0.19, 1.42, 0.85
    phi = np.linspace(0.0, 2.0 * math.pi, segments, endpoint=False)
    z = np.linspace(shirt_top, shirt_bottom, rows + 1)
    local = np.stack([np.tile(shirt_radius * np.cos(phi), rows + 1), np.tile(shirt_radius * np.sin(phi), rows + 1),
                      np.repeat(z, segments)], axis=1)
    s = np.arange(segments)
    r = np.arange(rows)[:, None]
    a, b = r * segments + s, r * segments + (s + 1) % segments
    c, d = (r + 1) * segments + (s + 1) % segments, (r + 1) * segments + s
    triangles = np.concatenate([np.stack([a, d, c], axis=2), np.stack([a, c, b], axis=2)], axis=2).reshape(-1, 3)
    first_particle, first_triangle = len(builder.particle_q), len(builder.tri_indices)
    builder.add_cloth_mesh(pos=wp.vec3(0.0, 0.0, 0.0), rot=wp.quat_identity(), scale=1.0,
                           vertices=[wp.vec3(*p) for p in local], indices=triangles.reshape(-1).tolist(),
                           vel=wp.vec3(0.0, 0.0, 0.0), density=0.15, tri_ke=5.0e3, tri_ka=5.0e3, tri_kd=1.0e-2,
                           edge_ke=1.0e-2, edge_kd=1.0e-3, particle_radius=0.004)
    shirt = _cloth_from_builder(builder, "/World/Shirt", first_particle, first_triangle)
    builder.color(include_bending=True)
    collar = (first_particle + np.arange(segments)).astype(np.int64)
    collar_rest = local[:segments] - (0.0, 0.0, torso_z)             # in the torso frame
    period = 2.0

    def setup(model):
        _set_kinematic_particles(model, collar)

    def torso_pose(t):
        twist = math.radians(25.0) * math.sin(2.0 * math.pi * t / period)
        sway = 0.05 * math.sin(math.pi * t / period)
        return (sway, 0.0, torso_z), _quat_about_z(twist)

    def drive(model, state_in, state_out, t):
        position, orientation = torso_pose(t)
        collar_world = collider_meshes.transform_points(collar_rest, position, orientation)
        swing = math.radians(40.0) * math.sin(2.0 * math.pi * t / (0.8 * period))
        for state in (state_in, state_out):
            _write_body(state, torso, position, orientation)
            _write_particles(state, collar - 0, collar_world)
            for arm, sign in arms:
                shoulder = collider_meshes.transform_points(np.array([[sign * shoulder_x, 0.0, shoulder_z - torso_z]]),
                                                            position, orientation)[0]
                # swing forward/back (about the body's X axis) and inward against the shirt
                inward = _quat_multiply(_quat_about_x(sign * swing), (0.0, math.sin(sign * 0.06), 0.0,
                                                                     math.cos(sign * 0.06)))
                _write_body(state, arm, shoulder, _quat_multiply(orientation, inward))

    return Scene(builder, [shirt], colliders, default_frames=150, substeps=5, iterations=5,
                 solver_options=dict(particle_enable_self_contact=True, particle_self_contact_margin=0.003,
                                     particle_self_contact_gap=0.002),
                 pipeline_options=dict(soft_contact_gap=0.02),
                 contact_model=dict(soft_contact_ke=1.0e4, soft_contact_kd=1.0e-2, soft_contact_mu=0.3),
                 drive=drive, setup=setup,
                 note=f"shirt: a {len(shirt.triangles)}-triangle tube pinned at the collar to a twisting, swaying "
                      f"capsule body whose capsule arms swing against it")


def _offset(mesh, offset):
    points, counts, indices = mesh
    return points + np.asarray(offset, np.float64), counts, indices


SCENES = {"tablecloth": scene_tablecloth, "tablecloth_press": scene_tablecloth_press, "twist": scene_twist,
          "cards": scene_cards, "shirt": scene_shirt}


# --------------------------------------------------------------------------- simulate

def simulate(scene: Scene, frames: int, progress: bool = True, every_substep: bool = False):
    """Run the scene; returns (particle positions float32[S, P, 3], body poses float64[S, B, 7]) at S = frames + 1
    samples, one a frame, or with ``every_substep`` S = frames * substeps + 1, one after each substep (the
    frames are every ``substeps``-th of them)."""
    import newton
    import warp as wp

    model = scene.builder.finalize(device="cpu")
    for name, value in scene.contact_model.items():
        setattr(model, name, value)
    if scene.setup is not None:
        scene.setup(model)
    solver = newton.solvers.SolverVBD(model, iterations=scene.iterations, **scene.solver_options)
    pipeline = newton.CollisionPipeline(model, **scene.pipeline_options)
    contacts = pipeline.contacts()
    state_0, state_1 = model.state(), model.state()
    control = model.control()
    frame_dt = 1.0 / FRAMES_PER_SECOND
    dt = frame_dt / scene.substeps
    per_frame = scene.substeps if every_substep else 1
    samples = frames * per_frame + 1
    positions = np.empty((samples, model.particle_count, 3), np.float32)
    bodies = np.zeros((samples, max(model.body_count, 1), 7), np.float64)

    def record(sample):
        positions[sample] = state_0.particle_q.numpy()
        if model.body_count:
            bodies[sample, :model.body_count] = state_0.body_q.numpy()

    sim_time = 0.0
    if scene.drive is not None:
        scene.drive(model, state_0, state_1, sim_time)
    record(0)
    clock = Clock()
    for frame in range(1, frames + 1):
        for substep in range(1, scene.substeps + 1):
            if scene.drive is not None:
                scene.drive(model, state_0, state_1, sim_time)
            state_0.clear_forces()
            pipeline.collide(state_0, contacts)
            solver.step(state_0, state_1, control, contacts, dt)
            state_0, state_1 = state_1, state_0
            sim_time += dt
            if every_substep and substep < scene.substeps:
                # Kinematic bodies posed at the sample's time, as at a frame (the next substep poses them alike).
                if scene.drive is not None:
                    scene.drive(model, state_0, state_1, sim_time)
                wp.synchronize()
                record((frame - 1) * per_frame + substep)
        if scene.drive is not None:
            scene.drive(model, state_0, state_1, sim_time)
        wp.synchronize()
        record(frame * per_frame)
        if not np.all(np.isfinite(positions[(frame - 1) * per_frame + 1: frame * per_frame + 1])):
            raise RuntimeError(f"simulation blew up at frame {frame}")
        if progress and (frame % 10 == 0 or frame == frames):
            elapsed = clock.wall_s()
            print(f"  frame {frame}/{frames}  {elapsed:.0f} s", file=sys.stderr, flush=True)
    return positions, bodies


# --------------------------------------------------------------------------- write USD

def write_cache(path: str, scene: Scene, positions: np.ndarray, bodies: np.ndarray, metadata: Dict,
                samples_per_frame: int = 1) -> None:
    """Write the recorded samples as a USD cache (see the module docstring), sample i at time code
    i / samples_per_frame; atomically (temp file + rename)."""
    from pxr import Gf, Sdf, Usd, UsdGeom, Vt

    frames = (positions.shape[0] - 1) // samples_per_frame
    time_codes = [sample / samples_per_frame for sample in range(positions.shape[0])]
    temporary = path + ".partial" + os.path.splitext(path)[1]
    if os.path.exists(temporary):
        os.remove(temporary)
    stage = Usd.Stage.CreateNew(temporary)
    stage.SetTimeCodesPerSecond(FRAMES_PER_SECOND)
    stage.SetFramesPerSecond(FRAMES_PER_SECOND)
    stage.SetStartTimeCode(0.0)
    stage.SetEndTimeCode(float(frames))
    UsdGeom.SetStageUpAxis(stage, UsdGeom.Tokens.z)
    UsdGeom.SetStageMetersPerUnit(stage, 1.0)
    world = UsdGeom.Xform.Define(stage, "/World")
    stage.SetDefaultPrim(world.GetPrim())
    layer = stage.GetRootLayer()
    layer.customLayerData = {METADATA_KEY: _usd_safe(metadata)}
    layer.documentation = scene.note

    def define_parents(prim_path):
        parent = Sdf.Path(prim_path).GetParentPath()
        while parent != Sdf.Path("/World") and not stage.GetPrimAtPath(parent):
            UsdGeom.Xform.Define(stage, parent)
            parent = parent.GetParentPath()

    for cloth in scene.cloths:
        define_parents(cloth.path)
        mesh = UsdGeom.Mesh.Define(stage, cloth.path)
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(np.full(len(cloth.triangles), 3, np.int32)))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(cloth.triangles.reshape(-1).astype(np.int32)))
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
        mesh.CreateDoubleSidedAttr(True)
        points = mesh.CreatePointsAttr()
        piece = slice(cloth.first_particle, cloth.first_particle + cloth.particle_count)
        for sample, time_code in enumerate(time_codes):
            points.Set(Vt.Vec3fArray.FromNumpy(np.ascontiguousarray(positions[sample, piece])), time_code)
    for collider in scene.colliders:
        define_parents(collider.path)
        if collider.body >= 0:
            holder = Sdf.Path(collider.path).GetParentPath()
            xform = UsdGeom.Xform.Define(stage, holder)
            if not xform.GetOrderedXformOps():
                translate, orient = xform.AddTranslateOp(), xform.AddOrientOp()
                for sample, time_code in enumerate(time_codes):
                    px, py, pz, qx, qy, qz, qw = bodies[sample, collider.body]
                    translate.Set(Gf.Vec3d(px, py, pz), time_code)
                    orient.Set(Gf.Quatf(float(qw), float(qx), float(qy), float(qz)), time_code)
        mesh = UsdGeom.Mesh.Define(stage, collider.path)
        mesh.CreatePointsAttr(Vt.Vec3fArray.FromNumpy(collider.points.astype(np.float32)))
        mesh.CreateFaceVertexCountsAttr(Vt.IntArray.FromNumpy(collider.counts.astype(np.int32)))
        mesh.CreateFaceVertexIndicesAttr(Vt.IntArray.FromNumpy(collider.indices.astype(np.int32)))
        mesh.CreateSubdivisionSchemeAttr(UsdGeom.Tokens.none)
    layer.Save()
    del stage
    os.replace(temporary, path)


def _usd_safe(value):
    """customLayerData holds strings, numbers, lists and dicts; no None."""
    if isinstance(value, dict):
        return {str(k): _usd_safe(v) for k, v in value.items() if v is not None}
    if isinstance(value, (list, tuple)):
        return [_usd_safe(v) for v in value]
    return value


# --------------------------------------------------------------------------- command line

def record(scene_name: str, frames: Optional[int], scale: float, out_dir: str, argv: List[str],
           every_substep: bool = False) -> str:
    import newton
    import warp as wp

    wp.config.quiet = True
    wp.init()
    scene = SCENES[scene_name](scale)
    frames = scene.default_frames if frames is None else frames
    suffix = "" if scale == 1.0 else f"_s{scale:g}"
    path = os.path.join(out_dir, f"newton_{scene_name}{suffix}_f{frames}.usdc")
    triangles = int(sum(len(c.triangles) for c in scene.cloths))
    print(f"{scene_name}: {triangles} cloth triangles in {len(scene.cloths)} pieces, {len(scene.colliders)} "
          f"colliders, {frames} frames{', a sample every substep' if every_substep else ''} -> {path}",
          file=sys.stderr, flush=True)
    simulated = call(simulate, scene, frames, True, every_substep)
    positions, bodies = simulated.value
    simulated_s, simulated_cpu_s = simulated.wall_s, simulated.cpu_s
    metadata = {
        "scene": scene_name, "note": scene.note, "frames": frames, "scale": scale,
        "framesPerSecond": FRAMES_PER_SECOND, "substeps": scene.substeps, "iterations": scene.iterations,
        "clothTriangles": triangles, "clothPieces": len(scene.cloths), "colliders": len(scene.colliders),
        "newtonVersion": newton.__version__, "warpVersion": wp.config.version, "device": "cpu",
        "command": " ".join(["python", "benchmarks/record_newton.py"] + list(argv)),
        "simulationSeconds": round(simulated_s, 1), "simulationCpuSeconds": round(simulated_cpu_s, 1),
        "recordedAt": time.strftime("%Y-%m-%dT%H:%M:%S"),
    }
    os.makedirs(out_dir, exist_ok=True)
    written = write_recording(path, scene, positions, bodies, metadata, scene.substeps if every_substep else 1)
    for target in written:
        print(f"{target}: {os.path.getsize(target) / 2 ** 20:.1f} MiB, simulated in {simulated_s:.0f} s",
              file=sys.stderr)
    return written[0]


def write_recording(path: str, scene: Scene, positions: np.ndarray, bodies: np.ndarray, metadata: Dict,
                    samples_per_frame: int = 1) -> List[str]:
    """Write what simulate() recorded, with a sidecar ``.json`` each, and return the caches written: ``path``
    when there is a sample a frame; with ``samples_per_frame`` N > 1 (a sample after every substep) the run
    twice, ``<path stem>_sub<N>.usdc`` with every sample and ``<path stem>_sub<N>_frames.usdc`` with every
    Nth (its whole frames)."""
    if samples_per_frame > 1:
        stem = os.path.splitext(path)[0] + f"_sub{samples_per_frame}"
        written = [(stem + ".usdc", positions, bodies, samples_per_frame),
                   (stem + "_frames.usdc", positions[::samples_per_frame], bodies[::samples_per_frame], 1)]
    else:
        written = [(path, positions, bodies, 1)]
    for target, sampled, poses, per_frame in written:
        described = dict(metadata, samplesPerFrame=per_frame)
        write_cache(target, scene, sampled, poses, described, per_frame)
        with open(os.path.splitext(target)[0] + ".json", "w") as sidecar:
            json.dump(described, sidecar, indent=2)
    return [target for target, *_ in written]


def main(argv=None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("scene", choices=sorted(SCENES) + ["all"])
    parser.add_argument("--frames", type=int, default=None, help="frames to record (default: per scene)")
    parser.add_argument("--scale", type=float, default=1.0,
                        help="triangle count factor (cloth resolution; card count for cards)")
    parser.add_argument("--out", default=CACHES, help="output folder (default: benchmarks/caches)")
    parser.add_argument("--every-substep", action="store_true",
                        help="also write a sample after every substep (<cache>_sub<N>.usdc) and the same run's "
                             "whole frames (<cache>_sub<N>_frames.usdc)")
    args = parser.parse_args(argv)
    if args.scale <= 0 or (args.frames is not None and args.frames < 1):
        parser.error("--scale must be positive and --frames at least 1")
    names = sorted(SCENES) if args.scene == "all" else [args.scene]
    for name in names:
        record(name, args.frames, args.scale, args.out, argv, args.every_substep)
    return 0


if __name__ == "__main__":
    sys.exit(main())
