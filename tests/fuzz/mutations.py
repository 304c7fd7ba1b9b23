"""Seeded, deterministic mutations of USD text: what a broken export, a bad merge or a flaky disk makes
of a cache. Every mutation is a pure function of (text, random.Random), so a case is named by its
sample, seed and kind, and replays exactly."""

from __future__ import annotations

import random
import re
from dataclasses import dataclass
from pathlib import Path
from typing import Callable, Dict, List, Sequence

SAMPLES = Path(__file__).resolve().parents[2] / "samples"
#: Values a number is replaced by: non-finite, the float and int extremes, subnormals, signed zeros.
EXTREME_VALUES = ("nan", "-nan", "inf", "-inf", "1e308", "-1e308", "1e39", "1e-320", "-0", "0",
                  "2147483647", "-2147483648", "4294967296", "9223372036854775807",
                  "99999999999999999999999", "1e400")
NUMBER = re.compile(rb"-?\d+(?:\.\d+)?(?:[eE][-+]?\d+)?")


def _lines(text: bytes) -> List[bytes]:
    return text.split(b"\n")


def delete_line(text: bytes, rng: random.Random) -> bytes:
    lines = _lines(text)
    del lines[rng.randrange(len(lines))]
    return b"\n".join(lines)


def delete_lines(text: bytes, rng: random.Random) -> bytes:
    lines = _lines(text)
    start = rng.randrange(len(lines))
    del lines[start:start + rng.randint(2, 8)]
    return b"\n".join(lines)


def duplicate_line(text: bytes, rng: random.Random) -> bytes:
    lines = _lines(text)
    index = rng.randrange(len(lines))
    lines.insert(index, lines[index])
    return b"\n".join(lines)


def swap_lines(text: bytes, rng: random.Random) -> bytes:
    lines = _lines(text)
    a, b = rng.randrange(len(lines)), rng.randrange(len(lines))
    lines[a], lines[b] = lines[b], lines[a]
    return b"\n".join(lines)


def replace_number(text: bytes, rng: random.Random) -> bytes:
    """One number (a coordinate, an index, a count, a time) becomes an extreme value."""
    matches = list(NUMBER.finditer(text))
    if not matches:
        return text
    match = matches[rng.randrange(len(matches))]
    value = rng.choice(EXTREME_VALUES).encode()
    return text[:match.start()] + value + text[match.end():]


def replace_numbers(text: bytes, rng: random.Random) -> bytes:
    for _ in range(rng.randint(2, 6)):
        text = replace_number(text, rng)
    return text


def replace_coordinate_by_huge(text: bytes, rng: random.Random) -> bytes:
    """One coordinate inside a points sample becomes a huge but finite value (a solver blow-up)."""
    sample_lines = [i for i, line in enumerate(_lines(text)) if line.lstrip().startswith(b"(")
                    or re.match(rb"\s*\d+(\.\d+)?: \[\(", line)]
    if not sample_lines:
        return replace_number(text, rng)
    lines = _lines(text)
    index = rng.choice(sample_lines)
    matches = list(NUMBER.finditer(lines[index]))[1:]   # not the sample's time
    if not matches:
        return text
    match = rng.choice(matches)
    value = rng.choice(("1e5", "1e7", "1e9", "2147483647", "1e15", "1e30", "3.4e38")).encode()
    lines[index] = lines[index][:match.start()] + value + lines[index][match.end():]
    return b"\n".join(lines)


def truncate(text: bytes, rng: random.Random) -> bytes:
    return text[:rng.randrange(len(text))]


def random_bytes(text: bytes, rng: random.Random) -> bytes:
    data = bytearray(text)
    for _ in range(rng.randint(1, 8)):
        position = rng.randrange(len(data))
        data[position:position + rng.randint(0, 3)] = bytes(rng.randrange(256) for _ in range(rng.randint(1, 4)))
    return bytes(data)


MUTATIONS: Dict[str, Callable[[bytes, random.Random], bytes]] = {
    "delete_line": delete_line,
    "delete_lines": delete_lines,
    "duplicate_line": duplicate_line,
    "swap_lines": swap_lines,
    "replace_number": replace_number,
    "replace_numbers": replace_numbers,
    "huge_coordinate": replace_coordinate_by_huge,
    "truncate": truncate,
    "random_bytes": random_bytes,
}


@dataclass(frozen=True)
class MutatedFile:
    """A sample mutated by one kind of mutation with one seed: replays exactly from its name."""

    sample: str
    kind: str
    seed: int

    @property
    def name(self) -> str:
        return f"{self.sample}-{self.kind}-{self.seed}"

    def text(self) -> bytes:
        original = (SAMPLES / f"{self.sample}.usda").read_bytes()
        return MUTATIONS[self.kind](original, random.Random(f"{self.sample}/{self.kind}/{self.seed}"))


def sample_names() -> List[str]:
    return sorted(path.stem for path in SAMPLES.glob("*.usda"))


def mutated_files(count: int, first_seed: int = 0, samples: Sequence[str] = ()) -> List[MutatedFile]:
    """``count`` cases cycling through samples and kinds, seeds from ``first_seed`` on."""
    samples = list(samples) or sample_names()
    kinds = sorted(MUTATIONS)
    cases = []
    for index in range(count):
        seed = first_seed + index
        cases.append(MutatedFile(samples[index % len(samples)], kinds[(index // len(samples)) % len(kinds)], seed))
    return cases
