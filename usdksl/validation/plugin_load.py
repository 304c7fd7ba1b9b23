"""What Plug imports when a USD tool loads usdksl's validator plugin (plugin/plugInfo.json): importing it
registers the task function, as a C++ plugin's TF_REGISTRY_FUNCTION would.

Plug then imports the plugin that holds the validator's metadata by its name, ``usdkslValidators``, which is no
module of its own: this module stands in for it (``sys.modules``), so that the validator keeps OpenUSD's
``<plugin>:<validator>`` name while its code stays in the usdksl package.
"""

import sys

from .names import PLUGIN_NAME
from .registration import register_task

register_task()
sys.modules.setdefault(PLUGIN_NAME, sys.modules[__name__])
