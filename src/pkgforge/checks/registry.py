"""The check registry: each check is a small function registered with a code and a name.

A check reads one PackageModel (and the workspace around it) and yields
Findings; it never opens files. The registry turns Findings into Diagnostics.
"""

from __future__ import annotations

import os
import re
from collections.abc import Callable, Iterable
from dataclasses import dataclass, replace
from pathlib import Path
from typing import TYPE_CHECKING

from pkgforge.diagnostics import Diagnostic, Finding, Group, Severity, flattened, one_line

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
        # every message one short line, whatever a check or an error it quotes wrote (a URDF in a
        # launch error, a xacro command line): the whole text is the detail
        message, detail = one_line(finding.message, finding.detail)
        return Diagnostic(
            code=self.code,
            name=self.name,
            severity=finding.severity or self.severity,
            package=package,
            path=finding.path,
            line=finding.line,
            column=finding.column,
            message=message,
            hint=flattened(finding.hint or self.hint),
            fix=finding.fix,
            detail=detail,
            group=finding.group,
        )


def _user_paths(finding: Finding, context: CheckContext) -> Finding:
    """Findings name the user's files, never pkgforge's temporary tree (/dev/shm/pkgforge-tree-...):
    in a text, a path there becomes the package's own file, else share/<package>/<path> (inside a
    file:// URI, the path in the user's install base: what their launch resolves); a finding
    located there is located at the user's file it stands for."""
    tree = context.tree
    if tree is None or tree.root is None and (tree.kind != "predicted" and tree.phantom is None):
        return finding
    roots = ([*tree.prefixes] if tree.kind == "predicted" else []) + ([tree.phantom] if tree.phantom else [])
    pattern = re.compile(
        "(file://)?(?:" + "|".join(re.escape(str(root)) + r"/[^\s'\"()\[\],;:]*" for root in roots) + ")"
        if roots
        else "(?!)"
    )
    temporary = str(tree.root) if tree.root is not None else None

    def shown(match: re.Match[str]) -> str:
        uri, path = match.group(1), match.group(0)[len(match.group(1) or "") :]
        located = tree.locate(path)
        if located is None:
            return match.group(0)
        package, relative, _ = located
        if uri and tree.user_install is not None and not tree.is_phantom(path):
            return uri + tree.as_users(path)
        owner = context.model_for_share(package)
        if owner is not None and owner is context.model and not uri:
            return relative
        return f"share/{package}/{relative}"

    def rewrite(text: str | None) -> str | None:
        if not text:
            return text
        text = pattern.sub(shown, text)
        if temporary is not None and temporary in text:  # what no prefix holds
            text = re.sub(re.escape(temporary) + r"(?=/|$)[^\s'\"()\[\],;:]*", elsewhere, text)
        return text

    def elsewhere(match: re.Match[str]) -> str:
        """A path in the tree outside its prefixes: the user's file it copies or mirrors, the
        path in the user's install base, else pkgforge's folder named as such."""
        path = match.group(0)
        origin = tree.origin(path)
        if temporary is not None and not (origin + os.sep).startswith(temporary + os.sep):
            return origin
        users = tree.as_users(path)
        return users if users != path else "(pkgforge's temporary tree)"

    changes: dict[str, object] = {}
    for name in ("message", "hint", "detail"):
        value = getattr(finding, name)
        if rewrite(value) != value:
            changes[name] = rewrite(value)
    group = finding.group
    if group is not None and (rewrite(group.item), rewrite(group.many)) != (group.item, group.many):
        changes["group"] = Group(group.cause, rewrite(group.item) or "", rewrite(group.many) or "")
    if temporary is not None and str(finding.path).startswith(temporary + os.sep):
        changes.update(_user_place(finding, context, temporary))
    return replace(finding, **changes) if changes else finding  # type: ignore[arg-type]


def _user_place(finding: Finding, context: CheckContext, temporary: str) -> dict[str, object]:
    """A finding located in pkgforge's tree: at the user's file that tree file copies (the same
    line), else at the package's manifest, without a line (no file of the user's holds it)."""
    assert context.tree is not None
    origin = context.tree.origin(str(finding.path))
    if not origin.startswith(temporary + os.sep):
        return {"path": Path(origin)}
    return {"path": context.model.path / "package.xml", "line": None, "column": None}


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


def close_checks(key: str) -> list[str]:
    """The codes and names of up to three checks that `key` may misspell (`pkgforge rule`,
    --select/--ignore, pkgforge.toml)."""
    import difflib

    checks = all_checks()
    names = [c.code for c in checks] + [c.name for c in checks]
    # a code typed with the letter O for the digit 0 (PF3O2): that code first
    typed = key.strip().upper()
    digits = typed.replace("O", "0") if typed.startswith("PF") else ""
    close = [n for n in names if n == digits] + [
        n
        for n in difflib.get_close_matches(key.strip(), names, n=3)
        or difflib.get_close_matches(typed, names, n=3)
        if n != digits
    ]
    return close[:3]
