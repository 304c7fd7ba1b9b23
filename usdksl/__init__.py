"""usdksl: continuous collision checking of USD animation caches.

The native core lives in the private ``usdksl._native`` module; the names a
user needs are re-exported here.
"""

from importlib.metadata import PackageNotFoundError, version

from ._openusd import require_openusd

require_openusd()   # one actionable line when neither usd-core nor a studio USD provides pxr

from . import _native  # noqa: F401  (private; wrapped by the modules below)
from . import ccd
from .collision import CollisionResult, FaceContacts, find_contacts
from .errors import UsdkslInputError, UsdkslUsageError
from .loader import MeshData, Shot, load_shot

try:
    __version__ = version("usdksl")
except PackageNotFoundError:  # running from a source tree without install
    __version__ = "0.0.0"

__all__ = [
    "__version__",
    "ccd",
    "CollisionResult",
    "FaceContacts",
    "find_contacts",
    "load_shot",
    "MeshData",
    "Shot",
    "UsdkslInputError",
    "UsdkslUsageError",
]
