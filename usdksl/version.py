"""The installed package's version, for ``--version`` and the JSON report."""

from importlib.metadata import PackageNotFoundError, version

try:
    __version__ = version("usdksl")
except PackageNotFoundError:  # running from a source tree without install
    __version__ = "0.0.0"
