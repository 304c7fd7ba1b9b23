"""The fuzz suite for as long as you like, with fresh inputs: leave it going, read the failures folder.

    python tests/fuzz/long_run.py --minutes 60 [--failures fuzz-failures] [--seed N] [--workers 2]

Each round runs a batch of mutated samples (fuzz/mutations.py, seeds counting up from ``--seed`` x
1,000,000, far from the seeds CI uses), a batch of random scenes through ``usdksl check`` and the same
scenes straight into the core (fuzz/scenes.py, Hypothesis seeded per round), with the checks of CI
(fuzz/runner.py, fuzz/core_case.py). Every failing input is saved as ``<failures>/<name>/`` with the input
(``.usda`` for the command, ``scene.npz`` for the core) and ``problem.txt`` (what went wrong and how to
replay it). Prints a line per round; exit code 1 when anything failed, 0 otherwise; Ctrl-C ends the run
after saving what it found.
"""

from __future__ import annotations

import argparse
import random
import shutil
import sys
import tempfile
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))   # tests/, for the fuzz package

from fuzz import core_case  # noqa: E402
from fuzz.mutations import mutated_files  # noqa: E402
from fuzz.runner import CASE_SECONDS, Case, describe, run_cases  # noqa: E402
from fuzz.scenes import core_meshes, scenes, write_usda  # noqa: E402

#: Mutated files and random scenes per round (a round takes a minute or two on two cores).
MUTATED_PER_ROUND = 60
SCENES_PER_ROUND = 60
#: Mutation seeds of a run start at --seed times this (CI uses seeds below it).
SEED_STRIDE = 1_000_000


def random_scenes(count: int, seed: int):
    """``count`` scenes drawn by Hypothesis from ``seed`` (same seed, same scenes)."""
    from hypothesis import HealthCheck, given, settings
    from hypothesis import seed as hypothesis_seed

    drawn = []

    @hypothesis_seed(seed)
    @settings(max_examples=count, deadline=None, database=None,
              suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])
    @given(scene=scenes())
    def draw(scene):
        drawn.append(scene)

    draw()
    return drawn


def save_failure(failures: Path, name: str, files, text: str) -> Path:
    """``files``: paths copied into ``<failures>/<name>/``; ``text`` goes to problem.txt."""
    folder = failures / name
    folder.mkdir(parents=True, exist_ok=True)
    for path in files:
        shutil.copy2(path, folder / Path(path).name)
    (folder / "problem.txt").write_text(text + "\n")
    return folder


def command_round(cases, workers: int, seconds: float, failures: Path, describe_input) -> int:
    """Run ``cases`` through the command; save each failing one; the number of failures."""
    found = 0
    for outcome in run_cases(cases, workers=workers, seconds=seconds):
        if outcome.problems():
            found += 1
            text = (f"{describe(outcome)}\n{describe_input(outcome.case)}\n"
                    f"replay: usdksl check {outcome.case.shot.name} {' '.join(outcome.case.arguments)}")
            print(f"  FAILED {save_failure(failures, outcome.case.label, [outcome.case.shot], text)}",
                  flush=True)
    return found


def mutated_round(work: Path, first_seed: int, args, failures: Path) -> int:
    cases = []
    for index, mutated in enumerate(mutated_files(MUTATED_PER_ROUND, first_seed=first_seed)):
        shot = work / mutated.name / f"{mutated.sample}.usda"
        shot.parent.mkdir(parents=True)
        shot.write_bytes(mutated.text())
        arguments = ("--threads", "1") if index % 2 else ()
        cases.append(Case(shot=shot, out=work / mutated.name / "out", arguments=arguments, label=mutated.name))
    by_label = {mutated.name: mutated for mutated in mutated_files(MUTATED_PER_ROUND, first_seed=first_seed)}
    return command_round(cases, args.workers, args.case_seconds, failures,
                         lambda case: f"input: {by_label[case.label]} (fuzz.mutations.MutatedFile)")


def scene_round(work: Path, seed: int, args, failures: Path) -> int:
    drawn = random_scenes(SCENES_PER_ROUND, seed)
    cases, specs = [], {}
    for index, scene in enumerate(drawn):
        label = f"scene-{seed}-{index}"
        shot = work / label / "scene.usda"
        shot.parent.mkdir(parents=True)
        write_usda(scene, shot)
        cases.append(Case(shot=shot, out=work / label / "out", label=label))
        specs[label] = scene
    found = command_round(cases, args.workers, args.case_seconds, failures,
                          lambda case: f"scene: {specs[case.label]}")
    for index, scene in enumerate(drawn):
        meshes = core_meshes(scene)
        if not meshes:
            continue
        problems = core_case.core_problems(meshes)
        if problems:
            found += 1
            label = f"core-{seed}-{index}"
            npz = work / f"{label}.npz"
            core_case.save(meshes, npz)
            text = (f"{label}: {'; '.join(problems)}\nscene: {scene}\n"
                    f"replay: python -c 'from fuzz import core_case; core_case.check_all_methods(\"{npz.name}\")'"
                    f" (from tests/)")
            print(f"  FAILED {save_failure(failures, label, [npz], text)}", flush=True)
    return found


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, required=True, help="how long to run")
    parser.add_argument("--failures", default="fuzz-failures", help="folder for failing inputs")
    parser.add_argument("--seed", type=int, default=None, help="first seed (default: a random one, printed)")
    parser.add_argument("--workers", type=int, default=2, help="runs at a time")
    parser.add_argument("--case-seconds", type=float, default=CASE_SECONDS, help="budget of one run")
    args = parser.parse_args(argv)
    seed = args.seed if args.seed is not None else random.randrange(1, 10 ** 6)
    failures = Path(args.failures).resolve()
    print(f"fuzzing for {args.minutes:g} min from seed {seed}; failing inputs go to {failures}", flush=True)
    deadline = time.monotonic() + args.minutes * 60
    started = time.monotonic()
    found = runs = 0
    round_index = 0
    try:
        while time.monotonic() < deadline:
            work = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-long-"))
            try:
                found += mutated_round(work / "mutated", seed * SEED_STRIDE + round_index * MUTATED_PER_ROUND,
                                       args, failures)
                found += scene_round(work / "scenes", seed * SEED_STRIDE + round_index, args, failures)
            finally:
                shutil.rmtree(work, ignore_errors=True)
            runs += MUTATED_PER_ROUND + 2 * SCENES_PER_ROUND
            round_index += 1
            print(f"round {round_index}: {runs} runs, {found} failing, {time.monotonic() - started:.0f} s",
                  flush=True)
    except KeyboardInterrupt:
        print("stopped", flush=True)
    print(f"{runs} runs in {time.monotonic() - started:.0f} s, {found} failing"
          + (f" (saved in {failures})" if found else ""), flush=True)
    return 1 if found else 0


if __name__ == "__main__":
    sys.exit(main())
