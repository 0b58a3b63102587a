"""ruff/mypy style: `path:line:col: CODE [severity] message (name)`, then `hint:`."""

from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING, Any

import click

from pkgforge.diagnostics import Diagnostic, Severity
from pkgforge.report import printable, relative

if TYPE_CHECKING:
    from pkgforge.verify.pipeline import VerifyResult

COLORS = {Severity.ERROR: "red", Severity.WARNING: "yellow", Severity.INFO: "cyan"}


def location(diagnostic: Diagnostic, root: Path) -> str:
    """`path:line:col`, the path printable (a file's name may hold any character but / and NUL)."""
    parts = [printable(relative(diagnostic.path, root))]
    if diagnostic.line is not None:
        parts.append(str(diagnostic.line))
        if diagnostic.column is not None:
            parts.append(str(diagnostic.column))
    return ":".join(parts)


def summary(result: VerifyResult) -> str:
    return printable(  # the distro may come from $ROS_DISTRO as it is
        f"{result.count(Severity.ERROR)} errors, {result.count(Severity.WARNING)} warnings, "
        f"{result.count(Severity.INFO)} infos in {len(result.reports)} packages"
        + engine_note(result)
        + sandbox_note(result)
    )


def sandbox_note(result: VerifyResult) -> str:
    """Said only when the kernel did not enforce what verify promises (sandbox/confinement.py)."""
    from pkgforge.sandbox.confinement import weaker

    note = weaker(result.sandbox) if result.sandbox is not None else None
    return f"; {note}" if note else ""


def engine_note(result: VerifyResult) -> str:
    """Which launch engine evaluated the launch files."""
    if result.engine != "ros":
        return "; launch: built-in engine" + (f" ({result.distro})" if result.distro else "")
    return f"; launch: ROS 2 {result.distro or '(distro unknown)'}"


def render(result: VerifyResult, *, color: bool = False, strict: bool = False) -> str:
    def style(text: str, **kwargs: Any) -> str:
        return click.style(text, **kwargs) if color else text

    lines = []
    for diagnostic in result.diagnostics:
        severity = style(f"[{diagnostic.severity.label}]", fg=COLORS[diagnostic.severity], bold=True)
        lines.append(
            f"{style(location(diagnostic, result.root), bold=True)}: "
            f"{style(diagnostic.code, bold=True)} {severity} {printable(diagnostic.message)} "
            f"({diagnostic.name})"
        )
        lines.append(f"    hint: {printable(diagnostic.hint)}")
    lines.append(summary(result))
    return "\n".join(lines) + "\n"
