"""The kinetic lists against brute force on seeded random animations built to reach the parts of the
step-box core that skip work: boxes asleep until their meshes' travel could close the gap, leaf pairs
covered several steps ahead on a clearance certificate, fronts coarsened every few steps, time windows
split over threads.

Each scene mixes meshes sampled at every frame on curves, meshes keyframed sparsely (so steps of one
mesh fall inside another's segments), meshes that hold still for stretches and then dash, rigid boxes
spinning through cloth, and cloth folding onto itself. Brute force tests every triangle pair on every
raw sample step; the answer of ``ksl`` (any thread count) and ``swept`` must be brute force's, bit for
bit: the same pairs, the same first-contact times, the same features. Brute force shares its triangle-pair
code with the others, so smaller scenes of the same kinds are also held to ipctk's Tight-Inclusion CCD
(tests/reference), which shares none of it."""

import collections
import functools
import sys
from pathlib import Path

import numpy as np
import pytest

from usdksl.ccd_defaults import DEFAULT_TOLERANCE
from usdksl.checking.collision import find_contacts

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))
from builders import animated, rotation, triangle_grid  # noqa: E402

#: Seeds of the scenes; each scene draws its own meshes, samples and thickness from its seed.
SEEDS = tuple(range(30))
#: Frames of every scene (time codes 0..FRAMES-1).
FRAMES = 40
#: Thicknesses (scene units) drawn from; the cloths are about one unit across.
THICKNESSES = (0.0, 0.0, 0.002, 0.02)
#: Range (low inclusive, high exclusive) of the quads along each side of a cloth.
CLOTH_CELLS = (5, 15)


def contact_columns(result):
    return [np.asarray(column).tolist() for column in
            (result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b, result.feature)]


def sample_times(rng) -> np.ndarray:
    """Every frame, sparse keyframes, or every other frame."""
    kind = rng.integers(3)
    if kind == 0:
        return np.arange(FRAMES, dtype=np.float64)
    if kind == 1:
        inner = np.sort(rng.choice(np.arange(1, FRAMES - 1), size=int(rng.integers(2, 8)), replace=False))
        return np.concatenate([[0.0], inner.astype(np.float64), [FRAMES - 1.0]])
    return np.append(np.arange(0, FRAMES - 1, 2, dtype=np.float64), FRAMES - 1.0)


def hold_and_dash(rng, times: np.ndarray) -> np.ndarray:
    """Motion parameter per sample: still until a random frame, then fast for a frame or two."""
    dash = rng.uniform(5, FRAMES - 5)
    return np.clip((times - dash) / rng.uniform(0.5, 2.0), 0.0, 1.0)


def cloth(rng, times: np.ndarray, cells=CLOTH_CELLS):
    """A sheet of n x n quads (n drawn from the range ``cells``) waving on curves while it drifts and
    folds; sometimes resting then dashing."""
    n = int(rng.integers(*cells))
    verts, tris = triangle_grid(n, n)
    verts = verts[:, [0, 2, 1]]  # lie in XZ, Y up
    offset = rng.uniform(-0.3, 0.3, size=3)
    amplitude, frequency, phase = rng.uniform(0.0, 0.15), rng.uniform(0.1, 0.6), rng.uniform(0, 2 * np.pi)
    fold_speed = rng.uniform(0.0, 0.08)
    dash = hold_and_dash(rng, times) if rng.random() < 0.3 else None
    frames = []
    for k, t in enumerate(times):
        p = verts + offset
        p[:, 1] += amplitude * np.sin(frequency * t + phase + 3.0 * verts[:, 0]) * np.cos(2.0 * verts[:, 2])
        angle = min(fold_speed * t, 1.2 * np.pi)
        right = verts[:, 0] > 0.5
        dx = verts[right, 0] - 0.5
        p[right, 0] = offset[0] + 0.5 + dx * np.cos(angle)
        p[right, 1] += dx * np.sin(angle) + 0.02 * dx
        if dash is not None:
            p[:, 1] += 2.0 * (1.0 - dash[k]) - 0.3 * dash[k]
        frames.append(p)
    return animated(times, frames, tris)


