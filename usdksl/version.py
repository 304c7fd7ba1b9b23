"""The installed package's version, for ``--version``, the JSON report and a farm chunk's manifest.

Looked up on first use: importlib.metadata costs tens of milliseconds at start-up, and a plain
``usdksl check`` never needs the version. ``from usdksl.version import __version__`` still works
(PEP 562) but pays for the lookup at import; code on the check's path calls :func:`package_version`.
"""

from functools import lru_cache

#: The version reported when usdksl runs from a source tree that was never installed.
UNINSTALLED_VERSION = "0.0.0"


@lru_cache(maxsize=None)
def package_version() -> str:
    """The installed distribution's version string (UNINSTALLED_VERSION without one)."""
    from importlib.metadata import PackageNotFoundError, version

    try:
        return version("usdksl")
    except PackageNotFoundError:  # running from a source tree without install
        return UNINSTALLED_VERSION


def __getattr__(name):
    if name == "__version__":
        return package_version()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
