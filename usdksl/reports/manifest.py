"""The run manifest ``<stem>.usdksl-run.json``: what a time-range run checked, so its outputs can be merged.

Written beside the other files by every ``usdksl check --time-range A B`` (a farm chunk) and by
``usdksl merge``. It names the shot (and the SHA-256 of its root layer file, so a chunk of another shot,
or of an edited one, is refused), the settings (time range included), the range checked, the mesh pairs
checked and the number of constant-topology segments, and the usdksl version.
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import List, Optional, Sequence, Tuple, Union

from .shot_hash import file_sha256

MANIFEST_SUFFIX = ".usdksl-run.json"


def checked_pairs(plan) -> List[List[str]]:
    """The plan's checked mesh pairs as sorted [prim_a, prim_b] path pairs (comparable across runs)."""
    return sorted(sorted((plan.paths[i], plan.paths[j])) for i, j in plan.pairs.tolist())


def manifest_text(shot: str, shot_sha256: str, settings: dict, span: Tuple[float, float], plan,
                  segment_count: int, version: str) -> str:
    document = {"tool": "usdksl", "version": version, "shot": str(shot), "shot_sha256": shot_sha256,
                "settings": settings, "time_range": [float(span[0]), float(span[1])],
                "checked_pairs": checked_pairs(plan), "segments": int(segment_count)}
    return json.dumps(document, indent=1, allow_nan=False) + "\n"


def read_manifest(path: Union[str, Path]) -> Optional[dict]:
    """The manifest at ``path``, or None when there is none; raises ValueError when it is not one."""
    path = Path(path)
    if not path.is_file():
        return None
    document = json.loads(path.read_text(encoding="utf-8"))
    if not isinstance(document, dict) or document.get("tool") != "usdksl" or "time_range" not in document:
        raise ValueError("not a usdksl run manifest")
    return document


def manifest_name(stem: str) -> str:
    return f"{stem}{MANIFEST_SUFFIX}"


__all__: Sequence[str] = ["MANIFEST_SUFFIX", "checked_pairs", "file_sha256", "manifest_name", "manifest_text",
                          "read_manifest"]
