"""Property-based fuzzing (Hypothesis) of random small scenes: through ``usdksl check`` and straight into
the native core. Every run ends within its budget, without a traceback, with exit code 0, 1 or 2, and
with its files complete or absent (fuzz/runner.py says what is checked); the core's continuous methods
agree with the brute-force reference on every scene they accept.

The examples are derandomized, so CI sees the same ones every run; ``tests/fuzz/long_run.py`` explores.
"""

import collections
import shutil
import tempfile
from pathlib import Path

from hypothesis import HealthCheck, given, settings

from fuzz import core_case
from fuzz.runner import Case, describe, run_case
from fuzz.scenes import core_meshes, scenes, write_usda

#: Examples per property in CI, the same ones every run (tests/fuzz/long_run.py tries fresh ones).
CLI_EXAMPLES = 200
CORE_EXAMPLES = 100

CI_SETTINGS = dict(deadline=None, derandomize=True, database=None,
                   suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])


def check_scene_through_the_command(scene) -> int:
    """The scene through ``usdksl check``; its exit code, once the run is found sound."""
    folder = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-scene-"))
    try:
        shot = folder / "in" / "scene.usda"
        shot.parent.mkdir()
        write_usda(scene, shot)
        outcome = run_case(Case(shot=shot, out=folder / "out"))
        assert not outcome.problems(), describe(outcome) + f"\nscene: {scene}"
        return outcome.exit_code
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def check_scene_in_the_core(scene) -> bool:
    """The scene straight into the core (every method); whether the core saw it (the loader would refuse
    some scenes that the core never gets)."""
    meshes = core_meshes(scene)
    if meshes:
        problems = core_case.core_problems(meshes)
        assert not problems, f"{problems}\nscene: {scene}"
    return bool(meshes)


def test_random_scenes_through_the_command():
    codes = collections.Counter()

    @settings(max_examples=CLI_EXAMPLES, **CI_SETTINGS)
    @given(scene=scenes())
    def run(scene):
        codes[check_scene_through_the_command(scene)] += 1

    run()
    assert sum(codes.values()) >= CLI_EXAMPLES, codes
    # refused scenes test the loader's messages, accepted ones the check: both must be common
    assert codes[2] >= CLI_EXAMPLES // 10 and codes[0] + codes[1] >= CLI_EXAMPLES // 4, codes


def test_random_scenes_in_the_core():
    seen = collections.Counter()

    @settings(max_examples=CORE_EXAMPLES, **CI_SETTINGS)
    @given(scene=scenes())
    def run(scene):
        seen[check_scene_in_the_core(scene)] += 1

    run()
    assert sum(seen.values()) >= CORE_EXAMPLES and seen[True] >= CORE_EXAMPLES // 2, seen