def spinning_box(rng, times: np.ndarray):
    """A rigid box (12 triangles) spinning about a random axis along a curved path."""
    corners = np.array([[x, y, z] for x in (-1, 1) for y in (-1, 1) for z in (-1, 1)], dtype=np.float64)
    corners *= rng.uniform(0.05, 0.25)
    faces = [(0, 1, 3), (0, 3, 2), (4, 6, 7), (4, 7, 5), (0, 4, 5), (0, 5, 1),
             (2, 3, 7), (2, 7, 6), (0, 2, 6), (0, 6, 4), (1, 5, 7), (1, 7, 3)]
    axis = rng.normal(size=3)
    axis /= np.linalg.norm(axis)
    spin = rng.uniform(0.05, 0.6)
    start, velocity = rng.uniform(-0.2, 1.2, size=3), rng.uniform(-0.04, 0.04, size=3)
    swing = rng.uniform(0.0, 0.3)
    frames = []
    for t in times:
        centre = start + velocity * t + swing * np.array([np.sin(0.2 * t), np.cos(0.15 * t) - 1.0, 0.0])
        frames.append(corners @ rotation(axis, spin * t).T + centre)
    return animated(times, frames, np.array(faces, dtype=np.int32))


def still_slab(rng):
    """A static floor under the cloths (one sample)."""
    verts, tris = triangle_grid(2, 2, size=2.0)
    verts = verts[:, [0, 2, 1]] + [-0.5, rng.uniform(-0.4, 0.0), -0.5]
    return animated([0.0], [verts], tris)


def checked_pairs(meshes):
    """Every moving mesh against itself, and every pair of meshes with one moving."""
    pairs = [(i, i) for i, mesh in enumerate(meshes) if len(mesh.times) > 1]
    pairs += [(i, j) for i in range(len(meshes)) for j in range(i + 1, len(meshes))
              if len(meshes[i].times) > 1 or len(meshes[j].times) > 1]
    return pairs


def random_scene(seed: int, thicknesses=THICKNESSES, cloth_cells=CLOTH_CELLS):
    rng = np.random.default_rng(seed)
    meshes = [cloth(rng, sample_times(rng), cloth_cells) for _ in range(int(rng.integers(1, 3)))]
    meshes += [spinning_box(rng, sample_times(rng)) for _ in range(int(rng.integers(0, 3)))]
    if rng.random() < 0.5:
        meshes.append(still_slab(rng))
    return meshes, checked_pairs(meshes), float(rng.choice(thicknesses))


def assert_every_method_gives_brute_force_s_answer(meshes, pairs, thickness, seed, **options):
    """ksl at one and two threads and swept (with ``options``) give brute force's answer bit for bit."""
    brute = contact_columns(find_contacts(meshes, pairs, method="brute", thickness=thickness))
    for method, threads in (("ksl", 1), ("ksl", 2), ("swept", 1)):
        answer = contact_columns(find_contacts(meshes, pairs, method=method, thickness=thickness, threads=threads,
                                               **options))
        missed = set(zip(*brute[1:5])) - set(zip(*answer[1:5]))
        assert not missed, f"{method} at {threads} threads missed {sorted(missed)[:5]} (seed {seed})"
        assert answer == brute, f"{method} at {threads} threads differs from brute force (seed {seed})"


@pytest.mark.parametrize("seed", SEEDS)
def test_kinetic_lists_equal_brute_force_on_random_animations(seed):
    meshes, pairs, thickness = random_scene(seed)
    assert_every_method_gives_brute_force_s_answer(meshes, pairs, thickness, seed)


#: Thicknesses of the graze scenes, and the seeds among them where a pair grazes at the thickness across a
#: raw step that ends at a sample: the candidate search at the thickness plus merge slack reports it
#: at the next step's begin, and confirmation must find it on the step before, as brute force does.
GRAZE_THICKNESSES = (0.0, 0.001, 0.005, 0.02, 0.05)
GRAZE_SEEDS = (185,)


@pytest.mark.parametrize("seed", GRAZE_SEEDS)
def test_a_graze_found_at_a_step_begin_is_confirmed_on_the_step_before(seed):
    meshes, pairs, thickness = random_scene(seed, GRAZE_THICKNESSES)
    brute = contact_columns(find_contacts(meshes, pairs, method="brute", thickness=thickness))
    for method in ("ksl", "swept"):
        assert contact_columns(find_contacts(meshes, pairs, method=method, thickness=thickness, threads=1)) == brute


def test_the_random_scenes_have_contacts_and_the_kinds_of_motion_they_are_for():
    # The scenes must exercise what they are for: contacts in most scenes, sparse keyframes beside
    # per-frame samples, and more than one thread window (40 frames hold 2 windows).
    with_contacts = 0
    mixed_sampling = 0
    for seed in SEEDS:
        meshes, pairs, thickness = random_scene(seed)
        if len(find_contacts(meshes, pairs, method="ksl", thickness=thickness, threads=1)):
            with_contacts += 1
        counts = {len(mesh.times) for mesh in meshes if len(mesh.times) > 1}
        if len(counts) > 1:
            mixed_sampling += 1
    assert with_contacts >= len(SEEDS) * 2 // 3
    assert mixed_sampling >= 3


