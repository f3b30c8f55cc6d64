"""JUnit XML check report (the Jenkins/Ant/Surefire dialect CI viewers load).

Layout: ``<testsuites>`` with one ``<testsuite>`` per checked file. Each error finding is a
failed ``<testcase>`` (``<failure type="CNC504">``); warnings and notes are passing test cases
whose ``<system-out>`` carries the message, so they show up without failing the build; an
unreadable file is a test case with ``<error>``; a clean file has one passing ``check`` case.
Validated in tests against Jenkins' ``junit-10.xsd`` (tests/schemas/).
"""

from __future__ import annotations

import xml.etree.ElementTree as ET

from cli.formats.base import CheckReport
from kernel.diagnostics import Severity


def _case(suite: ET.Element, name: str, classname: str) -> ET.Element:
    return ET.SubElement(suite, "testcase", name=name, classname=classname, time="0")


def render_junit(report: CheckReport) -> str:
    root = ET.Element("testsuites", name="cnc check")
    tests = failures = errors = 0
    for r in report.files:
        suite = ET.SubElement(root, "testsuite", name=r.file)
        n_tests = n_fail = n_err = 0
        if r.io_error:
            case = _case(suite, "read", r.file)
            ET.SubElement(case, "error", type="IO-ERROR", message=r.io_error).text = r.io_error
            n_tests, n_err = 1, 1
        for f in r.findings:
            where = f"{f.location.line}:{f.location.column}" if f.location.line else "-"
            case = _case(suite, f"{f.rule} at {where}", r.file)
            text = f.format()
            if f.severity == Severity.ERROR:
                ET.SubElement(case, "failure", type=f.code or f.rule, message=f.message).text = text
                n_fail += 1
            else:
                ET.SubElement(case, "system-out").text = text
            n_tests += 1
        if n_tests == 0:
            _case(suite, "check", r.file)
            n_tests = 1
        suite.set("tests", str(n_tests))
        suite.set("failures", str(n_fail))
        suite.set("errors", str(n_err))
        suite.set("skipped", "0")
        suite.set("time", f"{r.seconds:.3f}")
        tests, failures, errors = tests + n_tests, failures + n_fail, errors + n_err
    root.set("tests", str(tests))
    root.set("failures", str(failures))
    root.set("errors", str(errors))
    root.set("time", f"{report.seconds:.3f}")
    ET.indent(root)
    return '<?xml version="1.0" encoding="UTF-8"?>\n' + ET.tostring(root, encoding="unicode") + "\n"
