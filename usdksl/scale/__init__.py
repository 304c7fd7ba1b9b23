"""Running at scale: many shots in one call, on this process or a Dask cluster; farm chunks merged.

The names are imported on first use (PEP 562), so that ``usdksl.scale.shot_arguments`` (which every
``usdksl check`` reads its shot arguments with) does not import the many-shot machinery.
"""

from importlib import import_module
from typing import TYPE_CHECKING

#: Public name -> the module that defines it.
_EXPORTS = {name: "usdksl.scale.batch"
            for name in ("ShotJob", "ShotOutcome", "make_jobs", "run_batch", "run_job")}
_EXPORTS["expand_shots"] = "usdksl.scale.shot_arguments"

__all__ = sorted(_EXPORTS)


def __getattr__(name):
    module_name = _EXPORTS.get(name)
    if module_name is None:
        raise AttributeError(f"module 'usdksl.scale' has no attribute {name!r}")
    value = getattr(import_module(module_name), name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS))


if TYPE_CHECKING:   # what the names are, for type checkers and readers
    from .batch import ShotJob, ShotOutcome, make_jobs, run_batch, run_job  # noqa: F401
    from .shot_arguments import expand_shots  # noqa: F401
