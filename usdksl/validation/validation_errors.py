"""A check's result as UsdValidationErrors: what ``usdkslValidators:NoInterpenetration`` returns.

One error per contact region (the problems a person fixes, usdksl.regions), with the region's two prims as
its sites and its first contact in the message as a frame and a time code; one error per coverage entry the
check could not read (a validator that passes must mean that everything was checked and is clean); a warning
per vertex that blows up or cache glitch, whose contacts are reported like any others. A check that refused
the stage is one error, on the prim it names or the stage.
"""

from __future__ import annotations

from typing import List, Optional

from pxr import Sdf, Usd, UsdValidation

from ..clock import console_number
from ..errors import UsdkslInputError
from ..pipeline.coverage import NOT_CHECKED as COVERAGE_NOT_CHECKED
from ..pipeline.messages import WARNING
from ..pipeline.result import CheckResult
from ..reports.formats import depth_text
from ..warning_kinds import BLOW_UP, CACHE_GLITCH
from .names import INTERPENETRATION, NOT_CHECKED, NOT_READ, SUSPECT_MOTION

ERROR = UsdValidation.ValidationErrorType.Error
WARN = UsdValidation.ValidationErrorType.Warn

#: Warning kinds of the check that become validation warnings: motion whose contacts may be artefacts.
SUSPECT_KINDS = (BLOW_UP, CACHE_GLITCH)


def result_errors(stage: Usd.Stage, result: CheckResult) -> List[UsdValidation.ValidationError]:
    """The validation errors of ``result``, the check of ``stage``: regions in id order, then what was not
    checked, then suspect motion."""
    errors = _region_errors(stage, result)
    for entry in (result.coverage.with_status(COVERAGE_NOT_CHECKED) if result.coverage is not None else []):
        when = "" if entry.start is None else f" over time {entry.start:g}..{entry.end:g}"
        errors.append(_error(NOT_CHECKED, ERROR, stage, [entry.prim],
                             f"not checked{when}: {entry.reason} ({entry.kind})"))
    for message in result.messages:
        if message.level == WARNING and message.kind in SUSPECT_KINDS:
            errors.append(_error(SUSPECT_MOTION, WARN, stage, [], f"{message.text} ({message.kind})"))
    return errors


def refusal_error(stage: Usd.Stage, error: UsdkslInputError) -> UsdValidation.ValidationError:
    """The one error of a check that refused ``stage`` (bad input), on the prim it names, else the stage."""
    return _error(NOT_READ, ERROR, stage, [error.prim] if error.prim else [], f"nothing checked: {error}")


def failure_error(stage: Usd.Stage, error: Exception) -> UsdValidation.ValidationError:
    """The one error of a check that failed unexpectedly: the validation run goes on and says so."""
    return _error(NOT_READ, ERROR, stage, [], f"usdksl could not check the stage: {type(error).__name__}: {error}")


def _region_errors(stage: Usd.Stage, result: CheckResult) -> List[UsdValidation.ValidationError]:
    regions, clock = result.regions, result.clock
    if regions is None or regions.count == 0:
        return []
    paths = regions.paths if regions.paths is not None else result.table.paths
    errors = []
    for row, region in enumerate(regions.ids.tolist()):   # one error per region: a Python object each anyway
        a, b = paths[int(regions.mesh_a[row])], paths[int(regions.mesh_b[row])]
        first, last = float(regions.first_time[row]), float(regions.last_time[row])
        count = int(regions.face_pairs[row])
        what = f"{a} passes into itself" if a == b else f"{a} and {b} interpenetrate"
        errors.append(_error(INTERPENETRATION, ERROR, stage, [a] if a == b else [a, b], (
            f"region {region}: {what} from {clock.describe(first)} to frame {console_number(clock.frame(last))}: "
            f"{depth_text(regions.depth_measure[row], float(regions.max_depth[row]))} at frame "
            f"{console_number(clock.frame(float(regions.max_depth_time[row])))}, {count} face "
            f"pair{'s' if count != 1 else ''}")))
    return errors


def _error(name: str, kind, stage: Usd.Stage, prims: List[str], message: str) -> UsdValidation.ValidationError:
    sites = [UsdValidation.ValidationErrorSite(stage, path) for path in map(_site_path, prims) if path is not None]
    if not sites:   # the stage itself
        sites = [UsdValidation.ValidationErrorSite(stage, Sdf.Path.absoluteRootPath)]
    return UsdValidation.ValidationError(name, kind, sites, message)


def _site_path(prim: str) -> Optional[Sdf.Path]:
    """The Sdf path of a prim as the check names it: a PointInstancer instance (``/World/scatter[3]/box``) is
    sited on its instancer; None for what names no prim (a layer, an asset)."""
    text = str(prim).split("[", 1)[0]
    if not Sdf.Path.IsValidPathString(text):
        return None
    path = Sdf.Path(text)
    return path if path.IsAbsolutePath() and path.IsPrimPath() or path == Sdf.Path.absoluteRootPath else None


__all__ = ["failure_error", "refusal_error", "result_errors"]
