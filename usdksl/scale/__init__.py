"""Running at scale: many shots in one call, on this process or a Dask cluster; farm chunks merged.

The names are imported on first use (PEP 562), so that ``usdksl.scale.shot_arguments`` (which every
``usdksl check`` reads its shot arguments with) does not import the many-shot machinery.
"""

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

#: Public name -> the module that defines it.
_EXPORTS = {name: "usdksl.scale.batch"
            for name in ("ShotJob", "ShotOutcome", "make_jobs", "run_batch", "run_job")}
_EXPORTS["expand_shots"] = "usdksl.scale.shot_arguments"

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


if TYPE_CHECKING:   # what the names are, for type checkers and readers
    from .batch import ShotJob, ShotOutcome, make_jobs, run_batch, run_job  # noqa: F401
    from .shot_arguments import expand_shots  # noqa: F401
