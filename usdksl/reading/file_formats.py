"""File formats the USD build at hand cannot read, named in one line that says how to convert, not in pxr's words.

Cloth and character caches often come as Alembic. OpenUSD reads ``.abc`` only through its usdAbc file format
plugin, which a build has only when asked for (``build_usd.py --alembic``, ``PXR_BUILD_ALEMBIC_PLUGIN``); the
usd-core wheel on PyPI has none. Without it ``Usd.Stage.Open("shot.abc")`` fails with "Cannot determine file
format for @shot.abc@", and a reference or sublayer to an ``.abc`` asset resolves but does not open, so its prim
composes empty. Neither says what a TD should do about it, so usdksl says it:

* :func:`require_file_format` refuses the shot itself before the stage is opened (``usdksl.reading.loader``);
* :func:`missing_format_note` is what an asset the stage asks for adds to "resolves but does not open"
  (``usdksl.reading.composition``).

Where the build has the plugin, an ``.abc`` is a layer like any other and nothing here gets in its way.
"""

from __future__ import annotations

import os
from typing import Union

from pxr import Ar, Sdf, Tf

from ..errors import UsdkslInputError

#: The extension of Alembic files (compared without case) and OpenUSD's plugin that reads them.
ALEMBIC_EXTENSION = "abc"
ALEMBIC_PLUGIN = "usdAbc"
#: What the conversion writes: USD's binary crate format, compact for a cache of many samples.
CONVERTED_EXTENSION = ".usdc"


def reads_format(path: str) -> bool:
    """Whether this USD build has a file format plugin for ``path`` (by its extension, as Sdf chooses one; a
    package-relative ``a.usdz[b.usdc]`` by its inner file)."""
    try:
        return Sdf.FileFormat.FindByExtension(path) is not None
    except Tf.ErrorException:   # a path without an extension: no format is found for it
        return False


def is_unreadable_alembic(path: Union[str, os.PathLike]) -> bool:
    """``path`` names an Alembic file and this USD build has no plugin to read it."""
    text, _ = Sdf.Layer.SplitIdentifier(os.fspath(path))   # without file format arguments
    extension = Ar.GetResolver().GetExtension(text)
    return extension.lower() == ALEMBIC_EXTENSION and not reads_format(text)


def conversion_command(path: Union[str, os.PathLike]) -> str:
    """``usdcat shot.abc -o shot.usdc``: the command that converts ``path`` beside itself (quoted for a shell)."""
    import shlex   # only an error message needs it

    text, _ = Sdf.Layer.SplitIdentifier(os.fspath(path))
    converted = os.path.splitext(text)[0] + CONVERTED_EXTENSION
    return f"usdcat {shlex.quote(text)} -o {shlex.quote(converted)}"


def require_file_format(path: Union[str, os.PathLike]) -> None:
    """Refuse, with one line naming ``path``, an Alembic shot this USD build cannot read (exit code 2): pxr's
    own error says only that it cannot determine the file format. Returns for anything else."""
    if not is_unreadable_alembic(path):
        return
    raise UsdkslInputError(
        f"this USD build cannot read Alembic (it has no {ALEMBIC_PLUGIN} file format plugin; the usd-core wheel "
        f"from PyPI has none): convert the file with a USD build that has {ALEMBIC_PLUGIN} "
        f"({conversion_command(path)}) and check the {CONVERTED_EXTENSION}, or run usdksl with such a build",
        file=os.fspath(path))


def missing_format_note(asset_path: str) -> str:
    """What an asset that resolves but does not open adds to its line when it is Alembic and this build cannot
    read it (``asset_path`` as authored; empty otherwise): that it is Alembic, and how to convert it."""
    if not is_unreadable_alembic(asset_path):
        return ""
    return (f": it is Alembic and this USD build has no {ALEMBIC_PLUGIN} file format plugin; convert it with a "
            f"USD build that has {ALEMBIC_PLUGIN} ({conversion_command(asset_path)}) and use the "
            f"{CONVERTED_EXTENSION} in its place, or run usdksl with such a build")


__all__ = ["ALEMBIC_EXTENSION", "ALEMBIC_PLUGIN", "CONVERTED_EXTENSION", "conversion_command",
           "is_unreadable_alembic", "missing_format_note", "reads_format", "require_file_format"]
