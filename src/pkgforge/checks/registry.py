"""The check registry: each check is a small function registered with a code and a name.

A check reads one PackageModel (and the workspace around it) and yields
Findings; it never opens files. The registry turns Findings into Diagnostics.
"""

from __future__ import annotations

import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic, Finding, Severity

if TYPE_CHECKING:
    from pkgforge.checks.context import CheckContext

# a check: reads one package's context, yields what is wrong
CheckFunction = Callable[["CheckContext"], Iterable[Finding]]


@dataclass(frozen=True)
class Check:
    code: str
    name: str
    severity: Severity
    summary: str  # one line: what is wrong
    explanation: str  # why it matters
    hint: str  # how to fix it, when the finding has no hint of its own
    area: str
    function: CheckFunction | None
    # `pkgforge fix`: None (no automatic fix), "safe" (cannot change behaviour beyond the
    # defect: applied by default) or "unsafe" (applied with --unsafe-fixes)
    fix: str | None = None
    # `pkgforge rule`: a short snippet that triggers the check and the same snippet fixed
    # (first line: the file, as a comment in its own syntax)
    bad: str | None = None
    good: str | None = None

    @property
    def anchor(self) -> str:
        """The check's heading anchor in docs/checks.md (GitHub's slug of `## PF101 name`)."""
        return f"{self.code.lower()}-{self.name}"

    def run(self, context: CheckContext) -> list[Diagnostic]:
        if self.function is None:
            return []
        return [
            self.diagnostic(context.model.name, _user_paths(finding, context))
            for finding in self.function(context)
        ]

    def diagnostic(self, package: str, finding: Finding) -> Diagnostic:
        return Diagnostic(
            code=self.code,
            name=self.name,
            severity=finding.severity or self.severity,
            package=package,
            path=finding.path,
            line=finding.line,
            column=finding.column,
            message=finding.message,
            hint=finding.hint or self.hint,
            fix=finding.fix,
        )


def _user_paths(finding: Finding, context: CheckContext) -> Finding:
    """Messages name the user's files, never pkgforge's temporary tree (/tmp/pkgforge-tree-...):
    a path there becomes the package's own file, else share/<package>/<path>."""
    tree = context.tree
    if tree is None or tree.kind != "predicted" and tree.phantom is None:
        return finding
    roots = ([*tree.prefixes] if tree.kind == "predicted" else []) + ([tree.phantom] if tree.phantom else [])
    pattern = re.compile("|".join(re.escape(str(root)) + r"/[^\s'\"()\[\],;:]*" for root in roots))

    def shown(match: re.Match[str]) -> str:
        located = tree.locate(match.group(0))
        if located is None:
            return match.group(0)
        package, relative, _ = located
        owner = context.model_for_share(package)
        if owner is not None and owner is context.model:
            return relative
        return f"share/{package}/{relative}"

    def rewrite(text: str | None) -> str | None:
        return pattern.sub(shown, text) if text else text

    message, hint = pattern.sub(shown, finding.message), rewrite(finding.hint)
    if (message, hint) == (finding.message, finding.hint):
        return finding
    return replace(finding, message=message, hint=hint)


REGISTRY: dict[str, Check] = {}
FIX_KINDS = (None, "safe", "unsafe")
# Checks whose fixer (src/pkgforge/fix/) needs nothing from the finding, so the fix holds
# even where the check's own @register does not say it (a check added on another branch).
DEFAULT_FIXES = {"find-package-undeclared": "safe"}
# A check's area follows its code's hundreds (PF3xx: launch), so `--select PF3` and the
# catalogue's areas agree; codes are stable, so a check in the wrong area moves area, not code.
# tests/test_conventions.py enforces it; a new hundred needs its area here.
AREAS = {
    "1": "manifest",
    "2": "install",
    "3": "launch",
    "4": "model",
    "5": "rviz",
    "6": "physics",
    "7": "simulation",
    "8": "migrate",
    "9": "run",
}


def register(
    code: str,
    name: str,
    severity: str,
    *,
    summary: str,
    explanation: str,
    hint: str,
    area: str,
    fix: str | None = None,
    bad: str | None = None,
    good: str | None = None,
) -> Callable[[CheckFunction | None], CheckFunction | None]:
    """Register a check function; `severity` is the default: error, warning or info.

    `fix`: whether `pkgforge fix` can fix its findings: None, "safe" or "unsafe"
    (src/pkgforge/fix/ holds the fixer, keyed by the check's name).
    `bad`/`good`: the examples `pkgforge rule` and docs/checks.md show.
    """
    fix = fix or DEFAULT_FIXES.get(name)
    if fix not in FIX_KINDS:
        raise ValueError(f"check {code} {name}: fix must be one of {FIX_KINDS}, not {fix!r}")

    def decorate(function: CheckFunction | None) -> CheckFunction | None:
        if code in REGISTRY or any(c.name == name for c in REGISTRY.values()):
            raise ValueError(f"check {code} {name} registered twice")
        REGISTRY[code] = Check(
            code, name, Severity.parse(severity), summary, explanation, hint, area, function, fix, bad, good
        )
        return function

    return decorate


def all_checks() -> list[Check]:
    from pkgforge.checks import load_all  # noqa: F401  (importing the modules registers their checks)

    return sorted(REGISTRY.values(), key=lambda c: c.code)


def find_check(key: str) -> Check | None:
    """The check with this code (any case) or name; None if there is none."""
    key = key.strip()
    for check in all_checks():
        if check.code == key.upper() or check.name == key:
            return check
    return None
