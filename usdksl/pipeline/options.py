"""What ``usdksl check`` is asked to do for one shot, without the output locations: :class:`CheckOptions`."""

from __future__ import annotations

from dataclasses import dataclass
from typing import Optional, Tuple

from ..ccd_defaults import DEFAULT_THICKNESS, DEFAULT_TOLERANCE
from ..checking.collision import METHODS
from ..checking.memory_windows import MIN_STEPS_PER_WINDOW
from ..errors import UsdkslUsageError
from ..reading.scope import split_patterns
from .memory_budget import parse_memory_size

TimeRange = Tuple[float, float]


@dataclass(frozen=True)
class CheckOptions:
    """What ``usdksl check`` is asked to do, without the output locations. Times in USD time codes;
    ``tolerance`` a fraction of one sample interval; ``thickness`` in scene units. A value the check cannot
    use raises UsdkslUsageError (exit 2) here, at construction, so nothing past it checks again."""

    method: str = "ksl"
    tolerance: float = DEFAULT_TOLERANCE
    thickness: float = DEFAULT_THICKNESS
    self_check: bool = True
    inter_check: bool = True
    time_range: Optional[TimeRange] = None
    prims: Tuple[str, ...] = ()
    exclude: Tuple[str, ...] = ()
    include_guides: bool = False
    include_invisible: bool = False
    #: Also check pairs in which neither mesh deforms (rigid or still against rigid or still).
    rigid: bool = False
    crosscheck: bool = False
    #: Also find each face pair's last contact by checking the shot played backwards
    #: (usdksl.checking.last_contact): a second run of the core, about as long as the first.
    last_contact: bool = False
    #: Turn warnings that mean the answer cannot be trusted (a simulation blow-up, geometry read past
    #: unchecked, nothing left to check) into input errors (exit 2), for CI. Does not change any result, so not in settings().
    strict: bool = False
    #: Threads of the core (None: every core this process may use). Does not change any result, so
    #: not in settings().
    threads: Optional[int] = None
    #: Memory the check may use: a size ("8G", bytes), "off", or None for what the machine has
    #: (usdksl.pipeline.memory_budget). Does not change any result, so not in settings().
    memory_limit: Optional[str] = None
    #: Sample steps of the memory windows the core is handed a long shot in (usdksl.checking.memory_windows;
    #: None: chosen from the threads and the memory available). Does not change any result, so not in settings().
    window: Optional[int] = None
    #: Check what the stage composes even when a reference, payload, sublayer or clip asset does not
    #: resolve (the coverage account names each as not checked). Off: such a stage is an input error.
    allow_missing_assets: bool = False
    #: Pose skinned meshes at their animation's keys only, instead of at every frame of the stage's range
    #: where the keys are sparser (as UsdSkel.BakeSkinning bakes them).
    skin_keys_only: bool = False

    def __post_init__(self) -> None:
        self.validate()

    def validate(self) -> None:
        """Raise UsdkslUsageError (exit 2) on a value the check cannot use (done at construction)."""
        parse_memory_size(self.memory_limit)
        if self.method not in METHODS:
            raise UsdkslUsageError(f"--method must be one of {', '.join(METHODS)}, got {self.method!r}")
        if self.window is not None and not (isinstance(self.window, int) and self.window >= MIN_STEPS_PER_WINDOW):
            raise UsdkslUsageError(f"--window must be a whole number of sample steps, at least "
                                   f"{MIN_STEPS_PER_WINDOW}, got {self.window!r}")
        if not self.tolerance > 0:
            raise UsdkslUsageError(f"--tolerance must be positive, got {self.tolerance!r}")
        if not self.thickness >= 0:
            raise UsdkslUsageError(f"--thickness must be zero or positive, got {self.thickness!r}")

    def patterns(self) -> Tuple[Tuple[str, ...], Tuple[str, ...]]:
        """(include, exclude) prim patterns, a leading '!' in --prims moved to the excludes."""
        return split_patterns(self.prims, self.exclude)

    def settings(self) -> dict:
        """The ``settings`` object of the JSON report (and of a chunk's manifest)."""
        include, excluded = self.patterns()
        return {"method": self.method, "tolerance": self.tolerance, "thickness": self.thickness,
                "self": self.self_check, "inter": self.inter_check,
                "time_range": list(self.time_range) if self.time_range else None,
                "prims": list(include), "exclude": list(excluded), "include_guides": self.include_guides,
                "include_invisible": self.include_invisible, "rigid": self.rigid,
                "last_contact": self.last_contact, "allow_missing_assets": self.allow_missing_assets,
                "skin_keys_only": self.skin_keys_only}
