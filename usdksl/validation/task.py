"""The task function of ``usdkslValidators:NoInterpenetration``: the check of a stage over the validation's
time range, with the package's default options (docs/contracts.md, In USD tools).

UsdValidation hands a stage validator the stage and a UsdValidationTimeRange. The whole range (what
``Validate(stage)`` and usdchecker pass: all of time) checks the shot as ``usdksl check`` does without
``--time-range``; a bounded interval is the check's time range; an interval open on one side ends there at the
stage's start or end time code. A time range that is the default time only has no motion to check: nothing is
checked and nothing reported.
"""

from __future__ import annotations

import math
from typing import List, Optional, Tuple

from pxr import Usd, UsdValidation

from ..errors import UsdkslInputError
from ..pipeline.options import CheckOptions
from ..pipeline.stage import check_stage
from .validation_errors import failure_error, refusal_error, result_errors


def no_interpenetration(stage: Usd.Stage, time_range: Optional[UsdValidation.ValidationTimeRange] = None
                        ) -> List[UsdValidation.ValidationError]:
    """The validation errors of ``stage`` over ``time_range`` (None: the whole range): one per contact region,
    one per item the check could not read, one when it could not check the stage at all; none for a clean
    stage."""
    interval = None if time_range is None else time_range.GetInterval()
    if interval is not None and interval.isEmpty:
        return []   # the default time only: no motion, so no contact over time
    try:
        result = check_stage(stage, CheckOptions(time_range=time_codes(stage, interval)))
    except UsdkslInputError as error:
        return [refusal_error(stage, error)]
    except Exception as error:   # noqa: BLE001  (a validator reports; the validation run goes on)
        return [failure_error(stage, error)]
    return result_errors(stage, result)


def time_codes(stage: Usd.Stage, interval) -> Optional[Tuple[float, float]]:
    """The check's time range for a GfInterval of time codes: None for all of time, else its ends, an infinite
    end replaced by the stage's start or end time code."""
    if interval is None or (math.isinf(interval.min) and math.isinf(interval.max)):
        return None
    start = stage.GetStartTimeCode() if math.isinf(interval.min) else float(interval.min)
    end = stage.GetEndTimeCode() if math.isinf(interval.max) else float(interval.max)
    return (float(start), float(end))


__all__ = ["no_interpenetration", "time_codes"]
