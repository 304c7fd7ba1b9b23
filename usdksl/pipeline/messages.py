"""What a check has to say, as data: plan lines, warnings and errors, each with a level and a kind.

:func:`usdksl.pipeline.check.check_shot` hands each :class:`Message` to its caller as it is known and keeps
them all in ``CheckResult.messages``; ``usdksl check`` prints the ones its verbosity shows (cli/check.py).
"""

from __future__ import annotations

from dataclasses import dataclass
from typing import Callable, List, Optional

# Message levels: how a line is shown (``usdksl: warning: ...``) and at which verbosity (cli/check.py):
# plan and info lines with -v; results (the baseline's new and fixed contacts) and warnings by default;
# errors always.
PLAN = "plan"
INFO = "info"
RESULT = "result"
WARNING = "warning"
ERROR = "error"
#: Console verbosity (usdksl check -q, default, -v) and the least verbosity that shows each level.
QUIET = 0
NORMAL = 1
VERBOSE = 2
LEVEL_VERBOSITY = {ERROR: QUIET, WARNING: NORMAL, RESULT: NORMAL, INFO: VERBOSE, PLAN: VERBOSE}


@dataclass(frozen=True)
class Message:
    """One line the check has to say: a plan line, a warning, an error found by the cross-check."""

    level: str
    text: str
    #: Stable name of what the line is about (usdksl.warning_kinds), as OpenUSD names its validators;
    #: None for lines that are not findings (plan lines, progress notes).
    kind: Optional[str] = None

    def shown(self, verbosity: int) -> bool:
        """Whether ``usdksl check`` at this verbosity prints it (LEVEL_VERBOSITY)."""
        return verbosity >= LEVEL_VERBOSITY.get(self.level, VERBOSE)

    def line(self, shot: Optional[str] = None) -> str:
        """As ``usdksl check`` prints it on stderr (after the shot's name when it checks several)."""
        prefix = f"{self.level}: " if self.level in (WARNING, ERROR) else ""
        return f"usdksl: {shot + ': ' if shot else ''}{prefix}{self.text}"


def message_collector(messages: List[Message],
                      on_message: Optional[Callable[[Message], None]] = None) -> Callable[..., None]:
    """say(level, text, kind=None): append the Message to ``messages`` and hand it to ``on_message``."""
    def say(level: str, text: str, kind: Optional[str] = None) -> None:
        message = Message(level, text, kind)
        messages.append(message)
        if on_message is not None:
            on_message(message)
    return say
