"""usdksl in OpenUSD's validation framework (UsdValidation: what ``usdchecker`` is built on).

``usdkslValidators:NoInterpenetration`` is a stage validator that checks a stage with
:func:`usdksl.pipeline.stage.check_stage` over the validation's time range and returns one UsdValidationError per
contact region (docs/contracts.md, In USD tools). ``names`` holds its names and plugin folder, ``task`` the task
function, ``validation_errors`` the errors it returns, ``registration`` :func:`register_validators` (in this
process), ``plugin_load`` what a USD tool imports when it loads the plugin (``plugin/plugInfo.json``), and
``python -m usdksl.validation`` prints the plugin folder for PXR_PLUGINPATH_NAME.

The names are imported on first use (PEP 562): ``python -m usdksl.validation`` loads neither USD nor the check.
"""

from typing import TYPE_CHECKING

from ..lazy_exports import lazy_exports

#: Public name -> the module that defines it.
_EXPORTS = {
    "PLUGIN_FOLDER": "usdksl.validation.names",
    "VALIDATOR_NAME": "usdksl.validation.names",
    "no_interpenetration": "usdksl.validation.task",
    "register_validators": "usdksl.validation.registration",
}

__all__ = sorted(_EXPORTS)


__getattr__, __dir__ = lazy_exports(__name__, _EXPORTS, globals())


if TYPE_CHECKING:   # what the names are, for type checkers and readers
    from .names import PLUGIN_FOLDER, VALIDATOR_NAME  # noqa: F401
    from .registration import register_validators  # noqa: F401
    from .task import no_interpenetration  # noqa: F401
