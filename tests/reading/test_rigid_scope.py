"""Default scope: a pair needs a deforming mesh; --rigid brings rigid-only pairs back."""

import numpy as np

from usdksl.reading.scope import PAIR_RIGID_ONLY, PAIR_SELF_RIGID, PAIR_STATIC_STATIC, ScopeOptions, SceneFlags, plan_pairs

from builders import rigid_bodies_and_cloth
from .conftest import run_cli


def test_plan_needs_a_deforming_mesh_per_pair_unless_rigid():
    paths = ["/Static", "/RigidA", "/RigidB", "/Cloth"]
    kinds = ["static", "rigid", "rigid", "deforming"]
    moving = np.array([False, True, True, True])
    plan = plan_pairs(paths, kinds, moving, SceneFlags.permissive(4))
    assert {tuple(p) for p in plan.pairs.tolist()} == {(0, 3), (1, 3), (2, 3), (3, 3)}
    skipped = {(i, j): reason for i, j, reason in plan.skipped_pairs}
    assert skipped[(1, 2)] == skipped[(0, 1)] == skipped[(0, 2)] == PAIR_RIGID_ONLY
    assert skipped[(0, 0)] != PAIR_RIGID_ONLY and skipped[(1, 1)] == PAIR_SELF_RIGID
    assert plan.skipped_pair_counts()[PAIR_RIGID_ONLY] == 3
    assert "  skip 3 pairs: neither deforms (use --rigid)" in plan.describe()
    rigid = plan_pairs(paths, kinds, moving, SceneFlags.permissive(4), ScopeOptions(rigid=True))
    assert {tuple(p) for p in rigid.pairs.tolist()} == {(0, 1), (0, 2), (1, 2), (0, 3), (1, 3), (2, 3), (3, 3)}
    assert PAIR_RIGID_ONLY not in rigid.skipped_pair_counts()
    assert {(i, j): r for i, j, r in rigid.skipped_pairs}[(1, 1)] == PAIR_SELF_RIGID   # still no rigid self


def test_a_deforming_mesh_that_never_moves_does_not_make_its_pairs_count():
    plan = plan_pairs(["/StillCloth", "/Rigid"], ["deforming", "rigid"], np.array([False, True]),
                      SceneFlags.permissive(2))
    assert plan.checked_pairs == 0
    assert {(i, j): r for i, j, r in plan.skipped_pairs}[(0, 1)] == PAIR_RIGID_ONLY
    both_still = plan_pairs(["/A", "/B"], ["static", "static"], np.array([False, False]), SceneFlags.permissive(2),
                            ScopeOptions(rigid=True))
    assert {(i, j): r for i, j, r in both_still.skipped_pairs}[(0, 1)] == PAIR_STATIC_STATIC


def _summary(directory):
    lines = (directory / "bodies.summary.csv").read_text().splitlines()[1:]
    return {tuple(line.split(",")[:2]) for line in lines}


def test_default_report_holds_only_pairs_with_the_cloth(tmp_path):
    path = tmp_path / "bodies.usda"
    names = rigid_bodies_and_cloth(path)
    default = run_cli("check", path, "--out", tmp_path / "default", "-v")
    assert default.exit_code == 1, default.stderr
    pairs = _summary(tmp_path / "default")
    assert pairs and all(names["cloth"] in pair for pair in pairs)
    summary_line = default.stderr.strip().splitlines()[-2]       # then -v names the files written
    assert "3 rigid-only pairs left out" in summary_line and "--rigid" in summary_line
    assert "skip 3 pairs: neither deforms (use --rigid)" in default.stderr

    rigid = run_cli("check", path, "--out", tmp_path / "rigid", "--rigid")
    assert rigid.exit_code == 1, rigid.stderr
    everything = _summary(tmp_path / "rigid")
    assert pairs < everything
    assert tuple(sorted((names["a"], names["b"]))) in everything          # the two boxes collide
    assert tuple(sorted((names["a"], names["floor"]))) in everything      # a box reaches the floor
    assert "rigid-only" not in rigid.stderr.strip().splitlines()[-1]
