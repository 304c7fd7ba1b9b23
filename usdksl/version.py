"""The installed package's version, for ``--version``, the JSON report, the override layer and a farm chunk's manifest.

The build writes it into ``usdksl/_version.py`` (``[[tool.scikit-build.generate]]`` in pyproject.toml), for
the wheel and an editable install alike, so reading it costs one tiny import. importlib.metadata would cost
every check tens of milliseconds of start-up, and a plain ``usdksl check`` must not pay that
(tests/cli/test_check_imports.py). A source tree that was never built has no ``_version.py`` (git-ignored):
its version is :data:`UNINSTALLED_VERSION`.
"""

from functools import lru_cache

#: The version reported when usdksl runs from a source tree that was never installed.
UNINSTALLED_VERSION = "0.0.0"


@lru_cache(maxsize=None)
def package_version() -> str:
    """The version this package was built as (UNINSTALLED_VERSION in a source tree that was never built)."""
    try:
        from ._version import version
    except ImportError:   # a source tree on the path, not an installed build: the generated file is not there
        return UNINSTALLED_VERSION
    return version


def __getattr__(name):
    if name == "__version__":
        return package_version()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")
