"""JUnit XML as Jenkins reads it: the structural rules of the xunit plugin's junit-10.xsd, checked by hand.

No XSD is vendored and no network is used. These are the constraints of junit-10.xsd (jenkinsci/
xunit-plugin, src/main/resources/org/jenkinsci/plugins/xunit/types/model/xsd/junit-10.xsd) that a
document must meet, written out:

* the root is ``testsuites`` (children: ``testsuite`` only; attributes name, time, tests, failures,
  errors, all optional) or a single ``testsuite``;
* ``testsuite``: attributes name, tests, failures, errors **required**; optional group, time, skipped,
  timestamp, hostname, id, package, file, log, url; nothing else. Children, in any order and number:
  testsuite, properties, testcase, system-out, system-err;
* ``testcase``: attribute name **required**; optional time, classname, group. Children, any order and
  number: skipped, error, failure, rerunFailure, rerunError, flakyFailure, flakyError, system-out,
  system-err;
* ``failure``, ``error``, ``skipped``: mixed content (text, no child elements); attributes type and
  message only;
* ``system-out``, ``system-err``: text only (xs:string, no child elements);
* ``time`` of testsuites and testsuite: the SUREFIRE_TIME pattern (digits, optional thousands commas,
  optional decimal fraction: no sign, no exponent).

Beyond the schema (what Jenkins' counters rely on): the numbers are non-negative integers and match the
test cases they count.
"""

import re
from xml.etree import ElementTree

SUREFIRE_TIME = re.compile(r"(([0-9]{0,3},)*[0-9]{3}|[0-9]{0,3})*(\.[0-9]*)?")

SUITES_ATTRIBUTES = {"name", "time", "tests", "failures", "errors"}
SUITE_REQUIRED = {"name", "tests", "failures", "errors"}
SUITE_ATTRIBUTES = SUITE_REQUIRED | {"group", "time", "skipped", "timestamp", "hostname", "id", "package", "file",
                                     "log", "url"}
SUITE_CHILDREN = {"testsuite", "properties", "testcase", "system-out", "system-err"}
CASE_ATTRIBUTES = {"name", "time", "classname", "group"}
CASE_CHILDREN = {"skipped", "error", "failure", "rerunFailure", "rerunError", "flakyFailure", "flakyError",
                 "system-out", "system-err"}
RESULT_ATTRIBUTES = {"type", "message"}


def _count(element, name):
    value = element.get(name)
    assert value is not None and value.isdigit(), f"{element.tag} {name}={value!r} is not a count"
    return int(value)


def _check_text_only(element):
    assert len(element) == 0, f"<{element.tag}> holds child elements"


def _check_case(case):
    assert "name" in case.attrib, "testcase without name"
    assert set(case.attrib) <= CASE_ATTRIBUTES, f"testcase attributes {set(case.attrib) - CASE_ATTRIBUTES}"
    for child in case:
        assert child.tag in CASE_CHILDREN, f"<{child.tag}> inside testcase"
        if child.tag in ("failure", "error", "skipped"):
            assert set(child.attrib) <= RESULT_ATTRIBUTES, f"{child.tag} attributes {set(child.attrib)}"
        _check_text_only(child)


def _check_suite(suite):
    missing = SUITE_REQUIRED - set(suite.attrib)
    assert not missing, f"testsuite lacks {missing}"
    assert set(suite.attrib) <= SUITE_ATTRIBUTES, f"testsuite attributes {set(suite.attrib) - SUITE_ATTRIBUTES}"
    if "time" in suite.attrib:
        assert SUREFIRE_TIME.fullmatch(suite.get("time")), suite.get("time")
    cases = []
    for child in suite:
        assert child.tag in SUITE_CHILDREN, f"<{child.tag}> inside testsuite"
        if child.tag == "testcase":
            _check_case(child)
            cases.append(child)
        elif child.tag == "testsuite":
            _check_suite(child)
        elif child.tag in ("system-out", "system-err"):
            _check_text_only(child)
    # counters agree with the cases (what Jenkins shows)
    assert _count(suite, "tests") == len(cases)
    assert _count(suite, "failures") == sum(case.find("failure") is not None for case in cases)
    assert _count(suite, "errors") == sum(case.find("error") is not None for case in cases)
    if "skipped" in suite.attrib:
        assert _count(suite, "skipped") == sum(case.find("skipped") is not None for case in cases)


def assert_valid_junit(text):
    """Parse ``text`` and assert every rule above; returns the root element."""
    root = ElementTree.fromstring(text.encode("utf-8") if isinstance(text, str) else text)
    if root.tag == "testsuite":
        _check_suite(root)
        return root
    assert root.tag == "testsuites", f"root <{root.tag}>"
    assert set(root.attrib) <= SUITES_ATTRIBUTES, f"testsuites attributes {set(root.attrib) - SUITES_ATTRIBUTES}"
    if "time" in root.attrib:
        assert SUREFIRE_TIME.fullmatch(root.get("time")), root.get("time")
    for child in root:
        assert child.tag == "testsuite", f"<{child.tag}> inside testsuites"
        _check_suite(child)
    for name in ("tests", "failures", "errors"):
        if name in root.attrib:
            assert _count(root, name) == sum(_count(suite, name) for suite in root)
    return root
