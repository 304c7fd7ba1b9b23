"""The shot's hash: SHA-256 of its root layer file, named by the override layer's customLayerData and by a
farm chunk's manifest (docs/contracts.md, Outputs; Windows and merging).

Its own module so that a plain check, which writes the override layer, does not load the manifest's.
"""

from __future__ import annotations

import hashlib
from concurrent.futures import Future, ThreadPoolExecutor
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


def file_sha256_in_background(path: Union[str, Path]) -> "Future[str]":
    """:func:`file_sha256` of ``path`` started on a thread of its own; ``.result()`` waits for it. Reading a file
    and hashing it let other threads run, so a check hashes its shot while it loads and checks it instead of
    after: the root layer of a densely sampled cache is 110 MB, 0.09 s of hashing."""
    executor = ThreadPoolExecutor(max_workers=1, thread_name_prefix="usdksl-shot-hash")
    try:
        return executor.submit(file_sha256, path)
    finally:
        executor.shutdown(wait=False)   # its thread ends with the hash


def text_sha256(text: str) -> str:
    """Hex SHA-256 of ``text`` as UTF-8 (the exported text of a root layer that has no file)."""
    return hashlib.sha256(text.encode("utf-8")).hexdigest()


__all__ = ["file_sha256", "file_sha256_in_background", "text_sha256"]
