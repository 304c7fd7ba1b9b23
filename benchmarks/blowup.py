"""What one exploded vertex costs: a sample shot against copies with one vertex blown far away.

    python benchmarks/blowup.py [SHOT] [--vertex V] [--time T] [--heights 1e3 1e5 1e7 1e9]

Moves vertex V of the shot's first deforming mesh to y = H at the sample nearest time T (a
simulation blow-up), checks every copy with the default method in this process, and prints, per
height: CPU time as a ratio of the unmodified shot's (target: at most 3x), whether every
contact away from the blown-up vertex's faces equals the unmodified run's, the number of pairs,
and the blow-up warning. Ratios come from one run; the machine is shared, so read ratios, not seconds.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import sys
from typing import Dict, List, Sequence, Tuple

import usdksl
from usdksl.reading.blowups import describe_blowups, shot_blowups

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from blowup_setup import add_blowup_arguments, blowup_target  # noqa: E402
from harness import measuring  # noqa: E402

DEFAULT_SHOT = os.path.join(HERE, "..", "samples", "drape.usda")
#: A blown-up copy may cost at most this many times the unmodified shot's CPU: one bad vertex must not make
#: a shot unaffordable to check.
COST_RATIO_TARGET = 3.0


def default_pairs(meshes: Sequence) -> List[Tuple[int, int]]:
    """Self pairs of deforming meshes and every inter pair with a deforming mesh (the default scope)."""
    deforming = [mesh.kind == "deforming" for mesh in meshes]
    pairs = [(i, i) for i, d in enumerate(deforming) if d]
    pairs += [(i, j) for i in range(len(meshes)) for j in range(i + 1, len(meshes)) if deforming[i] or deforming[j]]
    return pairs


def face_times(result, meshes) -> Dict[Tuple[int, int, int, int], float]:
    faces = result.face_contacts(meshes)
    return {(int(a), int(fa), int(b), int(fb)): float(t)
            for t, a, fa, b, fb in zip(faces.time, faces.mesh_a, faces.face_a, faces.mesh_b, faces.face_b)}


def away_from(contacts: Dict, mesh: int, faces: set) -> Dict:
    return {key: t for key, t in contacts.items()
            if not ((key[0] == mesh and key[1] in faces) or (key[2] == mesh and key[3] in faces))}


def timed_check(meshes, pairs):
    """(CPU seconds, contacts, blow-ups) of the blow-up scan and the check together."""
    with measuring() as measured:
        blowups = shot_blowups(meshes)
        result = usdksl.find_contacts(meshes, pairs)
    return measured.cpu_s, result, blowups


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    add_blowup_arguments(parser, DEFAULT_SHOT)
    args = parser.parse_args(argv)

    shot = usdksl.load_shot(args.shot)
    meshes = shot.meshes
    blowup = blowup_target(meshes, args)
    target, mesh, vertex, sample = blowup.mesh_index, blowup.mesh, blowup.vertex, blowup.sample
    pairs = default_pairs(meshes)
    blown_faces = set(mesh.triangle_face[(mesh.triangles == vertex).any(axis=1)].tolist())

    base_seconds, base, _ = timed_check(meshes, pairs)
    base_contacts = face_times(base, meshes)
    print(f"shot {args.shot}: {mesh.path} vertex {vertex} at time {mesh.times[sample]:g}; "
          f"unmodified: {base_seconds:.2f} s CPU, {len(base_contacts)} face pairs")
    print(f"{'height':>8} {'cpu ratio':>9} {'pairs':>7} {'away equal':>10}  warning")
    worst = 0.0
    all_equal = True
    for height in args.heights:
        blown = list(meshes)
        blown[target] = dataclasses.replace(mesh, points=blowup.blown_points(height))
        seconds, result, blowups = timed_check(blown, pairs)
        contacts = face_times(result, blown)
        equal = away_from(contacts, target, blown_faces) == away_from(base_contacts, target, blown_faces)
        warning = describe_blowups(blowups, os.path.basename(args.shot))
        ratio = seconds / base_seconds
        worst = max(worst, ratio)
        all_equal = all_equal and equal
        print(f"{height:8.0e} {ratio:9.2f} {len(contacts):7d} {str(equal):>10}  "
              f"{warning[0] if warning else 'NO WARNING'}")
    verdict = "met" if worst <= COST_RATIO_TARGET and all_equal else "MISSED"
    print(f"worst cost ratio {worst:.2f} (target <= {COST_RATIO_TARGET:g}), contacts away equal: {all_equal}: {verdict}")
    return 0 if verdict == "met" else 1


if __name__ == "__main__":
    sys.exit(main())
