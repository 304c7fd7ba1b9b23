"""The ``usdksl`` command line; installed as ``usdksl.cli``. It imports the library by absolute name
(``usdksl.pipeline...``) and its own modules relatively, so it reads the same in the checkout and the wheel."""
