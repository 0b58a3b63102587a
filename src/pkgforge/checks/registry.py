"""The check registry: each check is a small function registered with a code and a name.

A check reads one PackageModel (and the workspace around it) and yields
Findings; it never opens files. The registry turns Findings into Diagnostics.
"""

from __future__ import annotations

from collections.abc import Callable, Iterable
from dataclasses import dataclass

from ..diagnostics import Diagnostic, Finding, Severity


@dataclass(frozen=True)
class Check:
    code: str
    name: str
    severity: Severity
    summary: str  # one line: what is wrong
    explanation: str  # why it matters
    hint: str  # how to fix it, when the finding has no hint of its own
    area: str
    function: Callable[..., Iterable[Finding]] | None

    def run(self, context) -> list[Diagnostic]:
        if self.function is None:
            return []
        return [self.diagnostic(context.model.name, finding) for finding in self.function(context)]

    def diagnostic(self, package: str, finding: Finding) -> Diagnostic:
        return Diagnostic(
            code=self.code, name=self.name,
            severity=finding.severity or self.severity,
            package=package, path=finding.path, line=finding.line, column=finding.column,
            message=finding.message, hint=finding.hint or self.hint,
        )


REGISTRY: dict[str, Check] = {}


def register(code: str, name: str, severity: str, *, summary: str, explanation: str, hint: str,
             area: str) -> Callable:
    """Register a check function; `severity` is the default: error, warning or info."""

    def decorate(function: Callable | None) -> Callable | None:
        if code in REGISTRY or any(c.name == name for c in REGISTRY.values()):
            raise ValueError(f"check {code} {name} registered twice")
        REGISTRY[code] = Check(code, name, Severity.parse(severity), summary, explanation, hint,
                               area, function)
        return function

    return decorate


def all_checks() -> list[Check]:
    from . import load_all  # noqa: F401  (importing the modules registers their checks)

    return sorted(REGISTRY.values(), key=lambda c: c.code)
