"""What --last-contact costs: the check of each shot with and without the backwards run.

    python benchmarks/last_contact_cost.py [SHOT...] [--thickness D]

Runs ``usdksl.check_shot`` on each shot twice in this process (first contacts only, then with last
contacts) and prints the CPU time of the second as a ratio of the first, and the face pairs whose last
contact is later than their first. Ratios come from one run; the machine is shared, so read ratios, not
seconds.
"""

from __future__ import annotations

import argparse
import os
import sys

import numpy as np

import usdksl

HERE = os.path.dirname(os.path.abspath(__file__))
sys.path.insert(0, HERE)
from harness import call  # noqa: E402

DEFAULT_SHOTS = [os.path.join(HERE, "..", "samples", f"{name}.usda") for name in ("fold", "drape")]


def timed(shot: str, options: "usdksl.CheckOptions"):
    """(CPU seconds, result) of checking ``shot``."""
    measured = call(usdksl.check_shot, shot, options)
    return measured.cpu_s, measured.value


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("shots", nargs="*", default=DEFAULT_SHOTS)
    parser.add_argument("--thickness", type=float, default=0.0)
    args = parser.parse_args(argv)
    print(f"{'shot':<40} {'first only':>10} {'cpu ratio':>9} {'pairs':>7} {'last > first':>12}")
    for shot in args.shots:
        first_seconds, first = timed(shot, usdksl.CheckOptions(thickness=args.thickness))
        both_seconds, both = timed(shot, usdksl.CheckOptions(thickness=args.thickness, last_contact=True))
        assert np.array_equal(first.table.time, both.table.time)
        later = int(np.count_nonzero(both.table.last_time > both.table.time))
        print(f"{os.path.basename(shot):<40} {first_seconds:>9.2f}s {both_seconds / first_seconds:>8.2f}x "
              f"{both.table.count:>7} {later:>12}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
