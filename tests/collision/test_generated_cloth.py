"""KSL and swept on keyframed cloth from samples/generate.py against brute force on the raw samples.

Densely resampled keyframes merge into long flightplan segments, and the
merged methods grow the contact distance by the merge deviation, so their
first contacts may come earlier than brute force's but never later.
"""

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from usdksl.collision import find_contacts
from usdksl.loader import load_shot
from usdksl.scope import plan_shot

from .test_methods_agree import contacts_by_pair

REPO_ROOT = Path(__file__).resolve().parents[2]
TOLERANCE = 1e-6


@pytest.fixture(scope="module", params=[("tablecloth", 300), ("swirl", 200)], ids=lambda p: p[0])
def generated_shot(request, tmp_path_factory):
    scene, faces = request.param
    out = tmp_path_factory.mktemp(scene) / f"{scene}.usdc"
    subprocess.run([sys.executable, str(REPO_ROOT / "samples" / "generate.py"), scene, "--faces", str(faces),
                    "--keyframes", "5", "--samples-per-keyframe", "4", "--out", str(out)],
                   check=True, capture_output=True)
    shot = load_shot(str(out))
    return shot, plan_shot(shot)


def first_contacts(shot, plan, method):
    return contacts_by_pair(find_contacts(shot.meshes, plan.pairs, method=method, tolerance=TOLERANCE))


@pytest.mark.parametrize("method", ["ksl", "swept"])
def test_same_pairs_as_brute_force_and_never_later(generated_shot, method):
    shot, plan = generated_shot
    reference = first_contacts(shot, plan, "brute")
    found = first_contacts(shot, plan, method)
    assert reference, "the generated cloth must touch itself or the table"
    missed = sorted(set(reference) - set(found))
    assert not missed, f"{method} missed contacts brute force finds: {missed[:10]}"
    extra = sorted(set(found) - set(reference))
    assert not extra, f"{method} reported pairs brute force does not: {extra[:10]}"
    interval = float(np.max(np.diff(shot.meshes[-1].times)))
    late = {key: found[key] - t for key, t in reference.items() if found[key] > t + TOLERANCE * interval}
    assert not late, f"{method} first contacts later than brute force: {sorted(late.items())[:5]}"
