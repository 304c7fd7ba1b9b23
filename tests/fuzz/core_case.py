"""One random scene straight into the native core, every method, in a child process (fuzz/runner.py
run_function): what each method answered, as JSON on stdout. Imports nothing heavy beyond numpy and the
core, so a child forked from the runner's fork server starts at once."""

from __future__ import annotations

import json
import math
import shutil
import sys
import tempfile
from pathlib import Path
from typing import List, Tuple

import numpy as np


def check_all_methods(npz_path: str) -> None:
    from usdksl.checking.collision import METHODS, find_contacts

    data = np.load(npz_path)
    count = int(data["count"])
    meshes = [MeshArrays(data[f"times{i}"], data[f"points{i}"], data[f"triangles{i}"], data[f"faces{i}"])
              for i in range(count)]
    answers = {}
    for method in METHODS:
        try:
            result = find_contacts(meshes, all_pairs(count), method=method)
        except ValueError as error:
            answers[method] = {"error": str(error)}
            continue
        answers[method] = {"rows": [[float(t), int(ma), int(ta), int(mb), int(tb)] for t, ma, ta, mb, tb in
                                    zip(result.time, result.mesh_a, result.tri_a, result.mesh_b, result.tri_b)],
                           "undecided": int(np.count_nonzero(result.undecided))}
    sys.stdout.write(json.dumps(answers) + "\n")


def all_pairs(count: int) -> List[Tuple[int, int]]:
    """Every mesh pair, self pairs included."""
    return [(i, j) for i in range(count) for j in range(i, count)]


class MeshArrays:
    def __init__(self, times, points, triangles, triangle_face):
        self.times, self.points, self.triangles, self.triangle_face = times, points, triangles, triangle_face


def save(meshes, path) -> None:
    arrays = {"count": np.array(len(meshes))}
    for i, (times, points, triangles, faces) in enumerate(meshes):
        arrays.update({f"times{i}": times, f"points{i}": points, f"triangles{i}": triangles, f"faces{i}": faces})
    np.savez(path, **arrays)


#: Seconds one core run of a tiny scene (all four methods) may take.
CORE_SECONDS = 60.0


def core_problems(meshes, seconds: float = CORE_SECONDS) -> List[str]:
    """Run every method on ``meshes`` (scenes.core_meshes) in a child process; what is wrong (empty:
    nothing): a hang, a crash, a traceback, finite input refused, a time outside the checked span or a
    triangle out of range, and on finite input a continuous method that differs from brute force."""
    from fuzz.runner import run_function

    folder = Path(tempfile.mkdtemp(prefix="usdksl-fuzz-core-"))
    try:
        save(meshes, folder / "scene.npz")
        code, output = run_function(check_all_methods, [str(folder / "scene.npz")], seconds)
    finally:
        shutil.rmtree(folder, ignore_errors=True)
    if code is None:
        return [f"the core hung (still running after {seconds:.0f} s)"]
    if code != 0 or "Traceback" in output:
        return [f"the core failed (exit {code}): {output[-2000:]}"]
    answers = json.loads(output.strip().splitlines()[-1])
    finite = all(np.isfinite(points).all() for _, points, _, _ in meshes)
    begin = min(float(times[0]) for times, *_ in meshes)
    end = max(float(times[-1]) for times, *_ in meshes)
    problems = []
    for method, answer in answers.items():
        if "error" in answer:
            if finite:
                problems.append(f"{method} refused finite input: {answer['error']}")
            continue
        for time, mesh_a, tri_a, mesh_b, tri_b in answer["rows"]:
            if not (math.isfinite(time) and begin <= time <= end):
                problems.append(f"{method}: time {time} outside [{begin}, {end}]")
            if not (tri_a < len(meshes[mesh_a][2]) and tri_b < len(meshes[mesh_b][2])):
                problems.append(f"{method}: triangle out of range ({mesh_a}, {tri_a}, {mesh_b}, {tri_b})")
    if finite:
        reference = {tuple(row[1:]): row[0] for row in answers["brute"]["rows"]}
        for method in ("ksl", "swept"):
            found = {tuple(row[1:]): row[0] for row in answers[method]["rows"]}
            if found != reference:
                missed = sorted(set(reference) - set(found))[:5]
                extra = sorted(set(found) - set(reference))[:5]
                moved = sorted(key for key in set(found) & set(reference) if found[key] != reference[key])[:5]
                problems.append(f"{method} differs from brute force: missed {missed}, extra {extra}, "
                                f"other times {moved}")
    return problems