#: Quads along each side of the cloths of the scenes held to the ipctk reference (low inclusive, high
#: exclusive): the reference makes one Python call per primitive query, so its scenes are small.
REFERENCE_CLOTH_CELLS = (3, 6)
#: Seeds of those scenes: each thickness, contacts by every feature, about 0.3 s of reference each.
REFERENCE_SEEDS = (0, 2, 3, 5, 6, 7, 11, 13, 15, 18, 25, 29)


@functools.lru_cache(maxsize=None)
def small_scene_and_reference(seed: int):
    """(meshes, pairs, thickness, ipctk's first contacts) of the small scene of ``seed``."""
    from reference.tight_inclusion import first_contacts
    meshes, pairs, thickness = random_scene(seed, cloth_cells=REFERENCE_CLOTH_CELLS)
    return meshes, pairs, thickness, first_contacts(meshes, pairs, thickness=thickness)


@pytest.mark.parametrize("seed", REFERENCE_SEEDS)
def test_every_method_agrees_with_ipctk_on_small_random_animations(seed, ipctk_reference):
    meshes, pairs, thickness, reference = small_scene_and_reference(seed)
    for method, threads in (("brute", 1), ("ksl", 1), ("ksl", 2), ("swept", 1)):
        result = find_contacts(meshes, pairs, method=method, thickness=thickness, threads=threads)
        ipctk_reference.assert_agrees(reference, result, meshes, DEFAULT_TOLERANCE,
                                      f"{method} at {threads} threads (seed {seed}): ")


def test_the_small_scenes_have_first_contacts_of_every_feature_at_every_thickness(ipctk_reference):
    # The comparison above must have something to compare: first contacts by edges alone (a core that
    # tested edges only after a vertex touched would miss them), by vertices, already touching at the
    # start, and contacts at thickness 0 and above it.
    features = collections.Counter()
    with_contacts = collections.Counter()
    for seed in REFERENCE_SEEDS:
        _, _, thickness, reference = small_scene_and_reference(seed)
        features.update(reference.feature.values())
        with_contacts[thickness > 0] += bool(reference.must)
    assert features[ipctk_reference.EDGE_EDGE] >= 100
    assert features[ipctk_reference.VERTEX_FACE] + features[ipctk_reference.FACE_VERTEX] >= 100
    assert features[ipctk_reference.INITIAL] >= 10
    assert with_contacts[False] >= 5 and with_contacts[True] >= 3


#: Seeds of the whipping-corner scenes.
WHIP_SEEDS = tuple(range(16))


def whipping_corner(rng):
    """A sheet sampled at every frame, drifting slowly, whose corner holds still for most of the shot
    and then whips over (a fold of more than half a turn in a few frames) through the sheet itself and
    through a still slab hanging over it: the corner's boxes rest asleep beside the slab while other
    parts of the mesh move, until the whip."""
    n = int(rng.integers(6, 10))
    verts, tris = triangle_grid(n, n)
    verts = verts[:, [0, 2, 1]]  # lie in XZ, Y up
    times = np.arange(FRAMES, dtype=np.float64)
    hinge = rng.uniform(0.45, 0.7)
    corner = (verts[:, 0] > hinge) & (verts[:, 2] > rng.uniform(0.3, 0.7))
    whip_at, whip_frames = rng.uniform(4, FRAMES - 8), rng.uniform(1.5, 5.0)
    drift = rng.uniform(-0.004, 0.004, size=3)
    frames = []
    for t in times:
        p = verts + drift * t
        p[:, 1] += 0.01 * np.sin(0.3 * t + 4.0 * verts[:, 2])  # the rest of the sheet ripples a little
        angle = 1.15 * np.pi * np.clip((t - whip_at) / whip_frames, 0.0, 1.0)
        dx = verts[corner, 0] - hinge
        p[corner, 0] = drift[0] * t + hinge + dx * np.cos(angle)
        p[corner, 1] = drift[1] * t + dx * np.sin(angle) + 0.01 * dx
        frames.append(p)
    sheet = animated(times, frames, tris)
    slab_verts, slab_tris = triangle_grid(2, 2, size=0.4)
    slab_verts = slab_verts[:, [0, 2, 1]] + [hinge + rng.uniform(-0.1, 0.2), rng.uniform(0.1, 0.3), 0.5]
    slab = animated([0.0], [slab_verts], slab_tris)
    return [sheet, slab], [(0, 0), (0, 1)], float(rng.choice(THICKNESSES))


