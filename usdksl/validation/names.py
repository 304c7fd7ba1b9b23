"""The names usdksl's validator is known by in OpenUSD's validation framework, and where its plugin lies.

Kept apart from the validator so that ``python -m usdksl.validation`` (which prints the plugin folder for
``PXR_PLUGINPATH_NAME``) loads neither USD nor the check.
"""

from pathlib import Path

#: The plugin's name (plugin/plugInfo.json): UsdValidation names a plugin's validators ``<plugin>:<validator>``.
PLUGIN_NAME = "usdkslValidators"
#: The stage validator that checks a stage for interpenetrations over time.
VALIDATOR = "NoInterpenetration"
VALIDATOR_NAME = f"{PLUGIN_NAME}:{VALIDATOR}"
#: The keyword its metadata carries (``GetValidatorMetadataForKeyword``), as OpenUSD's own plugins carry theirs.
KEYWORD = "UsdkslValidators"
#: The validator's doc, as plugInfo.json says it (used when the registry was built before the plugin was known).
DOC = ("Meshes must not pass into each other or themselves over the validated time range (the stage's whole "
       "range by default): one error per contact region, on its two prims, with its first contact time and frame; "
       "an error for anything usdksl could not read.")

#: The folder of plugInfo.json: what PXR_PLUGINPATH_NAME names so that a USD tool finds the validator.
PLUGIN_FOLDER = Path(__file__).resolve().parent / "plugin"

#: Names of the UsdValidationError a run returns (``<validator>.<name>`` is its identifier).
INTERPENETRATION = "Interpenetration"
#: ... for what the check could not read: a coverage entry that is not checked.
NOT_CHECKED = "NotChecked"
#: ... for a stage the check refused (bad input: an asset that does not resolve, a payload not loaded, ...).
NOT_READ = "CheckRefused"
#: ... for a vertex that blows up or a cache glitch: contacts it causes are real on the cache (a warning).
SUSPECT_MOTION = "SuspectMotion"
