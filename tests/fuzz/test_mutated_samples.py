"""Mutated copies of the shipped samples through ``usdksl check``: lines deleted, duplicated and swapped,
numbers replaced by nan/inf/1e308/huge integers, huge coordinates, truncation, random bytes
(fuzz/mutations.py). Every run ends within its budget with exit code 0, 1 or 2, without a traceback, with
one error line naming the file on exit 2, and with its files complete or absent, no temporary file left
and the input untouched (fuzz/runner.py says exactly what is checked).

The cases are fixed (seeds 0..MUTATED_FILES-1), so CI sees the same files every run;
``tests/fuzz/long_run.py`` goes on with fresh seeds.
"""

import collections
import shutil
import tempfile
from pathlib import Path

import pytest

from fuzz.mutations import MUTATIONS, MutatedFile, mutated_files, sample_names
from fuzz.runner import Case, describe, run_cases

#: Mutated files run in CI, the same ones every run (tests/fuzz/long_run.py tries fresh ones).
MUTATED_FILES = 320
#: Runs at a time (each is a process of its own; the machines have two cores).
WORKERS = 2
#: One case in this many runs with the default thread count, the others with --threads 1: the threaded
#: windows see hostile input too, and single-threaded runs keep two workers from oversubscribing.
DEFAULT_THREADS_ONE_IN = 5


def case_arguments(index: int):
    return () if index % DEFAULT_THREADS_ONE_IN == 0 else ("--threads", "1")


def write_case(folder: Path, index: int, mutated: MutatedFile) -> Case:
    """The mutated text as ``<folder>/<name>/in/<sample>.usda`` (its own folder: the override layer
    sublayers it by a relative path), outputs to ``<name>/out``."""
    shot = folder / mutated.name / "in" / f"{mutated.sample}.usda"
    shot.parent.mkdir(parents=True)
    shot.write_bytes(mutated.text())
    return Case(shot=shot, out=folder / mutated.name / "out", arguments=case_arguments(index), label=mutated.name)


@pytest.fixture(scope="module")
def outcomes():
    folder = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-mutated-"))
    try:
        cases = [write_case(folder, index, mutated) for index, mutated in enumerate(mutated_files(MUTATED_FILES))]
        yield run_cases(cases, workers=WORKERS)
    finally:
        shutil.rmtree(folder, ignore_errors=True)


def test_every_kind_of_mutation_is_tried_on_every_sample_and_changes_the_text():
    cases = mutated_files(MUTATED_FILES)
    assert len(cases) >= 300
    tried = collections.Counter((case.sample, case.kind) for case in cases)
    assert set(tried) == {(sample, kind) for sample in sample_names() for kind in MUTATIONS}
    samples = {name: (Path(__file__).resolve().parents[2] / "samples" / f"{name}.usda").read_bytes()
               for name in sample_names()}
    unchanged = [case.name for case in cases if case.text() == samples[case.sample]]
    assert len(unchanged) <= len(cases) // 50, unchanged   # a swap of two equal lines, say
    assert all(case.text() == case.text() for case in cases[:20]), "a case replays exactly"


def test_mutated_samples_end_cleanly(outcomes):
    failures = [describe(outcome) for outcome in outcomes if outcome.problems()]
    assert not failures, f"{len(failures)} of {len(outcomes)} runs went wrong:\n" + "\n".join(failures)


def test_the_mutations_reach_the_check_as_well_as_the_parser(outcomes):
    """Not every mutation may be refused at the door: a fuzz suite that only ever sees exit 2 tests
    the USD parser, not the check."""
    codes = collections.Counter(outcome.exit_code for outcome in outcomes)
    assert codes[2] >= len(outcomes) // 10, codes
    assert codes[0] + codes[1] >= len(outcomes) // 4, codes
