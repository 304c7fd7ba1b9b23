"""The plugin a USD tool finds the validator by: a fresh process with PXR_PLUGINPATH_NAME set, as the README's
line sets it, loads usdkslValidators:NoInterpenetration through Plug alone (as usdchecker does: every
validator's metadata, then GetOrLoad, then a ValidationContext), and register_validators() works whether or not
the registry was built before it."""

import os
import subprocess
import sys
from pathlib import Path

from usdksl.validation.names import PLUGIN_FOLDER, VALIDATOR_NAME

REPO_ROOT = Path(__file__).resolve().parents[2]

#: Run in a fresh Python: the errors of every validator the registry knows, on the shot given as argv[1].
USDCHECKER_LIKE = f"""
import sys
from pxr import Usd, UsdValidation
registry = UsdValidation.ValidationRegistry()
assert 'usdksl' not in sys.modules                      # nothing imported usdksl: Plug will
validators = registry.GetOrLoadAllValidators()
stage = Usd.Stage.Open(sys.argv[1])
for error in UsdValidation.ValidationContext(validators).Validate(stage):
    if error.GetValidator().GetMetadata().name == {VALIDATOR_NAME!r}:
        print(error.GetErrorAsString())
"""

#: The registry is built first (by a tool that asked for validators before usdksl was imported).
REGISTRY_FIRST = f"""
import sys
from pxr import Usd, UsdValidation
registry = UsdValidation.ValidationRegistry()
assert registry.GetValidatorMetadata({VALIDATOR_NAME!r}) is None
import usdksl
validator = usdksl.register_validators()
assert usdksl.register_validators() is not None
for error in validator.Validate(Usd.Stage.Open(sys.argv[1])):
    print(error.GetErrorAsString())
"""


def run(code, argument, tmp_path, **environment):
    env = {key: value for key, value in os.environ.items() if key not in ("PXR_PLUGINPATH_NAME", "PYTHONPATH")}
    env.update(environment)
    return subprocess.run([sys.executable, "-c", code, str(argument)], cwd=tmp_path, env=env, capture_output=True,
                          text=True, timeout=120)


def test_plugin_folder_holds_the_plugin_and_python_m_prints_it(tmp_path):
    assert (PLUGIN_FOLDER / "plugInfo.json").is_file()   # shipped in the wheel: CI runs the installed package
    printed = subprocess.run([sys.executable, "-m", "usdksl.validation"], cwd=tmp_path, capture_output=True,
                             text=True, timeout=60)
    assert printed.returncode == 0 and printed.stdout.strip() == str(PLUGIN_FOLDER)


def test_a_usd_tool_loads_the_validator_from_the_plugin_path_alone(tmp_path, samples_dir):
    found = run(USDCHECKER_LIKE, samples_dir / "fold.usda", tmp_path, PXR_PLUGINPATH_NAME=str(PLUGIN_FOLDER))
    assert found.returncode == 0, found.stderr
    assert found.stdout.splitlines() == [
        "Error: (usdkslValidators:NoInterpenetration.Interpenetration) region 1: /World/Strip passes into itself "
        "from frame 31.916 (t=31.916) to frame 36: intersection 0.8 long at frame 35, 132 face pairs"]
    clean = run(USDCHECKER_LIKE, samples_dir / "clean.usda", tmp_path, PXR_PLUGINPATH_NAME=str(PLUGIN_FOLDER))
    assert clean.returncode == 0 and clean.stdout == "", clean.stderr


def test_without_the_plugin_path_a_usd_tool_has_no_such_validator(tmp_path, samples_dir):
    missing = run(USDCHECKER_LIKE, samples_dir / "fold.usda", tmp_path)
    assert missing.returncode == 0 and missing.stdout == "", missing.stderr


def test_register_validators_after_the_registry_was_built(tmp_path, samples_dir):
    late = run(REGISTRY_FIRST, samples_dir / "drape.usda", tmp_path)
    assert late.returncode == 0, late.stderr
    assert [line.split(") ", 1)[0] for line in late.stdout.splitlines()] == [
        "Error: (usdkslValidators:NoInterpenetration.Interpenetration"]


def test_the_readme_line_sets_the_plugin_path(tmp_path, samples_dir):
    readme = (REPO_ROOT / "README.md").read_text()
    line = next(text.strip() for text in readme.splitlines() if text.strip().startswith("export PXR_PLUGINPATH_NAME="))
    python_folder = os.path.dirname(sys.executable)
    env = {key: value for key, value in os.environ.items() if key not in ("PXR_PLUGINPATH_NAME", "PYTHONPATH")}
    env["PATH"] = python_folder + os.pathsep + env.get("PATH", "")
    shell = subprocess.run(["bash", "-c", f'{line} && python -c "$0" "$1"', USDCHECKER_LIKE,
                            str(samples_dir / "fold.usda")], cwd=tmp_path, env=env, capture_output=True, text=True,
                           timeout=120)
    assert shell.returncode == 0, shell.stderr
    assert shell.stdout.startswith("Error: (usdkslValidators:NoInterpenetration.Interpenetration) region 1")
