"""JUnit XML: one testsuite per package, one testcase per check; errors are failures.

Every text from the package (names, paths, messages) goes through `printable`: XML 1.0 has no
way to write most control characters, even as a character reference, and lxml refuses them."""

from __future__ import annotations

from typing import TYPE_CHECKING

from lxml import etree

from pkgforge.checks.registry import all_checks
from pkgforge.diagnostics import Severity
from pkgforge.report import InRepository, printable
from pkgforge.report.text import location

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    failing = {Severity.ERROR, Severity.WARNING} if strict else {Severity.ERROR}
    checks = [c for c in all_checks() if c.code in result.checks_run]
    suites = etree.Element("testsuites", name="pkgforge verify")
    total_tests = total_failures = 0
    in_repository = InRepository(result.root)  # a CI report: paths as the repository has them
    for report in result.reports:
        package = printable(report.name)
        suite = etree.SubElement(suites, "testsuite", name=package, errors="0", skipped="0", time="0")
        failures = 0
        for check in checks:
            found = [d for d in report.diagnostics if d.code == check.code]
            case = etree.SubElement(
                suite,
                "testcase",
                name=f"{check.code} {check.name}",
                classname=f"pkgforge.{package}",
                time="0",
            )
            failed = [d for d in found if d.severity in failing]
            if failed:
                failures += 1
                failure = etree.SubElement(
                    case, "failure", message=printable(failed[0].message), type=failed[0].severity.label
                )
                failure.text = "\n".join(
                    f"{location(d, in_repository)}: {printable(d.message)}\nhint: {printable(d.hint)}"
                    for d in failed
                )
            others = [d for d in found if d.severity not in failing]
            if others:
                out = etree.SubElement(case, "system-out")
                out.text = "\n".join(
                    f"{location(d, in_repository)}: [{d.severity.label}] {printable(d.message)}"
                    for d in others
                )
        suite.set("tests", str(len(checks)))
        suite.set("failures", str(failures))
        total_tests += len(checks)
        total_failures += failures
    suites.set("tests", str(total_tests))
    suites.set("failures", str(total_failures))
    suites.set("errors", "0")
    return etree.tostring(suites, pretty_print=True, xml_declaration=True, encoding="UTF-8").decode()
