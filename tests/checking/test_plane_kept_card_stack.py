"""A stack of tilted cards that slide and turn over each other while their gaps close, the top card
touching late: the kinetic lists keep card pairs whole on a separating plane and let them sleep while the
plane is sure to hold (kinetic/node_plane.hpp), and must still find exactly brute force's contacts, bit
for bit, at one thread and at two."""

import sys
from pathlib import Path

import numpy as np
import pytest

from usdksl.checking.collision import find_contacts

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from builders import animated, rotation, triangle_grid  # noqa: E402

#: Frames of the shot (time codes 0..FRAMES-1): every one is a breakpoint, the cards move on curves.
FRAMES = 60
#: Quads along each side of a card (72 triangles: a whole card is small enough to be kept by a plane).
CARD_CELLS = 6
#: Distance (scene units) between neighbouring cards along their normal at the start.
SPACING = 0.04
#: How far (scene units) each card sinks along the normal by the last frame, bottom card first: the
#: middle cards sink together, the top one 0.045 further, so only it touches (near frame 56 at thickness
#: 0, earlier at a thickness).
SINK = (0.0, 0.02, 0.02, 0.065)
#: Tilt of the stack out of every axis plane, so that the cards' boxes overlap.
TILT = rotation(np.array([0.6, 0.0, 0.8]), 0.45)


def card_stack():
    verts, tris = triangle_grid(CARD_CELLS, CARD_CELLS)
    local = verts[:, [0, 2, 1]] - [0.5, 0.0, 0.5]  # in the XZ plane, centred, the normal along Y
    times = np.arange(FRAMES, dtype=np.float64)
    meshes = []
    for level, sink in enumerate(SINK):
        frames = []
        for t in times:
            s = t / (FRAMES - 1)
            turn = rotation(np.array([0.0, 1.0, 0.0]), 0.25 * level * s)  # about the normal: in the plane
            slide = [0.1 * np.sin(0.07 * t + level), 0.0, 0.03 * level * s]
            p = local @ turn.T + slide
            p[:, 1] += SPACING * level - sink * s * s
            sway = [0.3 * np.sin(0.05 * t), 0.2 * s - 0.1 * s * s, 0.1 * np.cos(0.04 * t)]
            frames.append(p @ TILT.T + sway)
        meshes.append(animated(times, frames, tris))
    pairs = [(a, b) for a in range(len(meshes)) for b in range(a, len(meshes))]
    return meshes, pairs


def contact_columns(result):
    return [np.asarray(column).tolist() for column in
            (result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b, result.feature)]


@pytest.mark.parametrize("thickness", [0.0, 0.01])
def test_a_card_stack_kept_apart_by_planes_gets_brute_forces_contacts(thickness):
    meshes, pairs = card_stack()
    brute = find_contacts(meshes, pairs, method="brute", thickness=thickness)
    expected = contact_columns(brute)
    # Only the top card reaches the one below, late in the shot.
    assert len(brute.time) > 0
    assert {(a, b) for a, b in zip(expected[1], expected[3])} == {(2, 3)}
    assert min(expected[0]) > 0.6 * (FRAMES - 1)
    for threads in (1, 2):
        ksl = find_contacts(meshes, pairs, method="ksl", thickness=thickness, threads=threads)
        assert contact_columns(ksl) == expected, f"ksl at {threads} threads differs from brute force"
        assert ksl.counters["plane_kept_steps"] > 0, "planes must keep the card pairs whole"
