"""The ``usdksl`` command line; installed as ``usdksl.cli``."""