@pytest.mark.parametrize("seed", WHIP_SEEDS)
def test_a_corner_that_holds_still_then_whips_is_caught_as_brute_force_catches_it(seed):
    meshes, pairs, thickness = whipping_corner(np.random.default_rng(1000 + seed))
    brute = contact_columns(find_contacts(meshes, pairs, method="brute", thickness=thickness))
    assert brute[0], "the whip must make contacts"
    assert any(mesh_b == 1 for mesh_b in brute[3]), "the corner must pass through the slab"
    for threads in (1, 2):
        answer = contact_columns(find_contacts(meshes, pairs, method="ksl", thickness=thickness, threads=threads))
        assert answer == brute, f"ksl at {threads} threads differs from brute force (seed {seed})"


#: Whipping-corner seeds held to the ipctk reference: one at a thickness (0.002), one at 0.
WHIP_REFERENCE_SEEDS = (0, 7)


@pytest.mark.parametrize("seed", WHIP_REFERENCE_SEEDS)
def test_a_whipping_corner_agrees_with_ipctk(seed, ipctk_reference):
    meshes, pairs, thickness = whipping_corner(np.random.default_rng(1000 + seed))
    reference = ipctk_reference.first_contacts(meshes, pairs, thickness=thickness)
    assert any(key[2] == 1 for key in reference.must), "the corner must pass through the slab"
    for method in ("brute", "ksl"):
        result = find_contacts(meshes, pairs, method=method, thickness=thickness, threads=1)
        ipctk_reference.assert_agrees(reference, result, meshes, DEFAULT_TOLERANCE, f"{method} (seed {seed}): ")


#: Seeds of the scenes written with sub-frame samples, as a simulator writes them for motion blur.
SUB_FRAME_SEEDS = tuple(range(12))
#: Frames of those scenes, and the range (low inclusive, high exclusive) of samples per frame.
SUB_FRAME_FRAMES, SAMPLES_PER_FRAME = 24, (2, 6)
#: How fast the sub-frame scenes' meshes go through the random scenes' motions (motion time per time code).
SUB_FRAME_PACES = (0.1, 0.3, 1.0)


def sub_frame_scene(seed: int):
    """Cloth and spinning boxes sampled several times a frame on their curves, some meshes at whole frames
    only; the cloths sometimes rest, then dash (an impact: a frame the sub-frame samples bend far from
    its chord)."""
    rng = np.random.default_rng(2000 + seed)
    per_frame = int(rng.integers(*SAMPLES_PER_FRAME))
    dense = np.arange((SUB_FRAME_FRAMES - 1) * per_frame + 1, dtype=np.float64) / per_frame
    frames = np.arange(SUB_FRAME_FRAMES, dtype=np.float64)

    def slowed(build, times):
        # The same kinds of motion, most of them slowed down: a frame then bends little, as a
        # simulator's frames mostly do, and a fast one now and then bends a lot.
        pace = float(rng.choice(SUB_FRAME_PACES))
        mesh = build(rng, times * pace)
        return animated(times, mesh.points, mesh.triangles)

    meshes = [slowed(lambda r, t: cloth(r, t, (4, 9)), dense) for _ in range(int(rng.integers(1, 3)))]
    meshes += [slowed(spinning_box, dense if rng.random() < 0.7 else frames) for _ in range(int(rng.integers(1, 3)))]
    if rng.random() < 0.5:
        meshes.append(still_slab(rng))
    return meshes, checked_pairs(meshes), float(rng.choice(THICKNESSES))


@pytest.mark.parametrize("seed", SUB_FRAME_SEEDS)
def test_stepping_over_sub_frame_samples_gives_brute_force_s_answer(seed):
    meshes, pairs, thickness = sub_frame_scene(seed)
    assert_every_method_gives_brute_force_s_answer(meshes, pairs, thickness, seed, frames_per_time_code=1.0)


def test_the_sub_frame_scenes_have_contacts_and_step_over_most_sub_frame_samples():
    # The comparison above must reach what it is for: contacts, and a core that steps over sub-frame
    # samples (fewer steps than with every sample a step) while keeping some (the bent frames).
    with_contacts, steps, raw_steps, kept_some = 0, 0, 0, 0
    for seed in SUB_FRAME_SEEDS:
        meshes, pairs, thickness = sub_frame_scene(seed)
        over = find_contacts(meshes, pairs, method="ksl", thickness=thickness, threads=1, frames_per_time_code=1.0)
        every = find_contacts(meshes, pairs, method="ksl", thickness=thickness, threads=1)
        with_contacts += bool(len(over))
        steps += over.counters["bv_change_events"]
        raw_steps += every.counters["bv_change_events"]
        kept_some += over.counters["bv_change_events"] > SUB_FRAME_FRAMES - 1
    assert with_contacts >= len(SUB_FRAME_SEEDS) * 2 // 3
    assert steps < raw_steps // 2
    assert kept_some >= 2
