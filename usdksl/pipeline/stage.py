"""The check of a stage that is open already: a DCC's stage, or one a validator is handed.

:func:`check_stage` checks an open ``Usd.Stage`` as :func:`usdksl.pipeline.check.check_shot` checks a file,
and returns the same :class:`~usdksl.pipeline.result.CheckResult`. Nothing is opened again: what the stage
composes is what is checked, its session layer's opinions, variant selections, population mask and loaded
payloads included (docs/contracts.md, In USD tools). The unresolved-asset rule holds on it, and a payload the
stage has not loaded counts as an asset that is missing (usdksl.reading.composition).

The reports are named after the file of the stage's root layer, and go beside it unless ``targets`` says
otherwise. A root layer that lives only in memory (an anonymous layer, ``Usd.Stage.CreateInMemory``) has no
file: its reports go into ``targets`` or the working directory, its shot hash is the SHA-256 of its exported
text, and there is no override layer, which would have no file to sublayer (a message says so).
"""

from __future__ import annotations

import os
from pathlib import Path
from typing import Callable, List, Optional, Tuple

from pxr import Usd

from ..errors import UsdkslUsageError
from ..regions.baseline import AnyBaseline
from .check import ProgressFactory, check_shot
from .files import OutputTargets, root_layer_file
from .messages import INFO, WARNING, Message
from .options import CheckOptions
from .result import CheckResult

#: Name of a stage whose in-memory root layer has no display name either.
UNNAMED_STAGE = "stage"

# Messages said before the check's own (level, text).
NO_OVERRIDE_LAYER = ("the stage's root layer is in memory ({layer}): no override layer, which would sublayer "
                     "the shot's file (export the root layer and check that file for one); the reports go to "
                     "{folder}")
UNSAVED_EDITS = ("{layer} has unsaved edits: they are checked, but the override layer sublayers the file on "
                 "disk and its shot hash is the file's, both without them (save the layer to keep them together)")
SESSION_OPINIONS = ("the stage's session layer has opinions: they are checked, but the override layer sublayers "
                    "the root layer only")
POPULATION_MASK = ("the stage's population mask holds {paths}: prims outside it are not on the stage and are not "
                   "checked")


def check_stage(stage: Usd.Stage, options: CheckOptions = CheckOptions(), targets: Optional[OutputTargets] = None,
                name: Optional[str] = None, on_message: Optional[Callable[[Message], None]] = None,
                progress: Optional[ProgressFactory] = None,
                baseline: Optional[AnyBaseline] = None) -> CheckResult:
    """Check the open ``stage`` and render its reports; write nothing (``usdksl.write_files`` writes
    ``result.files``). Arguments as :func:`usdksl.pipeline.check.check_shot`'s; ``name`` defaults to the root
    layer's identifier (for an in-memory one, its display name). Raises UsdkslInputError on bad input (an asset
    that does not resolve or a payload not loaded, unless ``options.allow_missing_assets``) and
    UsdkslUsageError when ``stage`` is not an open stage."""
    if not isinstance(stage, Usd.Stage) or not stage.GetPseudoRoot():
        raise UsdkslUsageError(f"check_stage takes an open Usd.Stage, got {type(stage).__name__}")
    root = stage.GetRootLayer()
    file = _root_file(root)
    notes = _stage_notes(stage)
    if file is not None:
        if root.dirty:
            notes.append((WARNING, UNSAVED_EDITS.format(layer=root.identifier)))
        name = name or root.identifier
        _say(notes, on_message)
        result = check_shot(file, options, targets, on_message, progress, name, baseline, stage=stage)
        result.messages[:0] = _messages(notes)
        return result
    return _check_in_memory(stage, options, targets, name or root.GetDisplayName() or UNNAMED_STAGE, on_message,
                            progress, baseline, notes)


def _root_file(root) -> Optional[str]:
    """The file on disk that holds ``root`` (its real path), or None for a layer that lives in memory only (or
    whose asset is no local file: nothing to sublayer or hash)."""
    path = "" if root.anonymous else root.realPath
    return path if path and os.path.isfile(root_layer_file(path)) else None


def _stage_notes(stage: Usd.Stage) -> List[Tuple[str, str]]:
    """What a check of ``stage`` says first about how it differs from its root layer file."""
    notes = []
    if not stage.GetSessionLayer().empty:
        notes.append((INFO, SESSION_OPINIONS))
    mask = stage.GetPopulationMask()
    if mask != Usd.StagePopulationMask.All():
        paths = ", ".join(str(path) for path in mask.GetPaths()) or "nothing"
        notes.append((INFO, POPULATION_MASK.format(paths=paths)))
    return notes


def _check_in_memory(stage: Usd.Stage, options: CheckOptions, targets: Optional[OutputTargets], name: str,
                     on_message: Optional[Callable[[Message], None]], progress: Optional[ProgressFactory],
                     baseline: Optional[AnyBaseline], notes: List[Tuple[str, str]]) -> CheckResult:
    """:func:`check_stage` of a stage whose root layer has no file: the check reads ``stage`` and names it
    ``name``; the reports' shot hash is its root layer's exported text's, and there is no override layer."""
    root = stage.GetRootLayer()
    targets = targets or OutputTargets(out_dir=Path.cwd())
    notes.append((WARNING, NO_OVERRIDE_LAYER.format(layer=root.identifier, folder=targets.out_dir)))
    _say(notes, on_message)
    result = check_shot(name, options, targets, on_message, progress, name, baseline, stage=stage,
                        root_layer_text=root.ExportToString())
    result.messages[:0] = _messages(notes)
    return result


def _say(notes: List[Tuple[str, str]], on_message: Optional[Callable[[Message], None]]) -> None:
    """Hand each note to ``on_message`` as the check hands its own messages (they lead ``result.messages``)."""
    if on_message is not None:
        for message in _messages(notes):
            on_message(message)


def _messages(notes: List[Tuple[str, str]]) -> List[Message]:
    return [Message(level, text) for level, text in notes]


__all__ = ["check_stage"]
