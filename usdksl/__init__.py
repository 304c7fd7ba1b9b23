"""usdksl: continuous collision checking of USD animation caches.

The native core lives in the private ``usdksl._native`` module; the names a
user needs are re-exported here. The sub-packages, by topic:

``usdksl.contacts``    the contact table in canonical order, contacts.csv read and written, baselines
``usdksl.reading``     USD in: the stage as world-space arrays, and which mesh pairs are checked
``usdksl.checking``    first contacts: the native core's face (and the shot played backwards, for last contacts)
``usdksl.regions``     contacts grouped into regions (the problems a person fixes), each with its depth
``usdksl.reports``     summary.csv, JSON, JUnit, the override layer and the illustrated page; every file written atomically
``usdksl.crosscheck``  static frames intersected with Embree, held against the continuous result
``usdksl.pipeline``    the whole check of one shot (a file, or a stage open already): load, plan, find first contacts, render every report
``usdksl.scale``       many shots, on one process or a Dask cluster, and farm chunks merged
``usdksl.validation``  the check as a validator of OpenUSD's validation framework (UsdValidation, usdchecker)

They stand on floors (usdksl/README.md): a module imports only its own floor and the floors below it, which
tests/test_import_graph.py enforces.

The names are imported on first use (PEP 562), so that ``import usdksl.stopping`` (which the command
imports first, to hold a Ctrl-C back while numpy and USD load) costs nothing.
"""

from importlib import import_module
from importlib.util import find_spec
from typing import TYPE_CHECKING

from ._openusd import require_openusd

if find_spec("pxr") is None:   # cheap: finds the module without loading USD
    require_openusd()          # one actionable line when neither usd-core nor a studio USD provides pxr

#: Public name -> the module that defines it (a module itself when the name is a sub-module).
_EXPORTS = {
    "_native": "usdksl._native",
    "ccd": "usdksl.ccd",
    "errors": "usdksl.errors",
    "CollisionResult": "usdksl.checking.collision",
    "find_contacts": "usdksl.checking.collision",
    "CheckOptions": "usdksl.pipeline.options",
    "CheckResult": "usdksl.pipeline.result",
    "check_shot": "usdksl.pipeline.check",
    "check_stage": "usdksl.pipeline.stage",
    "register_validators": "usdksl.validation.registration",
    "report_for_results": "usdksl.pipeline.report",
    "RegionTable": "usdksl.regions.table",
    "ContactTable": "usdksl.contacts.table",
    "UsdkslInputError": "usdksl.errors",
    "UsdkslUsageError": "usdksl.errors",
    "MeshData": "usdksl.reading.loader",
    "Shot": "usdksl.reading.loader",
    "load_shot": "usdksl.reading.loader",
    "write_files": "usdksl.reports.output",
}

__all__ = ["__version__"] + sorted(name for name in _EXPORTS if not name.startswith("_"))


def __getattr__(name):
    if name == "__version__":   # the version file the build wrote (usdksl.version), read on first use
        from .version import package_version

        return package_version()
    module_name = _EXPORTS.get(name)
    if module_name is None:
        raise AttributeError(f"module 'usdksl' has no attribute {name!r}")
    require_openusd()   # one actionable line when neither usd-core nor a studio USD provides pxr
    module = import_module(module_name)
    value = module if module_name.endswith("." + name) else getattr(module, name)
    globals()[name] = value
    return value


def __dir__():
    return sorted(set(globals()) | set(_EXPORTS) | {"__version__"})


if TYPE_CHECKING:   # what the names are, for type checkers and readers
    from .version import __version__  # noqa: F401
    from . import _native, ccd, errors  # noqa: F401
    from .checking.collision import CollisionResult, find_contacts  # noqa: F401
    from .contacts.table import ContactTable  # noqa: F401
    from .errors import UsdkslInputError, UsdkslUsageError  # noqa: F401
    from .pipeline.check import check_shot  # noqa: F401
    from .pipeline.stage import check_stage  # noqa: F401
    from .validation.registration import register_validators  # noqa: F401
    from .pipeline.options import CheckOptions  # noqa: F401
    from .pipeline.report import report_for_results  # noqa: F401
    from .regions.table import RegionTable  # noqa: F401
    from .pipeline.result import CheckResult  # noqa: F401
    from .reading.loader import MeshData, Shot, load_shot  # noqa: F401
    from .reports.output import write_files  # noqa: F401
