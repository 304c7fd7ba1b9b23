"""Making usdksl's validator known to OpenUSD's validation framework in this process.

A USD tool finds it through its plugin (plugin/plugInfo.json on PXR_PLUGINPATH_NAME; README, In your USD
tools): UsdValidationRegistry reads the plugin's validator metadata when it is first built, and loading the
plugin registers the task function (:mod:`usdksl.validation.plugin_load`). In a Python session, a DCC's or a
test's, :func:`register_validators` does both on the spot, whenever it is called: the registry may have been
built before (usdksl was imported late, another tool asked for validators first), and then it never reads
plugins registered after it, so the validator is registered with its metadata spelled out here instead. The
validator is the same either way.
"""

from __future__ import annotations

from pxr import Plug, UsdValidation

from .names import DOC, KEYWORD, PLUGIN_FOLDER, VALIDATOR_NAME
from .task import no_interpenetration


def register_validators() -> UsdValidation.Validator:
    """Register usdksl's plugin with Plug and its validator, ``usdkslValidators:NoInterpenetration``, with
    UsdValidation's registry, and return the validator. Calling it again changes nothing (idempotent)."""
    Plug.Registry().RegisterPlugins(str(PLUGIN_FOLDER))   # registers nothing the second time
    register_task()
    return UsdValidation.ValidationRegistry().GetOrLoadValidatorByName(VALIDATOR_NAME)


def register_task() -> None:
    """Register the task function of ``usdkslValidators:NoInterpenetration`` unless it is registered: as the
    plugin's validator when the registry read the plugin's metadata, else with the same metadata given here."""
    registry = UsdValidation.ValidationRegistry()
    if registry.HasValidator(VALIDATOR_NAME):
        return
    if registry.GetValidatorMetadata(VALIDATOR_NAME) is not None:
        registry.RegisterPluginStageValidator(VALIDATOR_NAME, no_interpenetration)
        return
    registry.RegisterStageValidator(UsdValidation.ValidatorMetadata(
        name=VALIDATOR_NAME, doc=DOC, keywords=[KEYWORD], schemaTypes=[], isTimeDependent=False, isSuite=False),
        no_interpenetration)


__all__ = ["register_task", "register_validators"]
