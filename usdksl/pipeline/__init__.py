"""The pipeline: the check of one shot, from the USD file to the text of every report (usdksl/README.md, Floors).

``check`` runs it (:func:`~usdksl.pipeline.check.check_shot`); ``options`` is what it is asked to do,
``messages`` what it says, ``loading`` the shot loaded in pieces, ``files`` where the reports go and what
they hold, ``result`` what it returns; ``coverage`` accounts for every prim and stretch, ``memory_budget``
refuses a shot that would not fit, ``progress`` draws the bar on a terminal.

The names are imported on first use (PEP 562), so that ``usdksl.pipeline.progress`` (which the many-shot
bar reads) does not import the whole check.
"""

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

#: Public name -> the module that defines it.
_EXPORTS = {
    "CheckOptions": "usdksl.pipeline.options",
    "CheckResult": "usdksl.pipeline.result",
    "Message": "usdksl.pipeline.messages",
    "OutputTargets": "usdksl.pipeline.files",
    "check_shot": "usdksl.pipeline.check",
    "check_stage": "usdksl.pipeline.stage",
    "output_targets": "usdksl.pipeline.files",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


if TYPE_CHECKING:   # what the names are, for type checkers and readers
    from .check import check_shot  # noqa: F401
    from .stage import check_stage  # noqa: F401
    from .files import OutputTargets, output_targets  # noqa: F401
    from .messages import Message  # noqa: F401
    from .options import CheckOptions  # noqa: F401
    from .result import CheckResult  # noqa: F401
