"""Randomised queries with a planted first contact at an exactly known time.

Both primitives translate rigidly, so their relative motion is a straight
line and the planted contact is the only one. All coordinates are dyadic, so
the positions at the planted time are exact in double precision: the answer
must hit with a time of impact in [t* - tolerance, t*]. Contacts are planted
inside, on edges and at corners of the parameter domain, at t* = 0 and 1,
and far from the origin with tiny motion.
"""

import zlib

import numpy as np
import pytest

from usdksl import ccd

TOLERANCES = [1e-2, 1e-6, 1e-9]
COUNT = 1500
# Dyadic grids keep every product below exact in double precision.
TIME_STEPS = 64
COORDINATE_STEP = 1.0 / 256.0


def _dyadic(rng, shape, scale=4.0):
    return np.round(rng.uniform(-scale, scale, size=shape) / COORDINATE_STEP) * COORDINATE_STEP


def _planted_parameters(rng, count, triangle):
    """(u, v) on a 1/16 grid, a third of them on the domain boundary."""
    u = rng.integers(0, 17, size=count) / 16.0
    v = rng.integers(0, 17, size=count) / 16.0
    if triangle:
        over = u + v > 1.0
        u[over], v[over] = 1.0 - u[over], 1.0 - v[over]
    boundary = rng.random(count) < 1.0 / 3.0
    side = rng.integers(0, 3, size=count)
    u[boundary & (side == 0)] = 0.0
    v[boundary & (side == 1)] = 0.0
    if triangle:
        on_diagonal = boundary & (side == 2)
        v[on_diagonal] = 1.0 - u[on_diagonal]
    else:
        u[boundary & (side == 2)] = 1.0
    return u, v


def _planted(rng, kind, count, offset=0.0, motion=1.0):
    """Queries of shape (count, 8, 3) and their planted contact times."""
    t_star = rng.integers(0, TIME_STEPS + 1, size=count) / TIME_STEPS
    t_star[: count // 10] = 0.0
    t_star[count // 10: count // 5] = 1.0
    u, v = _planted_parameters(rng, count, triangle=kind == "vf")
    contact = _dyadic(rng, (count, 3)) + offset
    first_dir = _dyadic(rng, (count, 3))
    second_dir = _dyadic(rng, (count, 3))
    if kind == "vf":
        # Triangle a, a + e1, a + e2 with the contact at a + u e1 + v e2.
        a = contact - u[:, None] * first_dir - v[:, None] * second_dir
        second_points = np.stack([a, a + first_dir, a + second_dir], axis=1)
        first_points = contact[:, None, :]
    else:
        # Edge A passes through the contact at fraction u, edge B at v.
        first_points = np.stack([contact - u[:, None] * first_dir, contact + (1 - u[:, None]) * first_dir], axis=1)
        second_points = np.stack([contact - v[:, None] * second_dir, contact + (1 - v[:, None]) * second_dir], axis=1)
    first_velocity = _dyadic(rng, (count, 1, 3)) * motion
    second_velocity = _dyadic(rng, (count, 1, 3)) * motion
    at_contact = np.concatenate([first_points, second_points], axis=1)
    velocity = np.concatenate([np.repeat(first_velocity, first_points.shape[1], axis=1),
                               np.repeat(second_velocity, second_points.shape[1], axis=1)], axis=1)
    start = at_contact - t_star[:, None, None] * velocity
    end = start + velocity
    queries = np.concatenate([start, end], axis=1)
    assert np.array_equal(start + t_star[:, None, None] * velocity, at_contact), "planting lost exactness"
    return queries, t_star


@pytest.mark.parametrize("kind", ["vf", "ee"])
@pytest.mark.parametrize("tolerance", TOLERANCES)
@pytest.mark.parametrize("offset,motion", [(0.0, 1.0), (2.0**17, 2.0**-10)], ids=["unit", "far-small-motion"])
def test_planted_contact_found_at_its_time(kind, tolerance, offset, motion):
    rng = np.random.default_rng(zlib.crc32(f"{kind} {tolerance} {offset}".encode()))
    queries, t_star = _planted(rng, kind, COUNT, offset, motion)
    run = ccd.vertex_face_detailed if kind == "vf" else ccd.edge_edge_detailed
    answers = run(queries, tolerance=tolerance)
    missed = np.flatnonzero(~answers.hit)
    assert missed.size == 0, f"missed planted contacts, e.g. query {queries[missed[0]]!r} at t={t_star[missed[0]]}"
    late = np.flatnonzero(answers.toi > t_star)
    assert late.size == 0, (f"{late.size} answers later than the planted contact, e.g. {answers.toi[late[0]]} "
                            f"> {t_star[late[0]]} for {queries[late[0]]!r}")
    decided = ~answers.undecided
    assert np.all(answers.reached_tolerance[decided] <= tolerance)
    if offset == 0.0:
        # Far from the origin the rounding bound (about 1e-9 scene units at
        # 1.3e5) over approach speeds near 1e-3 units per step blurs the time
        # by up to 1e-3 whatever the tolerance: there only safety is checked.
        early = np.flatnonzero(decided & (answers.toi < t_star - tolerance))
        assert early.size == 0, f"{early.size} answers earlier than t* - tolerance"
