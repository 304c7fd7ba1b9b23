"""The shot's hash: SHA-256 of its root layer file, named by the override layer's customLayerData and by a
farm chunk's manifest (docs/contracts.md, Outputs; Windows and merging).

Its own module so that a plain check, which writes the override layer, does not load the manifest's.
"""

from __future__ import annotations

import hashlib
from pathlib import Path
from typing import Union

#: Bytes read at a time when hashing the shot.
_HASH_BLOCK_BYTES = 1 << 20


def file_sha256(path: Union[str, Path]) -> str:
    """Hex SHA-256 of a file's bytes (the shot's root layer; layers it references are not included)."""
    digest = hashlib.sha256()
    with open(path, "rb") as handle:
        for block in iter(lambda: handle.read(_HASH_BLOCK_BYTES), b""):
            digest.update(block)
    return digest.hexdigest()


def text_sha256(text: str) -> str:
    """Hex SHA-256 of ``text`` as UTF-8 (the exported text of a root layer that has no file)."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


__all__ = ["file_sha256", "text_sha256"]
