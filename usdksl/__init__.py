"""usdksl: continuous collision checking of USD animation caches.

The native core lives in the private ``usdksl._native`` module; the names a
user needs are re-exported here. The sub-packages, by topic:

``usdksl.reading``     USD in: the stage as world-space arrays, and which mesh pairs are checked
``usdksl.checking``    first contacts (the native core) and the whole check of one shot
``usdksl.reports``     contacts.csv, summary.csv, JSON, JUnit and the override layer, written atomically
``usdksl.crosscheck``  static frames intersected with Embree, held against the continuous result
``usdksl.scale``       many shots, on one process or a Dask cluster, and farm chunks merged
"""

from ._openusd import require_openusd

require_openusd()   # one actionable line when neither usd-core nor a studio USD provides pxr

from . import _native  # noqa: F401  (private; wrapped by the modules below)
from . import ccd, errors
from .checking.collision import CollisionResult, find_contacts
from .checking.pipeline import CheckOptions, CheckResult, check_shot
from .contacts import ContactTable
from .errors import UsdkslInputError, UsdkslUsageError
from .reading.loader import MeshData, Shot, load_shot
from .reports.output import write_files
from .version import __version__

__all__ = [
    "__version__",
    "ccd",
    "CheckOptions",
    "CheckResult",
    "check_shot",
    "CollisionResult",
    "ContactTable",
    "errors",
    "find_contacts",
    "load_shot",
    "MeshData",
    "Shot",
    "UsdkslInputError",
    "UsdkslUsageError",
    "write_files",
]
