"""What one check found and would write: :class:`CheckResult`, plain data (it pickles for Dask)."""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path
from typing import Dict, List, Optional, Tuple

from ..clock import StageClock
from ..contacts.baseline import BaselineComparison
from ..contacts.table import ContactTable
from ..reading.scope import Plan
from ..regions.table import RegionTable
from ..reports.formats import summary_line
from .coverage import Coverage
from .files import FileData
from .messages import Message
from .options import CheckOptions, TimeRange

#: CheckResult.counters entry: triangle pairs reported as contacts because the narrow phase hit its cap.
UNDECIDED_COUNTER = "undecided_triangle_pairs"


@dataclass
class CheckResult:
    """Everything one check found and would write; plain data (pickles for Dask)."""

    shot: str
    options: CheckOptions
    exit_code: int
    table: ContactTable
    plan: Plan
    span: TimeRange
    seconds: float
    counters: Dict[str, int]
    messages: List[Message]
    #: {target: text, bytes (a crate file, a PNG) or None (a stale file of ours to remove)}
    files: Dict[Path, "FileData"]
    stdout: Optional[str] = None
    segments: List[Tuple[Optional[TimeRange], ContactTable]] = field(default_factory=list)
    #: Frames and seconds of the shot's time codes (its stage metadata).
    clock: StageClock = StageClock()
    #: The contacts held against a baseline (None without one).
    baseline: Optional[BaselineComparison] = None
    #: Threads the core ran with (options.threads, or every core of the process that checked).
    threads: int = 1
    #: Every prim and stretch of the checked range, checked or not, with why (usdksl.pipeline.coverage).
    coverage: Optional[Coverage] = None
    #: The contacts grouped into regions, each measured (usdksl.regions); None for a result made without them.
    regions: Optional[RegionTable] = None
    #: {region row: PNG} of the worst regions, drawn when the check has a report target (--report).
    pictures: Dict[int, bytes] = field(default_factory=dict)

    @property
    def undecided(self) -> int:
        """Triangle pairs the narrow phase could not separate within the tolerance (reported as contacts)."""
        return self.counters.get(UNDECIDED_COUNTER, 0)

    @property
    def line(self) -> str:
        """The shot's line on the console: ``usdksl: SHOT: <summary>``."""
        return f"usdksl: {self.shot}: {self.summary[len('usdksl: '):]}"

    @property
    def summary(self) -> str:
        """The final line of ``usdksl check``."""
        return summary_line(self.table, self.plan, self.span, self.seconds, self.clock,
                            None if self.baseline is None else self.baseline.known,
                            None if self.baseline is None else self.baseline.fixed_count,
                            "" if self.coverage is None else self.coverage.summary_phrase(), self.regions)
