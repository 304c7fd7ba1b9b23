"""``python -m usdksl.validation``: the folder PXR_PLUGINPATH_NAME names so that a USD tool (usdchecker) finds
usdksl's validator (README, In your USD tools)."""

from .names import PLUGIN_FOLDER

print(PLUGIN_FOLDER)
