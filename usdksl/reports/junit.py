"""The ``--junit`` report: JUnit XML as Jenkins (xunit's junit-10.xsd), GitLab and GitHub read it.

One ``<testsuite>`` per shot inside one ``<testsuites>``, written on every exit code:

* a checked shot: one ``<testcase>`` per checked mesh pair, with a ``<failure type="contact">`` when the
  pair has contacts (with a baseline: new contacts; a pair with only known contacts passes and says so in
  ``<system-out>``); a shot with nothing to check has one ``<skipped>`` test case saying so;
* a shot that could not be checked (exit 2): one ``<testcase>`` with an ``<error type="input-error">``
  carrying the one-line error.

Only what the schema allows is written: on testsuites name, tests, failures, errors; on testsuite name,
tests, failures, errors, skipped (the first four always); on testcase name, classname; failure, error and
skipped carry type and message attributes and text only. No times or timestamps, so two runs (and a
merged run) write the same bytes.
"""

from __future__ import annotations

from typing import Iterable, Optional
from xml.etree import ElementTree

import numpy as np

from ..clock import StageClock
from ..contacts.table import ContactTable
from .formats import NEW_FACE_PAIRS, summary_rows

#: classname of the test case of a shot that could not be checked, and of one with nothing to check.
INPUT_CLASSNAME = "usdksl.input"
#: type of the <error> of a shot that could not be checked (exit 2).
INPUT_ERROR_TYPE = "input-error"
#: Name of the single test case of a shot that was not checked.
CHECK_CASE_NAME = "check"


def _plural(count: int, word: str) -> str:
    return f"{count} {word}{'s' if count != 1 else ''}"


def shot_suite(name: str, plan, table: ContactTable, clock: StageClock,
               known: Optional[np.ndarray] = None) -> ElementTree.Element:
    """The testsuite of a checked shot (module docstring)."""
    by_pair = {(row["prim_a"], row["prim_b"]): row for row in summary_rows(table, clock, known)}
    failures = 0
    cases = []
    for i, j in plan.pairs.tolist():
        a, b = sorted((plan.paths[i], plan.paths[j]))
        kind = "self" if i == j else "inter"
        case = ElementTree.Element("testcase", {"classname": f"usdksl.{kind}",
                                                "name": a if kind == "self" else f"{a} x {b}"})
        row = by_pair.get((a, b))
        if row is not None and row.get(NEW_FACE_PAIRS, row["face_pairs"]) == 0:
            output = ElementTree.SubElement(case, "system-out")
            output.text = f"{_plural(row['face_pairs'], 'known face pair')} in contact"
        elif row is not None:
            failures += 1
            message = f"{_plural(row['face_pairs'], 'face pair')} in contact, first at " \
                      f"{clock.describe(row['first_contact_time'])}"
            if NEW_FACE_PAIRS in row:
                message = f"{row[NEW_FACE_PAIRS]} new, " + message
            if "last_contact_time" in row:
                message += f", last at {clock.describe(row['last_contact_time'])}"
            failure = ElementTree.SubElement(case, "failure", {"message": message, "type": "contact"})
            failure.text = message
        cases.append(case)
    skipped = 0
    if not cases:
        skipped = 1
        case = ElementTree.Element("testcase", {"classname": INPUT_CLASSNAME, "name": CHECK_CASE_NAME})
        ElementTree.SubElement(case, "skipped", {"message": "no mesh pair left to check"}).text = \
            "no mesh pair left to check: nothing was checked"
        cases.append(case)
    suite = ElementTree.Element("testsuite", {"name": str(name), "tests": str(len(cases)),
                                              "failures": str(failures), "errors": "0", "skipped": str(skipped)})
    suite.extend(cases)
    return suite


def error_suite(name: str, message: str) -> ElementTree.Element:
    """The testsuite of a shot that could not be checked: one test case with an <error>."""
    case = ElementTree.Element("testcase", {"classname": INPUT_CLASSNAME, "name": CHECK_CASE_NAME})
    error = ElementTree.SubElement(case, "error", {"message": message, "type": INPUT_ERROR_TYPE})
    error.text = message
    suite = ElementTree.Element("testsuite", {"name": str(name), "tests": "1", "failures": "0", "errors": "1",
                                              "skipped": "0"})
    suite.append(case)
    return suite


def junit_document(suites: Iterable[ElementTree.Element]) -> str:
    """<testsuites> around the given suites, with their totals."""
    suites = list(suites)
    totals = {key: sum(int(suite.get(key, "0")) for suite in suites) for key in ("tests", "failures", "errors")}
    root = ElementTree.Element("testsuites", {"name": "usdksl check", **{k: str(v) for k, v in totals.items()}})
    root.extend(suites)
    if hasattr(ElementTree, "indent"):  # Python >= 3.9
        ElementTree.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ElementTree.tostring(root, encoding="unicode") + "\n"


def junit_report(name: str, plan, table: ContactTable, clock: StageClock, known: Optional[np.ndarray] = None) -> str:
    """The document of one checked shot."""
    return junit_document([shot_suite(name, plan, table, clock, known)])


def junit_error_report(names: Iterable[str], message: str) -> str:
    """The document of shots that could not be checked, each with the same error."""
    return junit_document([error_suite(name, message) for name in names])


__all__ = ["CHECK_CASE_NAME", "INPUT_ERROR_TYPE", "error_suite", "junit_document", "junit_error_report",
           "junit_report", "shot_suite"]
